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

Return mapping (backward Euler, exact for a given total deflection): trial force
f_tr = k_h ⊙ (δ − p); "independent": each axis clamped to ±f_h; "elliptical": if
q = f_tr ⊘ f_h has |q| > 1, the force returns to the closest point of the yield ellipse
(f_x/f_h,x)² + (f_y/f_h,y)² = 1 in the energy norm Σ Δf_i²/k_h,i (associative flow: Δp is
normal to the ellipse), f_i = f_tr,i/(1 + λ·k_h,i/f_h,i²) with the scalar λ from a few Newton
steps (closest_point_factors); when k_h,x/f_h,x² = k_h,y/f_h,y² (a round isolator, a square
column) that is the radial return q ← q/|q|. Then p = δ − f/k_h. The dissipated energy of the
increment is f·Δp, exact for the one-dimensional law (the force stays on the yield surface
while p moves).

Energy: E_strain = ½·uᵀK·u − uᵀg + ½·Σ k_h ⊙ p² (the recoverable energy of both springs),
E_hysteretic = Σ f·Δp. Nothing here allocates.
"""

from __future__ import annotations

import numpy as np

from .jit import kernel


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
def closest_point_factors(qx, qy, ax, ay):
    """(1 + λ·a_x, 1 + λ·a_y) for the closest point of the ellipse |q| = 1 to the trial
    q = f_tr ⊘ f_h (|q| > 1) in the energy norm Σ Δf_i²/k_h,i, a_i = k_h,i/f_h,i²: the returned
    force is f_i = f_tr,i/(1 + λ·a_i) with λ ≥ 0 the root of
    h(λ) = Σ (q_i/(1 + λ·a_i))² − 1. h is convex and decreasing, so Newton's method from λ = 0
    climbs to the root without overshooting; with a_x = a_y it is the radial return."""
    q = np.sqrt(qx * qx + qy * qy)
    if abs(ax - ay) <= 1e-12 * max(ax, ay):
        return q, q
    lam = 0.0
    for _ in range(100):
        bx = 1.0 + lam * ax
        by = 1.0 + lam * ay
        tx = qx / bx
        ty = qy / by
        h = tx * tx + ty * ty - 1.0
        if h <= 1e-15:
            break
        slope = -2.0 * (tx * tx * ax / bx + ty * ty * ay / by)
        lam -= h / slope
    return 1.0 + lam * ax, 1.0 + lam * ay


@kernel(inline="always")
def return_map(dx, dy, px, py, khx, khy, fhx, fhy, coupled):
    """Plastic-spring force (f_x, f_y) and plastic deflection (p_x, p_y) after a step to the
    total deflection (dx, dy) from plastic deflection (px, py); returns (fx, fy, px, py, yielded)."""
    fx = khx * (dx - px)
    fy = khy * (dy - py)
    qx = fx / fhx
    qy = fy / fhy
    if coupled:
        q2 = qx * qx + qy * qy
        if q2 <= 1.0:
            return fx, fy, px, py, False
        lam_x, lam_y = closest_point_factors(qx, qy, khx / (fhx * fhx), khy / (fhy * fhy))
        fx = fx / lam_x
        fy = fy / lam_y
        return fx, fy, dx - fx / khx, dy - fy / khy, True
    yielded = False
    if qx > 1.0 or qx < -1.0:
        fx = fhx if qx > 0 else -fhx
        px = dx - fx / khx
        yielded = True
    if qy > 1.0 or qy < -1.0:
        fy = fhy if qy > 0 else -fhy
        py = dy - fy / khy
        yielded = True
    return fx, fy, px, py, yielded


@kernel
def update_members(u, members, plastic, g):
    """Return-map every member at the displacement u; add the change of k_h ⊙ p to the
    plastic correction g. Returns (energy dissipated J, members that yielded)."""
    bottom, top, arm_b, arm_t, axes, k0, kh, fh, coupled = members
    dissipated = 0.0
    n_yielded = 0
    for m in range(top.size):
        dx, dy = member_deflection(m, u, bottom, top, arm_b, arm_t, axes)
        px0 = plastic[m, 0]
        py0 = plastic[m, 1]
        fx, fy, px, py, yielded = return_map(dx, dy, px0, py0, kh[m, 0], kh[m, 1], fh[m, 0], fh[m, 1], coupled[m])
        if yielded:
            n_yielded += 1
            dissipated += fx * (px - px0) + fy * (py - py0)
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


@kernel
def plastic_energy_terms(u, g, members, plastic):
    """−uᵀg + ½·Σ k_h ⊙ p²: what the plastic deflections change in the strain energy ½uᵀKu, J."""
    kh = members[6]
    e = 0.0
    for d in range(u.size):
        e -= u[d] * g[d]
    for m in range(kh.shape[0]):
        e += 0.5 * (kh[m, 0] * plastic[m, 0] ** 2 + kh[m, 1] * plastic[m, 1] ** 2)
    return e


@kernel
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


@kernel
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
    forces = np.empty((len(deflection), 2))
    energy = np.empty(len(deflection))
    total = 0.0
    for i, (dx, dy) in enumerate(np.asarray(deflection, dtype=float)):
        fx, fy, px, py, yielded = return_map(dx, dy, p[0], p[1], kh[0], kh[1], fh[0], fh[1], coupled)
        if yielded:
            total += fx * (px - p[0]) + fy * (py - p[1])
            p[:] = px, py
        forces[i] = k0 * (dx, dy) - kh * p
        energy[i] = total
    return forces, energy
