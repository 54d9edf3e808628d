"""The central difference method (the paper's integrator), compiled with numba.

Written in the equivalent leapfrog form with half-step velocities, which is algebraically
the classical CDM of Chopra (Table 5.3.1) for M·ü + C·u̇ + K·u = p(t):

    r_n       = p_n − K·u_n − C·v_{n−½}
    Δv_n      = (M/Δt + C/2)⁻¹ · r_n
    v_{n+½}   = v_{n−½} + Δv_n,     u_{n+1} = u_n + Δt·v_{n+½}
    v_n       = v_{n−½} + Δv_n/2,   a_n = Δv_n/Δt   (central-difference velocity, acceleration)

with p_n = −M·ι·a_g(t_n) and C = a0·M + a1·K per building (plus, for a base-isolated
building, the 6×6 links of assembly/damping.py: its Rayleigh damping acts on the
superstructure's deformation). (M/Δt + C/2)⁻¹ is dense per building and computed once. One
storey mat-vec per step, z = K·v_{n+½}, serves both the damping force C·v_{n+½} and the update
K·u_{n+1} = K·u_n + Δt·z; K·u is recomputed exactly at every output step so rounding cannot
accumulate.

Contact forces (contact.py) are explicit: computed from u_n and v_{n−½}, they join p_n.

Energy (relative-motion form): E_input = ∫ v·p dt, E_damping = ∫ v·C·v dt and E_contact =
−∫ v·F_contact dt by the trapezoidal rule over the central-difference velocities v_n
(C·v_n = ½(C·v_{n−½} + C·v_{n+½}) since C is linear); E_kinetic = ½ v_nᵀM v_n, E_strain =
½ u_nᵀK u_n. The balance error E_input − (E_k + E_s + E_d + E_c) is O(Δt²).

State vectors hold n_dof + 3 entries: the last three are the ground, an extra floor whose
DOFs stay zero and which is the bottom floor of every ground storey, so no storey is a
special case. Everything here works on plain arrays and allocates nothing.
"""

from __future__ import annotations

import numpy as np
from .jit import REASSOCIATE, kernel

from .contact import contact_forces
from .hysteresis import member_states, plastic_correction, plastic_energy_terms, update_members
from .peaks import update_peaks

# energy columns, in the order of the HDF5 /energy dataset
E_INPUT, E_KINETIC, E_STRAIN, E_DAMPING, E_HYSTERETIC, E_CONTACT, E_BALANCE = range(7)
ENERGY_NAMES = ("input", "kinetic", "strain", "damping", "hysteretic", "contact", "balance_error")

# accumulators carried between calls: input, damping and contact energy, their last powers,
# the number of steps with a contact, and a flag "no earlier power to integrate from" (set at
# the start and when an integrator takes over at an instant already accounted for); the
# hybrid's exact steps leave their exact input and damping work in the last two
# (hybrid.propagate)
(ACC_INPUT, ACC_DAMPING, ACC_CONTACT, ACC_P_INPUT, ACC_P_DAMPING, ACC_P_CONTACT, ACC_CONTACT_STEPS,
 ACC_FRESH, ACC_ENERGY_FLOOR, ACC_HYSTERETIC, ACC_STEP_INPUT, ACC_STEP_DAMPING) = range(12)  # fmt: skip
N_ACC = 12

STATUS_OK, STATUS_DIVERGED, STATUS_ENERGY = 0, 1, 2

ENERGY_LIMIT = 0.05
"""A run whose energy balance error passes this fraction of the energy in play has gone
unstable (a healthy run stays below 1e-4): it stops with STATUS_ENERGY. So does a run whose
contacts have given out more energy than they took, by more than this fraction of the input
(passive contacts store what they take while compressed and lose the rest to friction and
dashpots: their account never falls below zero in a healthy run; an impact integrated with
too long a step creates energy, and the balance, which counts the contact forces' work,
still closes). Energies below acc[ACC_ENERGY_FLOOR] (the structure moving at 1 cm/s) are
too small to judge."""


@kernel(inline="always")
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


@kernel(fastmath=REASSOCIATE)
def storey_matvec(x, storey_k, bottom, top, out):
    """out = K·x, summed storey by storey (K_s is 6×6 on the DOFs of bottom[s], top[s])."""
    out[:] = 0.0
    for s in range(storey_k.shape[0]):
        b = 3 * bottom[s]
        t = 3 * top[s]
        for r in range(6):
            acc = 0.0
            for c in range(3):
                acc += storey_k[s, r, c] * x[b + c] + storey_k[s, r, c + 3] * x[t + c]
            out[b + r if r < 3 else t + r - 3] += acc


@kernel(fastmath=REASSOCIATE)
def storey_matvec_pair(x, y, storey_k, bottom, top, kx, ky):
    """kx = K·x and ky = K·y in one pass over the storeys (as storey_matvec, twice)."""
    kx[:] = 0.0
    ky[:] = 0.0
    for s in range(storey_k.shape[0]):
        b = 3 * bottom[s]
        t = 3 * top[s]
        for r in range(6):
            ax = 0.0
            ay = 0.0
            for c in range(3):
                k_b = storey_k[s, r, c]
                k_t = storey_k[s, r, c + 3]
                ax += k_b * x[b + c] + k_t * x[t + c]
                ay += k_b * y[b + c] + k_t * y[t + c]
            d = b + r if r < 3 else t + r - 3
            kx[d] += ax
            ky[d] += ay


@kernel
def damping_force(v, kv, mass, damping, n_dof, out):
    """out = C·v = a0·M·v + a1·K·v + Σ links·v, given kv = K·v. damping = (a0, a1 per DOF;
    link matrices (n, 6, 6), bottom and top floors (n,)): the links are 6×6 blocks on two
    floors' DOFs (the ground, an extra zero floor, for a bottom) that make an isolated
    building's C its superstructure's on its deformation (assembly/damping.py); none else."""
    a0, a1, link, link_bottom, link_top = damping
    for d in range(n_dof):
        out[d] = a0[d] * mass[d] * v[d] + a1[d] * kv[d]
    for k in range(link.shape[0]):
        b = 3 * link_bottom[k]
        t = 3 * link_top[k]
        for r in range(6):
            acc = 0.0
            for c in range(3):
                acc += link[k, r, c] * v[b + c] + link[k, r, c + 3] * v[t + c]
            out[b + r if r < 3 else t + r - 3] += acc


@kernel(fastmath=REASSOCIATE)
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


@kernel(inline="always")
def accumulate_energy(acc, dt, p_in, p_damp, p_contact):
    """Trapezoidal step of the input, damping and contact work (powers in W over dt s)."""
    if acc[ACC_FRESH] == 0.0:
        acc[ACC_INPUT] += 0.5 * dt * (acc[ACC_P_INPUT] + p_in)
        acc[ACC_DAMPING] += 0.5 * dt * (acc[ACC_P_DAMPING] + p_damp)
        acc[ACC_CONTACT] += 0.5 * dt * (acc[ACC_P_CONTACT] + p_contact)
    acc[ACC_FRESH] = 0.0
    acc[ACC_P_INPUT] = p_in
    acc[ACC_P_DAMPING] = p_damp
    acc[ACC_P_CONTACT] = p_contact


@kernel
def write_output(k, u, v, a_abs, ku, agx, agy, mass, acc, pair_now, out_u, out_v, out_a, out_ground,
                 out_energy, out_contact, u_limit, e_plastic):  # fmt: skip
    """Store the state at output sample k (ku = K·u at that instant, e_plastic what yielding
    members change in the strain energy ½uᵀKu, hysteresis.py); returns STATUS_OK, or
    STATUS_DIVERGED when a displacement passes u_limit or is NaN, or STATUS_ENERGY when the
    energy balance error passes ENERGY_LIMIT of the energy in play."""
    n_dof = mass.size
    e_kin = 0.0
    e_str = e_plastic
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
    e_hyst = acc[ACC_HYSTERETIC]
    out_energy[k, E_HYSTERETIC] = e_hyst
    out_energy[k, E_CONTACT] = acc[ACC_CONTACT]
    out_energy[k, E_BALANCE] = acc[ACC_INPUT] - (e_kin + e_str + acc[ACC_DAMPING] + e_hyst + acc[ACC_CONTACT])
    for p in range(pair_now.shape[0]):
        for c in range(pair_now.shape[1]):
            out_contact[k, p, c] = pair_now[p, c]
    if not worst <= u_limit:
        return STATUS_DIVERGED
    in_play = max(abs(acc[ACC_INPUT]), e_kin + e_str + acc[ACC_DAMPING] + e_hyst + abs(acc[ACC_CONTACT]))
    if abs(out_energy[k, E_BALANCE]) > ENERGY_LIMIT * in_play and in_play > acc[ACC_ENERGY_FLOOR]:
        return STATUS_ENERGY
    if -acc[ACC_CONTACT] > ENERGY_LIMIT * max(abs(acc[ACC_INPUT]), acc[ACC_ENERGY_FLOOR]):
        return STATUS_ENERGY  # the contacts created energy
    return STATUS_OK


@kernel
def advance(
    n_start, n_stop, dt, stride, u_limit,
    # structure
    mass, damping, storey_k, storey_bottom, storey_top, binv, dof_start, dof_count,
    # ground
    ground, ground_dt,
    # geometry for peaks
    storey_axes, centre, col_storey, col_arm,
    # state, carried between calls: u_n, v_{n-1/2}, K·u_n, C·v_{n-1/2}, energy accumulators
    u, v_half, ku, cv_half, acc,
    # peaks
    peak_col, peak_rot, peak_disp, peak_acc,
    # outputs at every `stride` steps
    out_u, out_v, out_a, out_ground, out_energy, out_contact,
    # work arrays (n_dof + 3 each, and n_storeys × 3)
    r, dv, v, a_abs, z, cv_next, storey_work,
    # contact: tuples of arrays (see contact.contact_forces), pair state, impact log, buffers,
    # broad phase (broad_phase.sweep_arrays)
    geometry, params, pair_state, pair_now, events, n_events, fc, v_est, cbuf, broad,
    # yielding members (hysteresis.py): parameters, plastic deflections, correction g, outputs
    members, plastic, g, out_member, peak_member,
):
    """Advance steps n_start … n_stop − 1; returns (STATUS_OK, n_stop), or (status, m) for the
    first state u_m (at t_m = m·dt) that fails a check: a displacement that passes u_limit or
    is not finite (NaN, ±inf; a non-finite velocity or force makes it so within the step)
    stops the run at the step that made it (STATUS_DIVERGED), checked at every step at the
    cost of one comparison per DOF."""
    n_dof = mass.size
    n_floors = n_dof // 3
    has_members = plastic.shape[0] > 0
    for n in range(n_start, n_stop):
        # 1. ground input at t_n
        agx, agy = ground_at(n * dt, ground, ground_dt)
        # 2. internal forces K·u_n and C·v_{n-1/2} are carried in ku, cv_half
        # 3. contact forces from the displaced outlines (broad phase, narrow phase, impact law)
        fc[:] = 0.0
        if params[0].size > 0:
            for d in range(n_dof):  # v_n ≈ v_{n-1/2} + Δv_{n-1}/2 (dv still holds the last step's)
                v_est[d] = v_half[d] + 0.5 * dv[d]
            if contact_forces(n, dt, u, v_half, v_est, geometry, params, pair_state, pair_now, events, n_events,
                              fc, broad, cbuf[0], cbuf[1], cbuf[2], cbuf[3], cbuf[4], cbuf[5], cbuf[6]) > 0:  # fmt: skip
                acc[ACC_CONTACT_STEPS] += 1.0
        # 4. residual and velocity increment
        for f in range(n_floors):
            d = 3 * f
            r[d] = -mass[d] * agx - ku[d] + g[d] - cv_half[d] + fc[d]
            r[d + 1] = -mass[d + 1] * agy - ku[d + 1] + g[d + 1] - cv_half[d + 1] + fc[d + 1]
            r[d + 2] = -ku[d + 2] + g[d + 2] - cv_half[d + 2] + fc[d + 2]
        solve_blocks(binv, dof_start, dof_count, r, dv)
        # 5. state at t_n: central-difference velocity, absolute acceleration
        for d in range(n_dof):
            v[d] = v_half[d] + 0.5 * dv[d]
            a_abs[d] = dv[d] / dt
        for f in range(n_floors):
            a_abs[3 * f] += agx
            a_abs[3 * f + 1] += agy
        # 6. the one mat-vec of the step: z = K·v_{n+1/2}, C·v_{n+1/2}
        for d in range(n_dof):
            v_half[d] += dv[d]
        storey_matvec(v_half, storey_k, storey_bottom, storey_top, z)
        damping_force(v_half, z, mass, damping, n_dof, cv_next)
        # 7. energy: trapezoidal input, damping and contact work
        p_in = 0.0
        p_damp = 0.0
        p_contact = 0.0
        for f in range(n_floors):
            p_in -= mass[3 * f] * (agx * v[3 * f] + agy * v[3 * f + 1])
        for d in range(n_dof):
            p_damp += 0.5 * v[d] * (cv_half[d] + cv_next[d])
            p_contact -= fc[d] * v[d]
        accumulate_energy(acc, dt, p_in, p_damp, p_contact)
        # 8. peaks at every step
        update_peaks(u, a_abs, n_dof, storey_bottom, storey_top, storey_axes, centre,
                     col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc)
        # 9. output and divergence check
        if n % stride == 0:
            e_plastic = 0.0
            if has_members:
                member_states(u, members, plastic, n // stride, out_member, peak_member)
                e_plastic = plastic_energy_terms(u, g, members, plastic)
            status = write_output(n // stride, u, v, a_abs, ku, agx, agy, mass, acc, pair_now,
                                  out_u, out_v, out_a, out_ground, out_energy, out_contact, u_limit, e_plastic)  # fmt: skip
            if status != STATUS_OK:
                return status, n
        elif has_members:
            member_states(u, members, plastic, -1, out_member, peak_member)
        # 10. update to t_{n+1} (the ground entries stay zero); a bad value stops the run here
        for d in range(n_dof):
            u[d] += dt * v_half[d]
            ku[d] += dt * z[d]
            cv_half[d] = cv_next[d]
            if not abs(u[d]) <= u_limit:
                return STATUS_DIVERGED, n + 1
        if has_members:
            acc[ACC_HYSTERETIC] += update_members(u, members, plastic, g)[0]
        if (n + 1) % stride == 0:
            storey_matvec(u, storey_k, storey_bottom, storey_top, ku)
            if has_members:
                plastic_correction(members, plastic, g)
    return STATUS_OK, n_stop
