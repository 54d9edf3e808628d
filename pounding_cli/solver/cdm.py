"""The central difference method (the paper's integrator), compiled with numba.

Written in the equivalent leapfrog form with half-step velocities, which is algebraically
the classical CDM of Chopra (Table 5.3.1) for M·ü + C·u̇ + f_s(u) = p(t):

    r_n       = p_n − f_s(u_n) − C·v_{n−½}
    Δv_n      = (M/Δt + C/2)⁻¹ · r_n
    v_{n+½}   = v_{n−½} + Δv_n,     u_{n+1} = u_n + Δt·v_{n+½}
    v_n       = v_{n−½} + Δv_n/2,   a_n = Δv_n/Δt   (central-difference velocity, acceleration)

with p_n = −M·ι·a_g(t_n) and C = a0·M + a1·K per building. (M/Δt + C/2)⁻¹ is dense per
building and computed once. Everything here works on plain arrays and allocates nothing.

Energy (relative-motion form): E_input = ∫ v·p dt and E_damping = ∫ v·C·v dt by the
trapezoidal rule over the central-difference velocities v_n; E_kinetic = ½ v_nᵀM v_n,
E_strain = ½ u_nᵀK u_n. The balance error E_input − (E_k + E_s + E_d) is O(Δt²).
"""

from __future__ import annotations

import numpy as np
from numba import njit

# energy columns, in the order of the HDF5 /energy dataset
E_INPUT, E_KINETIC, E_STRAIN, E_DAMPING, E_HYSTERETIC, E_CONTACT, E_BALANCE = range(7)
ENERGY_NAMES = ("input", "kinetic", "strain", "damping", "hysteretic", "contact", "balance_error")

# accumulators carried between calls: input energy, damping energy, last powers
ACC_INPUT, ACC_DAMPING, ACC_P_INPUT, ACC_P_DAMPING = range(4)

STATUS_OK, STATUS_DIVERGED = 0, 1


@njit(cache=True, inline="always")
def ground_at(t, ground, ground_dt):
    """Ground acceleration (X, Y) at time t, linear between samples, zero after the record."""
    x = t / ground_dt
    i = int(np.floor(x))
    n = ground.shape[0]
    if i < 0 or i >= n:
        return 0.0, 0.0
    if i == n - 1:
        if x - i <= 1e-9:
            return ground[i, 0], ground[i, 1]
        return 0.0, 0.0
    w = x - i
    return (1 - w) * ground[i, 0] + w * ground[i + 1, 0], (1 - w) * ground[i, 1] + w * ground[i + 1, 1]


@njit(cache=True)
def storey_forces(x, y, storey_k, bottom, top, a1, fx, fy):
    """fx = K·x and fy = Σ_s a1_s·K_s·y over all storeys (linear shear storeys)."""
    fx[:] = 0.0
    fy[:] = 0.0
    for s in range(storey_k.shape[0]):
        b = bottom[s]
        t = top[s]
        for r in range(6):
            acc_x = 0.0
            acc_y = 0.0
            for c in range(6):
                if c < 3:
                    if b < 0:
                        continue
                    xc = x[3 * b + c]
                    yc = y[3 * b + c]
                else:
                    xc = x[3 * t + c - 3]
                    yc = y[3 * t + c - 3]
                k = storey_k[s, r, c]
                acc_x += k * xc
                acc_y += k * yc
            if r < 3:
                if b < 0:
                    continue
                fx[3 * b + r] += acc_x
                fy[3 * b + r] += a1[s] * acc_y
            else:
                fx[3 * t + r - 3] += acc_x
                fy[3 * t + r - 3] += a1[s] * acc_y


@njit(cache=True)
def storey_matvec(x, storey_k, bottom, top, weight, out):
    """out = Σ_s weight_s·K_s·x over all storeys."""
    out[:] = 0.0
    for s in range(storey_k.shape[0]):
        b = bottom[s]
        t = top[s]
        for r in range(6):
            if r < 3 and b < 0:
                continue
            acc = 0.0
            for c in range(6):
                if c < 3:
                    if b >= 0:
                        acc += storey_k[s, r, c] * x[3 * b + c]
                else:
                    acc += storey_k[s, r, c] * x[3 * t + c - 3]
            row = 3 * b + r if r < 3 else 3 * t + r - 3
            out[row] += weight[s] * acc


@njit(cache=True)
def solve_blocks(binv, dof_start, dof_count, r, out):
    """out = blockdiag(B⁻¹)·r, one dense block per building."""
    for b in range(dof_start.size):
        d0 = dof_start[b]
        n = dof_count[b]
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += binv[b, i, j] * r[d0 + j]
            out[d0 + i] = acc


@njit(cache=True)
def update_peaks(u, acc_abs, storey_top, storey_bottom, col_storey, arm_b, arm_t, axes,
                 peak_col, peak_rot, peak_disp, peak_acc):
    """Running maxima: column deflections in building axes, storey twist, floor motion."""
    for c in range(col_storey.size):
        s = col_storey[c]
        t = storey_top[s]
        b = storey_bottom[s]
        dx = u[3 * t] - u[3 * t + 2] * arm_t[c, 1]
        dy = u[3 * t + 1] + u[3 * t + 2] * arm_t[c, 0]
        if b >= 0:
            dx -= u[3 * b] - u[3 * b + 2] * arm_b[c, 1]
            dy -= u[3 * b + 1] + u[3 * b + 2] * arm_b[c, 0]
        lx = abs(axes[c, 0] * dx + axes[c, 1] * dy)
        ly = abs(-axes[c, 1] * dx + axes[c, 0] * dy)
        if lx > peak_col[c, 0]:
            peak_col[c, 0] = lx
        if ly > peak_col[c, 1]:
            peak_col[c, 1] = ly
    for s in range(storey_top.size):
        t = storey_top[s]
        b = storey_bottom[s]
        rot = u[3 * t + 2] - (u[3 * b + 2] if b >= 0 else 0.0)
        if abs(rot) > peak_rot[s]:
            peak_rot[s] = abs(rot)
    for d in range(u.size):
        if abs(u[d]) > peak_disp[d]:
            peak_disp[d] = abs(u[d])
        if abs(acc_abs[d]) > peak_acc[d]:
            peak_acc[d] = abs(acc_abs[d])


@njit(cache=True)
def advance(
    n_start, n_stop, dt, stride, u_limit,
    # structure
    mass, dof_a0, storey_k, storey_bottom, storey_top, storey_a1, binv, dof_start, dof_count,
    # ground
    ground, ground_dt,
    # columns (for peaks)
    col_storey, arm_b, arm_t, axes,
    # state, carried between calls
    u, v_half, acc,
    # peaks
    peak_col, peak_rot, peak_disp, peak_acc,
    # outputs at every `stride` steps
    out_u, out_v, out_a, out_ground, out_energy,
    # work arrays (n_dof each)
    ku, cv, r, dv, v, a_abs,
):
    """Advance steps n_start … n_stop − 1; returns (status, last step done + 1)."""
    n_dof = mass.size
    for n in range(n_start, n_stop):
        # 1. ground input at t_n
        agx, agy = ground_at(n * dt, ground, ground_dt)
        # 2. internal forces: K·u_n and the stiffness part of C·v_{n-1/2}
        storey_forces(u, v_half, storey_k, storey_bottom, storey_top, storey_a1, ku, cv)
        # 3. (contact forces: none yet)
        # 4. residual and velocity increment
        for d in range(n_dof):
            ag = agx if d % 3 == 0 else (agy if d % 3 == 1 else 0.0)
            r[d] = -mass[d] * ag - ku[d] - cv[d] - dof_a0[d] * mass[d] * v_half[d]
        solve_blocks(binv, dof_start, dof_count, r, dv)
        # 5. state at t_n: central-difference velocity, absolute acceleration
        for d in range(n_dof):
            v[d] = v_half[d] + 0.5 * dv[d]
            ag = agx if d % 3 == 0 else (agy if d % 3 == 1 else 0.0)
            a_abs[d] = dv[d] / dt + ag
        # 6. energy: trapezoidal input and damping work
        storey_matvec(v, storey_k, storey_bottom, storey_top, storey_a1, cv)
        p_in = 0.0
        p_damp = 0.0
        for d in range(n_dof):
            ag = agx if d % 3 == 0 else (agy if d % 3 == 1 else 0.0)
            p_in += -mass[d] * ag * v[d]
            p_damp += v[d] * (cv[d] + dof_a0[d] * mass[d] * v[d])
        if n > 0:
            acc[ACC_INPUT] += 0.5 * dt * (acc[ACC_P_INPUT] + p_in)
            acc[ACC_DAMPING] += 0.5 * dt * (acc[ACC_P_DAMPING] + p_damp)
        acc[ACC_P_INPUT] = p_in
        acc[ACC_P_DAMPING] = p_damp
        # 7. peaks at every step
        update_peaks(u, a_abs, storey_top, storey_bottom, col_storey, arm_b, arm_t, axes,
                     peak_col, peak_rot, peak_disp, peak_acc)
        # 8. output and divergence check
        if n % stride == 0:
            k = n // stride
            e_kin = 0.0
            e_str = 0.0
            worst = 0.0
            for d in range(n_dof):
                e_kin += 0.5 * mass[d] * v[d] * v[d]
                e_str += 0.5 * u[d] * ku[d]
                out_u[k, d] = u[d]
                out_v[k, d] = v[d]
                out_a[k, d] = a_abs[d]
                if u[d] != u[d]:
                    worst = np.inf
                elif abs(u[d]) > worst:
                    worst = abs(u[d])
            out_ground[k, 0] = agx
            out_ground[k, 1] = agy
            out_energy[k, E_INPUT] = acc[ACC_INPUT]
            out_energy[k, E_KINETIC] = e_kin
            out_energy[k, E_STRAIN] = e_str
            out_energy[k, E_DAMPING] = acc[ACC_DAMPING]
            out_energy[k, E_HYSTERETIC] = 0.0
            out_energy[k, E_CONTACT] = 0.0
            out_energy[k, E_BALANCE] = acc[ACC_INPUT] - (e_kin + e_str + acc[ACC_DAMPING])
            if not worst <= u_limit:
                return STATUS_DIVERGED, n + 1
        # 9. update
        for d in range(n_dof):
            v_half[d] += dv[d]
            u[d] += dt * v_half[d]
    return STATUS_OK, n_stop
