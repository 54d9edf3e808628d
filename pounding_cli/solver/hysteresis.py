"""Yielding members in the time loop: the bilinear hysteretic law and its forces on floors.

A member (an inelastic column in one storey, or an isolator) deflects by δ, its top minus its
bottom in its local axes; with arm r from a floor's mass centre a point moves by
u + θ·ẑ×r, so in global axes D = (u_t + θ_t·ẑ×r_t) − (u_b + θ_b·ẑ×r_b) and δ = Qᵀ·D
(Q: the member's local axes). The bilinear law with initial stiffness k, yield force F_y and
post-yield ratio α is split exactly into

    f = α·k·δ + k_h·(δ − p),    k_h = (1 − α)·k,   |k_h·(δ − p)| ≤ f_h = (1 − α)·F_y,

an elastic spring and an elastic–perfectly-plastic one with plastic deflection p. So
f = k·δ − k_h·p: the storey stiffness K (initial stiffness, linear) gives k·δ, and the members
add the plastic correction g = Σ Bᵀ·Q·(k_h ⊙ p) (B maps floor DOFs to D): the restoring force
is K·u − g. The equation of motion becomes M·ü + C·u̇ + K·u = p(t) + g + F_contact, with
C = a0·M + a1·K the initial-stiffness Rayleigh damping.

Return mapping, exact along the straight path between two calls: trial force
f_tr = k_h ⊙ (δ − p); "independent": each axis clamped to ±f_h (a 1D law's state depends on
the end point only); "elliptical": if q = f_tr ⊘ f_h has |q| > 1, the path from the last
deflection is followed: elastic until q reaches the yield ellipse (f_x/f_h,x)² + (f_y/f_h,y)² = 1,
then on it with associative flow (ṗ normal to the ellipse in force space), q' = r − λ'·A·q,
λ' = (q·r)/(qᵀA·q), a_i = k_h,i/f_h,i², r the path's normalised rate. For a circle
(k_h,x/f_h,x² = k_h,y/f_h,y²: a round isolator, a square column) tan(β/2) of the angle β
between q and r decays as exp(−|r|·s), in closed form; otherwise RK4 in short pieces. Then
p = δ − f/k_h, and the dissipated energy is ∫f·dp along the same path. Only the path between
the states is assumed (a chord), so the law converges at second order in the time step; a
closest-point (backward-Euler) return of each increment, used before, converged at first
(docs/theory.md §12).

Energy: E_strain = ½·uᵀK·u − uᵀg + ½·Σ k_h ⊙ p² (the recoverable energy of both springs),
E_hysteretic = Σ ∫f·dp. Nothing here allocates.
"""

from __future__ import annotations

import numpy as np

from .jit import INTERNAL, kernel
from .tunables import PLASTIC_SUBSTEP


@kernel(inline="always")
def member_deflection(m, x, bottom, top, arm_b, arm_t, axes):
    """(δ_x, δ_y) of member m in its local axes for the floor vector x (n_dof + 3, ground
    last; `bottom` already maps the ground to the last floor)."""
    b = 3 * bottom[m]
    t = 3 * top[m]
    dx = x[t] - x[t + 2] * arm_t[m, 1] - x[b] + x[b + 2] * arm_b[m, 1]
    dy = x[t + 1] + x[t + 2] * arm_t[m, 0] - x[b + 1] - x[b + 2] * arm_b[m, 0]
    c = axes[m, 0]
    s = axes[m, 1]
    return c * dx + s * dy, -s * dx + c * dy


@kernel(inline="always")
def scatter_member(m, fx, fy, bottom, top, arm_b, arm_t, axes, out):
    """out += Bᵀ·Q·(fx, fy): a local force pair on member m as floor forces and moments."""
    c = axes[m, 0]
    s = axes[m, 1]
    gx = c * fx - s * fy
    gy = s * fx + c * fy
    b = 3 * bottom[m]
    t = 3 * top[m]
    out[t] += gx
    out[t + 1] += gy
    out[t + 2] += arm_t[m, 0] * gy - arm_t[m, 1] * gx
    out[b] -= gx
    out[b + 1] -= gy
    out[b + 2] -= arm_b[m, 0] * gy - arm_b[m, 1] * gx


@kernel(inline="always")
def _flow_rate(qx, qy, rx, ry, ax, ay):
    """dq/ds of the normalised force q = f ⊘ f_h on the ellipse |q| = 1 while the deflection
    moves by r per unit s (normalised, r = k_h ⊙ Δδ ⊘ f_h): q' = r − λ'·A·q with
    λ' = (q·r)/(qᵀA·q), A = diag(a_x, a_y), a_i = k_h,i/f_h,i² (associative flow: the
    plastic rate is normal to the ellipse in force space); and the power dissipated per unit
    s, f·p' = Σ (q_i·r_i − q_i·q_i')/a_i, J."""
    lam = (qx * rx + qy * ry) / (ax * qx * qx + ay * qy * qy)
    dqx = rx - lam * ax * qx
    dqy = ry - lam * ay * qy
    return dqx, dqy, (qx * (rx - dqx)) / ax + (qy * (ry - dqy)) / ay


@kernel(inline="always")
def return_map(d0x, d0y, dx, dy, px, py, khx, khy, fhx, fhy, coupled):
    """Plastic-spring force (f_x, f_y) and plastic deflection (p_x, p_y) after the member's
    deflection moved in a straight line from (d0x, d0y) to (dx, dy), from plastic deflection
    (px, py); returns (fx, fy, px, py, dissipated J, yielded).

    "independent": each axis clamped to ±f_h (exact: a 1D law depends on the end point only).
    "elliptical": integrated exactly along the straight path: elastic up to the point where
    q = f ⊘ f_h reaches the ellipse |q| = 1, then the flow q' = r − λ'·A·q on it (_flow_rate),
    in closed form for a circle (a_x = a_y: a round bearing, a square column) and by RK4 in
    pieces of PLASTIC_SUBSTEP otherwise. (A backward-Euler, closest-point return of the whole
    increment is exact only for proportional loading: along a turning path its error is of
    the order of the increment squared per step, first order in the time step overall.)"""
    fx = khx * (dx - px)
    fy = khy * (dy - py)
    if not coupled:
        yielded = False
        px1 = px
        py1 = py
        if abs(fx) > fhx:
            fx = fhx if fx > 0 else -fhx
            px1 = dx - fx / khx
            yielded = True
        if abs(fy) > fhy:
            fy = fhy if fy > 0 else -fhy
            py1 = dy - fy / khy
            yielded = True
        return fx, fy, px1, py1, fx * (px1 - px) + fy * (py1 - py), yielded
    q1x = fx / fhx
    q1y = fy / fhy
    if q1x * q1x + q1y * q1y <= 1.0:
        return fx, fy, px, py, 0.0, False
    ax = khx / (fhx * fhx)
    ay = khy / (fhy * fhy)
    # the start of the path in q and its normalised length r
    qx = khx * (d0x - px) / fhx
    qy = khy * (d0y - py) / fhy
    rx = khx * (dx - d0x) / fhx
    ry = khy * (dy - d0y) / fhy
    rr = rx * rx + ry * ry
    if rr == 0.0:  # no motion, the start outside the ellipse by rounding: onto it
        size = np.sqrt(q1x * q1x + q1y * q1y)
        fx = fhx * q1x / size
        fy = fhy * q1y / size
        return fx, fy, dx - fx / khx, dy - fy / khy, 0.0, True
    c = qx * qx + qy * qy - 1.0
    if c >= 0.0:  # on the ellipse already (or, by rounding, just past it): onto it
        size = np.sqrt(qx * qx + qy * qy)
        qx /= size
        qy /= size
        c = 0.0
    b = qx * rx + qy * ry
    # where the path leaves the ellipse: the root in [0, 1] of rr·s² + 2b·s + c (from the
    # surface, s = 0 when moving out, the far side when moving in)
    if b > 0.0:
        s_yield = -c / (b + np.sqrt(b * b - rr * c))
    else:
        s_yield = (np.sqrt(b * b - rr * c) - b) / rr
    s_yield = min(s_yield, 1.0)
    qx += s_yield * rx
    qy += s_yield * ry
    rest = 1.0 - s_yield
    if abs(ax - ay) <= 1e-12 * max(ax, ay):
        # a circle: q' = r − (q·r)·q. With e = r/|r| and e⊥ = ẑ × e, q = cos β·e − sin β·e⊥,
        # and tan(β/2) decays as exp(−|r|·s); f·p' = (q·r)/a, whose integral is
        # (ln sin β₀ − ln sin β₁)/a.
        norm = np.sqrt(rr)
        ex = rx / norm
        ey = ry / norm
        size = np.sqrt(qx * qx + qy * qy)
        cos0 = (qx * ex + qy * ey) / size
        sin0 = (qx * ey - qy * ex) / size
        length = norm * rest
        tau0 = sin0 / (1.0 + cos0)  # cos0 ≥ 0: the path leaves the circle here
        tau1 = tau0 * np.exp(-length)
        cos1 = (1.0 - tau1 * tau1) / (1.0 + tau1 * tau1)
        sin1 = 2.0 * tau1 / (1.0 + tau1 * tau1)
        qx = cos1 * ex + sin1 * ey
        qy = cos1 * ey - sin1 * ex
        dissipated = (length + np.log((1.0 + tau1 * tau1) / (1.0 + tau0 * tau0))) / ax
    else:
        # the flow pulls q across the ellipse at up to max(a)/min(a)·|r| per unit s: pieces
        # short in that measure keep RK4 accurate (and stable) on the stiff axis
        stiff = max(ax, ay) / min(ax, ay)
        pieces = max(1, int(np.ceil(np.sqrt(rr) * rest * stiff / PLASTIC_SUBSTEP)))
        hs = rest / pieces
        dissipated = 0.0
        for _ in range(pieces):
            k1x, k1y, w1 = _flow_rate(qx, qy, rx, ry, ax, ay)
            k2x, k2y, w2 = _flow_rate(qx + 0.5 * hs * k1x, qy + 0.5 * hs * k1y, rx, ry, ax, ay)
            k3x, k3y, w3 = _flow_rate(qx + 0.5 * hs * k2x, qy + 0.5 * hs * k2y, rx, ry, ax, ay)
            k4x, k4y, w4 = _flow_rate(qx + hs * k3x, qy + hs * k3y, rx, ry, ax, ay)
            qx += hs / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
            qy += hs / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y)
            dissipated += hs / 6.0 * (w1 + 2.0 * w2 + 2.0 * w3 + w4)
            size = np.sqrt(qx * qx + qy * qy)  # back onto the ellipse (the flow keeps |q| = 1)
            qx /= size
            qy /= size
    fx = fhx * qx
    fy = fhy * qy
    return fx, fy, dx - fx / khx, dy - fy / khy, dissipated, True


@kernel
def update_members(u, members, plastic, g):
    """Return-map every member along the straight path from its deflection at the last call
    (plastic[:, 2:4]) to its deflection at u; add the change of k_h ⊙ p to the plastic
    correction g. plastic: (n_members, 4) p_x, p_y, then δ_x, δ_y at the last call, m.
    Returns (energy dissipated J, members that yielded)."""
    bottom, top, arm_b, arm_t, axes, k0, kh, fh, coupled = members
    dissipated = 0.0
    n_yielded = 0
    for m in range(top.size):
        dx, dy = member_deflection(m, u, bottom, top, arm_b, arm_t, axes)
        px0 = plastic[m, 0]
        py0 = plastic[m, 1]
        fx, fy, px, py, work, yielded = return_map(plastic[m, 2], plastic[m, 3], dx, dy, px0, py0, kh[m, 0],
                                                   kh[m, 1], fh[m, 0], fh[m, 1], coupled[m])  # fmt: skip
        plastic[m, 2] = dx
        plastic[m, 3] = dy
        if yielded:
            n_yielded += 1
            dissipated += work
            plastic[m, 0] = px
            plastic[m, 1] = py
            scatter_member(m, kh[m, 0] * (px - px0), kh[m, 1] * (py - py0), bottom, top, arm_b, arm_t, axes, g)
    return dissipated, n_yielded


@kernel
def plastic_correction(members, plastic, g):
    """g = Σ Bᵀ·Q·(k_h ⊙ p) from scratch (so increments cannot accumulate rounding)."""
    bottom, top, arm_b, arm_t, axes, k0, kh, fh, coupled = members
    g[:] = 0.0
    for m in range(top.size):
        scatter_member(m, kh[m, 0] * plastic[m, 0], kh[m, 1] * plastic[m, 1], bottom, top, arm_b, arm_t, axes, g)


@kernel(**INTERNAL)
def plastic_energy_terms(u, g, members, plastic):
    """−uᵀg + ½·Σ k_h ⊙ p²: what the plastic deflections change in the strain energy ½uᵀKu, J."""
    kh = members.kh
    e = 0.0
    for d in range(u.size):
        e -= u[d] * g[d]
    for m in range(kh.shape[0]):
        e += 0.5 * (kh[m, 0] * plastic[m, 0] ** 2 + kh[m, 1] * plastic[m, 1] ** 2)
    return e


@kernel(**INTERNAL)
def member_states(u, members, plastic, k, out_member, peak_member):
    """Deflection and force of every member at u: into the output row k (k ≥ 0) and the
    running peaks (|δ_x|, |δ_y|, |δ|, |f_x|, |f_y|, |f|)."""
    bottom, top, arm_b, arm_t, axes, k0, kh, fh, coupled = members
    for m in range(top.size):
        dx, dy = member_deflection(m, u, bottom, top, arm_b, arm_t, axes)
        fx = k0[m, 0] * dx - kh[m, 0] * plastic[m, 0]
        fy = k0[m, 1] * dy - kh[m, 1] * plastic[m, 1]
        if k >= 0:
            out_member[k, m, 0] = dx
            out_member[k, m, 1] = dy
            out_member[k, m, 2] = fx
            out_member[k, m, 3] = fy
        size = (abs(dx), abs(dy), np.sqrt(dx * dx + dy * dy), abs(fx), abs(fy), np.sqrt(fx * fx + fy * fy))
        for j in range(6):
            if size[j] > peak_member[m, j]:
                peak_member[m, j] = size[j]


@kernel(**INTERNAL)
def yield_possible_within(horizon, u, v, a, members, plastic):
    """Whether some member may reach its yield surface within `horizon` s: its plastic-spring
    force bounded by |f| + k_h·(|δ̇|·H + ½|δ̈|·H²) per axis (δ̇, δ̈ from v and a)."""
    bottom, top, arm_b, arm_t, axes, k0, kh, fh, coupled = members
    for m in range(top.size):
        dx, dy = member_deflection(m, u, bottom, top, arm_b, arm_t, axes)
        vx, vy = member_deflection(m, v, bottom, top, arm_b, arm_t, axes)
        ax, ay = member_deflection(m, a, bottom, top, arm_b, arm_t, axes)
        bx = (abs(kh[m, 0] * (dx - plastic[m, 0])) + kh[m, 0] * (abs(vx) * horizon + 0.5 * abs(ax) * horizon**2))
        by = (abs(kh[m, 1] * (dy - plastic[m, 1])) + kh[m, 1] * (abs(vy) * horizon + 0.5 * abs(ay) * horizon**2))
        qx = bx / fh[m, 0]
        qy = by / fh[m, 1]
        if coupled[m]:
            if qx * qx + qy * qy >= 1.0:
                return True
        elif qx >= 1.0 or qy >= 1.0:
            return True
    return False


def bilinear_response(deflection: np.ndarray, k: tuple[float, float], yield_force: tuple[float, float],
                      post_yield_ratio: tuple[float, float], coupled: bool) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Forces (n, 2) N and cumulative dissipated energy (n,) J of one member driven through
    the local deflections (n, 2) m, by the same return mapping as the time loop (for tests and
    the docs' loop plots)."""
    k0 = np.asarray(k, dtype=float)
    alpha = np.asarray(post_yield_ratio, dtype=float)
    kh, fh = (1 - alpha) * k0, (1 - alpha) * np.asarray(yield_force, dtype=float)
    p = np.zeros(2)
    last = np.zeros(2)
    forces = np.empty((len(deflection), 2))
    energy = np.empty(len(deflection))
    total = 0.0
    for i, (dx, dy) in enumerate(np.asarray(deflection, dtype=float)):
        fx, fy, px, py, work, yielded = return_map(last[0], last[1], dx, dy, p[0], p[1], kh[0], kh[1], fh[0], fh[1],
                                                   coupled)  # fmt: skip
        last[:] = dx, dy
        if yielded:
            total += work
            p[:] = px, py
        forces[i] = k0 * (dx, dy) - kh * p
        energy[i] = total
    return forces, energy
