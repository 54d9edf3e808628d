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
"""

from __future__ import annotations

from .contact import (
    contact_finest_level_within,
    contact_forces,
    contact_pairs_needed,
    contact_possible_within,
    contact_ruled_out_within,
)
from .jit import phase


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
        force[e] = 0.0
        force[e + 1] = 0.0
        force[e + 2] = 0.0


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
