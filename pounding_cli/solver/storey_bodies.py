"""Storeys struck between two floors, as virtual floors of the contact kernel, compiled.

The contact kernel (contact.py) moves every body with one floor: it reads (u_x, u_y, θ) of
floor f at 3f…3f + 2 of a state vector and adds the body's generalized force there. A storey
struck at height ξ·h (assembly/storey_contact.py) moves as the rigid body

    q_k = (1 − s)·T·q_below + s·q_above,   T·q = (u_x − θ·d_y, u_y + θ·d_x, θ),

referred to the upper floor's mass centre (d: G_above − G_below at rest). Before the kernel
runs, each state vector it reads is copied with these appended as floors n_floors + 1 + k
(extend; slot n_floors is the ground, zero); after it, the force on virtual floor k goes back
to the floors by the transpose of the same map (hand_back): Q_above += s·Q_k,
Q_below += (1 − s)·Tᵀ·Q_k, where Tᵀ·(F_x, F_y, M) = (F_x, F_y, M − d_y·F_x + d_x·F_y). The
kernel's force is work-conjugate to q_k, so its work on the floors is its work on the outline.
Scenes without struck storeys call the kernel on the state vectors themselves, unchanged.

The struck columns' local modes (assembly/local_modes.py) move the outline further, by
Σ_m φ_m(ξ)·q_m, q_m = y_m − w₀·T₀·u₀ − w₁·T₁·u₁ (its pseudo-floor's displacement less what
the floors carry it by at the columns' point, T_b·u = (u_x − θ·r_y, u_y + θ·r_x)); the
transpose hands the force on the outline (F_x, F_y) to them: φ_m·F to the pseudo-floor,
−w_b·φ_m·T_bᵀ·F to the floors.
"""

from __future__ import annotations

import numpy as np

from .contact import (
    ST_ACTIVE,
    ST_EVENT,
    contact_finest_level_within,
    contact_forces,
    contact_pairs_needed,
    contact_possible_within,
    contact_ruled_out_within,
)
from .jit import kernel, phase


@phase
def extend(x, storeys, out):
    """out = x (n_dof + 3 entries, the ground last) followed by the virtual floors' q_k."""
    n = x.size
    for d in range(n):
        out[d] = x[d]
    for k in range(storeys.shape.size):
        lo = 3 * storeys.below[k]
        hi = 3 * storeys.above[k]
        s = storeys.shape[k]
        r = 1.0 - s
        e = n + 3 * k
        turn = x[lo + 2]
        out[e] = s * x[hi] + r * (x[lo] - turn * storeys.arm[k, 1])
        out[e + 1] = s * x[hi + 1] + r * (x[lo + 1] + turn * storeys.arm[k, 0])
        out[e + 2] = s * x[hi + 2] + r * turn
        for m in range(storeys.mode_first[k], storeys.mode_first[k + 1]):
            qx, qy = _modal_deflection(x, lo, hi, m, storeys)
            out[e] += storeys.mode_phi[m] * qx
            out[e + 1] += storeys.mode_phi[m] * qy


@kernel(inline="always")
def _modal_deflection(x, lo, hi, m, storeys):
    """Local mode m's coordinate q = y − w₀·T₀·u₀ − w₁·T₁·u₁ (x, y components, m): its
    pseudo-floor's displacement less what the floors below (DOF lo) and above (hi) carry it by
    at the struck columns' point (assembly/local_modes.py)."""
    p = 3 * storeys.mode_floor[m]
    w0 = storeys.mode_weight[m, 0]
    w1 = storeys.mode_weight[m, 1]
    arm = storeys.mode_arm
    qx = x[p] - w0 * (x[lo] - x[lo + 2] * arm[m, 1]) - w1 * (x[hi] - x[hi + 2] * arm[m, 3])
    qy = x[p + 1] - w0 * (x[lo + 1] + x[lo + 2] * arm[m, 0]) - w1 * (x[hi + 1] + x[hi + 2] * arm[m, 2])
    return qx, qy


@phase
def _extend_three(x, y, z, storeys):
    """The three state vectors a contact kernel reads, extended into storeys.u, .v, .w."""
    extend(x, storeys, storeys.u)
    extend(y, storeys, storeys.v)
    extend(z, storeys, storeys.w)


@phase
def hand_back(force, storeys, n):
    """Move the forces on the virtual floors (entries n… of force, n = n_dof + 3) to the floors
    above and below each storey, and clear them (nothing goes to the ground's slot)."""
    ground = n - 3
    for k in range(storeys.shape.size):
        e = n + 3 * k
        fx = force[e]
        fy = force[e + 1]
        m = force[e + 2]
        storeys.load[k, 0] = fx
        storeys.load[k, 1] = fy
        s = storeys.shape[k]
        hi = 3 * storeys.above[k]
        force[hi] += s * fx
        force[hi + 1] += s * fy
        force[hi + 2] += s * m
        lo = 3 * storeys.below[k]
        if lo != ground:
            r = 1.0 - s
            force[lo] += r * fx
            force[lo + 1] += r * fy
            force[lo + 2] += r * (m - storeys.arm[k, 1] * fx + storeys.arm[k, 0] * fy)
        arm = storeys.mode_arm
        for j in range(storeys.mode_first[k], storeys.mode_first[k + 1]):
            p = 3 * storeys.mode_floor[j]
            gx = storeys.mode_phi[j] * fx
            gy = storeys.mode_phi[j] * fy
            force[p] += gx
            force[p + 1] += gy
            w1 = storeys.mode_weight[j, 1]
            force[hi] -= w1 * gx
            force[hi + 1] -= w1 * gy
            force[hi + 2] -= w1 * (-arm[j, 3] * gx + arm[j, 2] * gy)
            if lo != ground:
                w0 = storeys.mode_weight[j, 0]
                force[lo] -= w0 * gx
                force[lo + 1] -= w0 * gy
                force[lo + 2] -= w0 * (-arm[j, 1] * gx + arm[j, 0] * gy)
        force[e] = 0.0
        force[e + 1] = 0.0
        force[e + 2] = 0.0


@phase
def track_column_shears(t, agx, agy, u, a_abs, contact):
    """After a CDM step's velocity update at t (u = u_n, a_abs the accelerations at t_n, the
    ground's (agx, agy) m/s²): from the start of each impact of a storey body whose struck columns
    have local modes to the start of its next (the columns ring on after the contact: their shear
    peaks there too), while the CDM carries the buildings, the impact's part of the bundle's end
    shears (assembly/local_modes.py;
    docs/theory.md §10), at each end b the force the bundle's bending puts on floor b less the
    inertia of its mass that moves with the floors,

        R_b = Σ_m w_m,b·(K_m·q_m − φ_m(ξ)·F) + ψ_b(ξ)·F − Σ_c (M_bb − Σ_m m·w_m·w_mᵀ)_bc·ü_c,

    ψ = (1 − s, s), F the force on the outline (storeys.load, zero once the contact has ended),
    ü_c the absolute acceleration of floor c at the columns' point (the ground's below a first
    storey); kept, per impact (the row of its log), at the step where the larger of the bundle's
    whole end shears (with the storey's own, K·δ, K the bundle's stiffness and δ its drift at the
    columns' point) peaks: (that |Q|, t, R_foot x, y, −R_top x, y), the shear Q (the force of the part above a section on the part below) just
    above the foot and just below the top. With the modes static (q_m = φ_m·K_m⁻¹·F) and no
    mass it is the fixed–fixed point load's (1 − s, s)·F. The end moments likewise,
    h·(Σ_m θ_m,b·(K_m·q_m − φ_m·F) + θ_b(ξ)·F), θ the rotation shapes' couplings (Betti), their
    magnitudes (without the floors' inertia), and the floors' (u_x, u_y, θ) below and above at
    that step (the storey's own shear K·δ)."""
    storeys = contact.storeys
    peak = storeys.shear_peak
    ground = u.size - 3
    for k in range(storeys.shape.size):
        m0 = storeys.mode_first[k]
        m1 = storeys.mode_first[k + 1]
        if m0 == m1:
            continue
        p = storeys.pair[k]
        if contact.state[p, ST_ACTIVE] != 0.0:
            storeys.last_event[k] = int(contact.state[p, ST_EVENT])
        e = storeys.last_event[k]
        if e < 0 or e >= peak.shape[0]:
            continue
        fx = storeys.load[k, 0]
        fy = storeys.load[k, 1]
        s = storeys.shape[k]
        lo = 3 * storeys.below[k]
        hi = 3 * storeys.above[k]
        arm = storeys.mode_arm
        if lo == ground:
            abx = agx
            aby = agy
        else:
            abx = a_abs[lo] - a_abs[lo + 2] * arm[m0, 1]
            aby = a_abs[lo + 1] + a_abs[lo + 2] * arm[m0, 0]
        atx = a_abs[hi] - a_abs[hi + 2] * arm[m0, 3]
        aty = a_abs[hi + 1] + a_abs[hi + 2] * arm[m0, 2]
        res = storeys.residual_mass
        bx = (1.0 - s) * fx - res[k, 0, 0] * abx - res[k, 0, 1] * atx
        by = (1.0 - s) * fy - res[k, 0, 0] * aby - res[k, 0, 1] * aty
        tx = s * fx - res[k, 1, 0] * abx - res[k, 1, 1] * atx
        ty = s * fy - res[k, 1, 0] * aby - res[k, 1, 1] * aty
        rot = storeys.rotation_shape
        h = storeys.height[k]
        mbx = rot[k, 0] * fx
        mby = rot[k, 0] * fy
        mtx = rot[k, 1] * fx
        mty = rot[k, 1] * fy
        km = storeys.mode_k
        for m in range(m0, m1):
            qx, qy = _modal_deflection(u, lo, hi, m, storeys)
            rx = km[m, 0, 0] * qx + km[m, 0, 1] * qy - storeys.mode_phi[m] * fx
            ry = km[m, 1, 0] * qx + km[m, 1, 1] * qy - storeys.mode_phi[m] * fy
            bx += storeys.mode_weight[m, 0] * rx
            by += storeys.mode_weight[m, 0] * ry
            tx += storeys.mode_weight[m, 1] * rx
            ty += storeys.mode_weight[m, 1] * ry
            mbx += h * storeys.mode_theta[m, 0] * rx
            mby += h * storeys.mode_theta[m, 0] * ry
            mtx += h * storeys.mode_theta[m, 1] * rx
            mty += h * storeys.mode_theta[m, 1] * ry
        # the bundle's whole shear adds the storey's own, K·δ, δ its drift at the columns' point
        kb = storeys.bundle_k
        dx = u[hi] - u[hi + 2] * arm[m0, 3] - (u[lo] - u[lo + 2] * arm[m0, 1])
        dy = u[hi + 1] + u[hi + 2] * arm[m0, 2] - (u[lo + 1] + u[lo + 2] * arm[m0, 0])
        sx = kb[k, 0, 0] * dx + kb[k, 0, 1] * dy
        sy = kb[k, 1, 0] * dx + kb[k, 1, 1] * dy
        size = max(np.hypot(sx + bx, sy + by), np.hypot(sx - tx, sy - ty))
        if size > peak[e, 0]:
            peak[e, 0] = size
            peak[e, 1] = t
            peak[e, 2] = bx
            peak[e, 3] = by
            peak[e, 4] = -tx
            peak[e, 5] = -ty
            peak[e, 6] = np.hypot(mbx, mby)
            peak[e, 7] = np.hypot(mtx, mty)
            for j in range(3):
                peak[e, 8 + j] = u[lo + j]  # the floors' motion there, for the storey's own shear
                peak[e, 11 + j] = u[hi + j]


@phase
def forces_with_storeys(n, dt, u, v_half, v_est, contact):
    """contact_forces, with the struck storeys as virtual floors (the module docstring)."""
    storeys = contact.storeys
    if storeys.shape.size == 0:
        return contact_forces(n, dt, u, v_half, v_est, contact)
    _extend_three(u, v_half, v_est, storeys)
    live = contact_forces(n, dt, storeys.u, storeys.v, storeys.w, contact)
    hand_back(contact.force, storeys, u.size)
    return live


@phase
def possible_within(horizon, u, v, acc, contact):
    """contact_possible_within, with the struck storeys as virtual floors."""
    storeys = contact.storeys
    if storeys.shape.size == 0:
        return contact_possible_within(horizon, u, v, acc, contact)
    _extend_three(u, v, acc, storeys)
    return contact_possible_within(horizon, storeys.u, storeys.v, storeys.w, contact)


@phase
def ruled_out_within(horizon, u, v, acc, contact):
    """contact_ruled_out_within, with the struck storeys as virtual floors."""
    storeys = contact.storeys
    if storeys.shape.size == 0:
        return contact_ruled_out_within(horizon, u, v, acc, contact)
    _extend_three(u, v, acc, storeys)
    return contact_ruled_out_within(horizon, storeys.u, storeys.v, storeys.w, contact)


@phase
def finest_level_within(horizon, u, v, acc, contact, pair_level, coarsest):
    """contact_finest_level_within, with the struck storeys as virtual floors."""
    storeys = contact.storeys
    if storeys.shape.size == 0:
        return contact_finest_level_within(horizon, u, v, acc, contact, pair_level, coarsest)
    _extend_three(u, v, acc, storeys)
    return contact_finest_level_within(horizon, storeys.u, storeys.v, storeys.w, contact, pair_level, coarsest)


@phase
def needed_within(horizon, u, v, acc, contact, body_building, flag, need, keep):
    """contact_pairs_needed, with the struck storeys as virtual floors."""
    storeys = contact.storeys
    if storeys.shape.size == 0:
        return contact_pairs_needed(horizon, u, v, acc, contact, body_building, flag, need, keep)
    _extend_three(u, v, acc, storeys)
    return contact_pairs_needed(horizon, storeys.u, storeys.v, storeys.w, contact, body_building, flag, need, keep)
