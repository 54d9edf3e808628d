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
special case. Everything here works on the plain arrays of the records in records.py and
allocates nothing.
"""

from __future__ import annotations

import numpy as np
from .jit import INTERNAL, REASSOCIATE, kernel, phase
from .layout import E_BALANCE, E_CONTACT, E_DAMPING, E_HYSTERETIC, E_INPUT, E_KINETIC, E_STRAIN
from .storey_bodies import forces_with_storeys, track_column_shears
from .hysteresis import member_states, plastic_correction, plastic_energy_terms, update_members
from .peaks import update_peaks, update_peaks_range
from .tunables import DIVERGENCE_LIMIT, ENERGY_LIMIT


# accumulators carried between calls: input, damping and contact energy, their last powers,
# the number of steps with a contact, and a flag "no earlier power to integrate from" (set at
# the start and when an integrator takes over at an instant already accounted for); the
# hybrid's exact steps leave their exact input and damping work in the last two
# (exact.propagate)
(ACC_INPUT, ACC_DAMPING, ACC_CONTACT, ACC_P_INPUT, ACC_P_DAMPING, ACC_P_CONTACT, ACC_CONTACT_STEPS,
 ACC_FRESH, ACC_ENERGY_FLOOR, ACC_HYSTERETIC, ACC_STEP_INPUT, ACC_STEP_DAMPING) = range(12)  # fmt: skip
N_ACC = 12

STATUS_OK, STATUS_DIVERGED, STATUS_ENERGY = 0, 1, 2


@kernel(inline="always")
def ground_at(t, ground):
    """Ground acceleration (X, Y) at time t, m/s², linear between samples, zero after the
    record (ground: records.Ground)."""
    record = ground.acceleration
    x = t / ground.dt
    i = int(np.floor(x))
    n = record.shape[0]
    if i < 0 or i >= n:
        return 0.0, 0.0
    if i == n - 1:
        if x - i <= 1e-9:
            return record[i, 0], record[i, 1]
        return 0.0, 0.0
    w = x - i
    return (1 - w) * record[i, 0] + w * record[i + 1, 0], (1 - w) * record[i, 1] + w * record[i + 1, 1]


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def storey_matvec(x, storey_k, bottom, top, out):
    """out = K·x, summed storey by storey (K_s is 6×6 on the DOFs of bottom[s], top[s]), then
    link by link."""
    _storey_product(x, storey_k, bottom, top, 0, x.size // 3 - 1, out)


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def storey_matvec_range(x, storey_k, bottom, top, f0, f1, out):
    """out = K·x on the floors f0 … f1 − 1 of whole buildings, from their storeys alone (storey s
    is the one beneath floor s, so a building's storeys are its floors' numbers): the entries of
    those floors are set, the ground's (the last three, which no one reads) cleared, the rest
    left as they are."""
    _storey_product(x, storey_k, bottom, top, f0, f1, out)


@kernel(fastmath=REASSOCIATE, inline="always")
def _storey_product(x, storey_k, bottom, top, f0, f1, out):
    """storey_matvec_range's body, inlined into both kernels (numba's inlining: a call layer
    cost 10 % of a CDM step of two buildings). The stiffness links after the storeys
    (records.Structure.storey_k: the struck columns' local modes) count where their top floor
    is in range (a link joins two floors of one building)."""
    for d in range(3 * f0, 3 * f1):
        out[d] = 0.0
    for d in range(out.size - 3, out.size):
        out[d] = 0.0
    for s in range(f0, f1):
        _block_product(s, x, storey_k, bottom, top, out)
    for s in range(x.size // 3 - 1, storey_k.shape[0]):
        if f0 <= top[s] < f1:
            _block_product(s, x, storey_k, bottom, top, out)


@kernel(fastmath=REASSOCIATE, inline="always")
def _block_product(s, x, storey_k, bottom, top, out):
    """out += K_s·x for the 6×6 block s on the DOFs of floors bottom[s] and top[s]."""
    b = 3 * bottom[s]
    t = 3 * top[s]
    for r in range(6):
        acc = 0.0
        for c in range(3):
            acc += storey_k[s, r, c] * x[b + c] + storey_k[s, r, c + 3] * x[t + c]
        out[b + r if r < 3 else t + r - 3] += acc


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def storey_matvec_pair_range(x, y, storey_k, bottom, top, f0, f1, kx, ky):
    """kx = K·x and ky = K·y in one pass over the storeys of the floors f0 … f1 − 1 of whole
    buildings (as storey_matvec_range, twice)."""
    for d in range(3 * f0, 3 * f1):
        kx[d] = 0.0
        ky[d] = 0.0
    for d in range(kx.size - 3, kx.size):
        kx[d] = 0.0
        ky[d] = 0.0
    for s in range(f0, f1):
        _block_pair_product(s, x, y, storey_k, bottom, top, kx, ky)
    for s in range(x.size // 3 - 1, storey_k.shape[0]):
        if f0 <= top[s] < f1:
            _block_pair_product(s, x, y, storey_k, bottom, top, kx, ky)


@kernel(fastmath=REASSOCIATE, inline="always")
def _block_pair_product(s, x, y, storey_k, bottom, top, kx, ky):
    """kx += K_s·x and ky += K_s·y for the 6×6 block s (as _block_product, twice)."""
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
    building's C its superstructure's on its deformation (assembly/damping.py) and give the
    struck columns' local modes their own dashpots (assembly/local_modes.py); none else."""
    _damping_product(v, kv, mass, damping, 0, n_dof, out)


@kernel(**INTERNAL)
def damping_force_range(v, kv, mass, damping, d0, d1, out):
    """damping_force on the DOFs d0 … d1 − 1 of whole buildings, and the links whole (scenes
    with links never put a building to sleep, sleep.py: there the range is every DOF)."""
    _damping_product(v, kv, mass, damping, d0, d1, out)


@kernel(inline="always")
def _damping_product(v, kv, mass, damping, d0, d1, out):
    """damping_force_range's body, inlined into both kernels."""
    a0, a1, link, link_bottom, link_top = damping
    for d in range(d0, d1):
        out[d] = a0[d] * mass[d] * v[d] + a1[d] * kv[d]
    for k in range(link.shape[0]):
        b = 3 * link_bottom[k]
        t = 3 * link_top[k]
        for r in range(6):
            acc = 0.0
            for c in range(3):
                acc += link[k, r, c] * v[b + c] + link[k, r, c + 3] * v[t + c]
            out[b + r if r < 3 else t + r - 3] += acc


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def solve_blocks(binv, dof_start, dof_count, dof_real, r, out):
    """out = blockdiag(B⁻¹)·r, one dense block per building; a building with local modes
    (dof_real < dof_count) by its factored form (_solve_reduced; its rows of r are overwritten)."""
    for b in range(dof_start.size):
        d0 = dof_start[b]
        n = dof_count[b]
        if dof_real[b] < n:
            _solve_reduced(binv, b, d0, n, dof_real[b], r, out)
            continue
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += binv[b, i, j] * r[d0 + j]
            out[d0 + i] = acc


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def solve_listed(binv, dof_start, dof_count, dof_real, blocks, n_blocks, r, out):
    """solve_blocks for the buildings blocks[0 … n_blocks − 1] alone (written out: shared
    through an inlined body, the CDM step of two buildings measured 6-10 % slower)."""
    for k in range(n_blocks):
        b = blocks[k]
        d0 = dof_start[b]
        n = dof_count[b]
        if dof_real[b] < n:
            _solve_reduced(binv, b, d0, n, dof_real[b], r, out)
            continue
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += binv[b, i, j] * r[d0 + j]
            out[d0 + i] = acc


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def _solve_reduced(binv, b, d0, n, nr, r, out):
    """B·x = r for a building whose DOFs nr … n − 1 are its struck columns' local modes
    (pseudo-floors, assembly/local_modes.py), by the Schur complement on its own floors: B_pp is
    block-diagonal (3 × 3 per pseudo-floor: a mode is linked to the floors alone), so with
    binv[b] = [[S⁻¹, B_rp], [G, B_pp⁻¹]] (G = B_pp⁻¹·B_pr, S = B_rr − B_rp·G;
    integrate.step_matrices) y = B_pp⁻¹·r_p, x_r = S⁻¹·(r_r − B_rp·y), x_p = y − G·x_r:
    n_r² + 2·n_r·n_p + 3·n_p products instead of n². r_r is overwritten."""
    for j in range(nr, n, 3):
        for i in range(3):
            acc = 0.0
            for c in range(3):
                acc += binv[b, j + i, j + c] * r[d0 + j + c]
            out[d0 + j + i] = acc
    for i in range(nr):
        acc = r[d0 + i]
        for j in range(nr, n):
            acc -= binv[b, i, j] * out[d0 + j]
        r[d0 + i] = acc
    for i in range(nr):
        acc = 0.0
        for k in range(nr):
            acc += binv[b, i, k] * r[d0 + k]
        out[d0 + i] = acc
    for j in range(nr, n):
        acc = out[d0 + j]
        for k in range(nr):
            acc -= binv[b, j, k] * out[d0 + k]
        out[d0 + j] = acc


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


@kernel(**INTERNAL)
def write_output(k, u, v, a_abs, ku, agx, agy, mass, acc, pair_now, fc, out, e_plastic):
    """Store the state at output sample k into out (records.Output; ku = K·u at that instant,
    fc the contact forces on the floors, e_plastic what yielding members change in the strain
    energy ½uᵀKu, hysteresis.py);
    returns STATUS_OK, or STATUS_DIVERGED when a displacement passes DIVERGENCE_LIMIT or is
    NaN, or STATUS_ENERGY when the energy balance error passes ENERGY_LIMIT of the energy in
    play."""
    out_u, out_v, out_a, out_energy, out_contact = out.displacement, out.velocity, out.acceleration, out.energy, \
        out.contact  # fmt: skip
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
        out.floor_contact[k, d] = fc[d]
        if u[d] != u[d]:
            worst = np.inf
        elif abs(u[d]) > worst:
            worst = abs(u[d])
    out.ground[k, 0] = agx
    out.ground[k, 1] = agy
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
    if not worst <= DIVERGENCE_LIMIT:
        return STATUS_DIVERGED
    in_play = max(abs(acc[ACC_INPUT]), e_kin + e_str + acc[ACC_DAMPING] + e_hyst + abs(acc[ACC_CONTACT]))
    if abs(out_energy[k, E_BALANCE]) > ENERGY_LIMIT * in_play and in_play > acc[ACC_ENERGY_FLOOR]:
        return STATUS_ENERGY
    if -acc[ACC_CONTACT] > ENERGY_LIMIT * max(abs(acc[ACC_INPUT]), acc[ACC_ENERGY_FLOOR]):
        return STATUS_ENERGY  # the contacts created energy
    return STATUS_OK


@phase
def _contact_phase_awake(n, dt, motion, dv, contact, awake):
    """Contact forces at t_n from the displaced outlines into contact.force (zero without
    candidates): broad phase, narrow phase, impact law (contact.contact_forces; struck storeys as virtual floors,
    storey_bodies.py), with the
    dashpots' velocity v_n ≈ v_{n−½} + Δv_{n−1}/2 (dv still holds the last step's) of the
    awake buildings (a sleeping one has no pair that can touch)."""
    contact.force[:] = 0.0
    if contact.law.a.size > 0:
        runs = awake.runs
        for i in range(awake.n_runs[0]):
            for d in range(3 * runs[i, 0], 3 * runs[i, 1]):
                contact.v_est[d] = motion.v_half[d] + 0.5 * dv[d]
        if forces_with_storeys(n, dt, motion.u, motion.v_half, contact.v_est, contact) > 0:
            motion.energy[ACC_CONTACT_STEPS] += 1.0


@phase
def _velocity_update_awake(agx, agy, step, structure, motion, work, fc, awake):
    """_velocity_update for the awake buildings (no yielding members: where buildings sleep
    there are none, integrate.may_sleep)."""
    mass, ku, cv_half, v_half = structure.mass, motion.ku, motion.cv_half, motion.v_half
    ground_mass, influence = structure.ground_mass, structure.influence
    r, dv, v, a_abs = work.r, work.dv, work.v, work.a_abs
    runs = awake.runs
    for i in range(awake.n_runs[0]):
        for f in range(runs[i, 0], runs[i, 1]):
            d = 3 * f
            r[d] = -ground_mass[d] * agx - ku[d] - cv_half[d] + fc[d]
            r[d + 1] = -ground_mass[d + 1] * agy - ku[d + 1] - cv_half[d + 1] + fc[d + 1]
            r[d + 2] = -ku[d + 2] - cv_half[d + 2] + fc[d + 2]
    for i in range(awake.n_runs[0]):
        solve_listed(step.inverse, structure.dof_start, structure.dof_count, structure.dof_real,
                     structure.buildings[runs[i, 6]:],
                     runs[i, 7] - runs[i, 6], r, dv)  # fmt: skip
    for i in range(awake.n_runs[0]):
        d0 = 3 * runs[i, 0]
        d1 = 3 * runs[i, 1]
        for d in range(d0, d1):
            v[d] = v_half[d] + 0.5 * dv[d]
            a_abs[d] = dv[d] / step.dt
        for f in range(runs[i, 0], runs[i, 1]):
            a_abs[3 * f] += influence[3 * f] * agx
            a_abs[3 * f + 1] += influence[3 * f + 1] * agy
        for d in range(d0, d1):
            v_half[d] += dv[d]
        storey_matvec_range(v_half, structure.storey_k, structure.storey_bottom, structure.storey_top, runs[i, 0],
                            runs[i, 1], work.z)  # fmt: skip
        damping_force_range(v_half, work.z, mass, structure.damping, d0, d1, work.cv_next)


@phase
def _step_energy_awake(agx, agy, dt, mass, motion, work, fc, awake):
    """The trapezoidal step of the input, damping and contact work of the awake buildings, from
    the powers at t_n (mass: M·ι, the masses the ground drives) (C·v_n = ½(C·v_{n−½} + C·v_{n+½}), C being linear)."""
    v, cv_half, cv_next = work.v, motion.cv_half, work.cv_next
    runs = awake.runs
    p_in = 0.0
    p_damp = 0.0
    p_contact = 0.0
    for i in range(awake.n_runs[0]):
        for f in range(runs[i, 0], runs[i, 1]):
            p_in -= mass[3 * f] * (agx * v[3 * f] + agy * v[3 * f + 1])
    for i in range(awake.n_runs[0]):
        for d in range(3 * runs[i, 0], 3 * runs[i, 1]):
            p_damp += 0.5 * v[d] * (cv_half[d] + cv_next[d])
            p_contact -= fc[d] * v[d]
    accumulate_energy(motion.energy, dt, p_in, p_damp, p_contact)


@phase
def _step_peaks_awake(motion, work, structure, peaks, awake):
    """The running peaks of the awake buildings at t_n."""
    runs = awake.runs
    for i in range(awake.n_runs[0]):
        update_peaks_range(motion.u, work.a_abs, structure, work.storey_work, peaks, runs[i, 0], runs[i, 1],
                           runs[i, 2], runs[i, 3], runs[i, 4], runs[i, 5])  # fmt: skip


@phase
def _position_update_awake(n, step, structure, motion, work, awake):
    """_position_update for the awake buildings (no yielding members, as above). False when a
    displacement passes DIVERGENCE_LIMIT or is not finite."""
    u, ku, cv_half = motion.u, motion.ku, motion.cv_half
    dt = step.dt
    runs = awake.runs
    for i in range(awake.n_runs[0]):
        for d in range(3 * runs[i, 0], 3 * runs[i, 1]):
            u[d] += dt * motion.v_half[d]
            ku[d] += dt * work.z[d]
            cv_half[d] = work.cv_next[d]
            if not abs(u[d]) <= DIVERGENCE_LIMIT:
                return False
        if (n + 1) % step.per_output == 0:
            storey_matvec_range(u, structure.storey_k, structure.storey_bottom, structure.storey_top, runs[i, 0],
                                runs[i, 1], ku)  # fmt: skip
    return True


@phase
def _contact_phase(n, dt, motion, dv, contact):
    """Contact forces at t_n from the displaced outlines into contact.force (zero without
    candidates): broad phase, narrow phase, impact law (contact.contact_forces; struck storeys as virtual floors,
    storey_bodies.py), with the
    dashpots' velocity v_n ≈ v_{n−½} + Δv_{n−1}/2 (dv still holds the last step's)."""
    contact.force[:] = 0.0
    if contact.law.a.size > 0:
        for d in range(motion.u.size - 3):
            contact.v_est[d] = motion.v_half[d] + 0.5 * dv[d]
        if forces_with_storeys(n, dt, motion.u, motion.v_half, contact.v_est, contact) > 0:
            motion.energy[ACC_CONTACT_STEPS] += 1.0


@phase
def _velocity_update(agx, agy, step, structure, motion, work, fc, g):
    """r_n = p_n − K·u_n − C·v_{n−½} + F_contact + g; Δv_n = B⁻¹·r_n; the state at t_n
    (v_n = v_{n−½} + Δv_n/2, a_n = Δv_n/Δt plus the ground's); v_{n+½} = v_{n−½} + Δv_n and
    the step's one mat-vec z = K·v_{n+½}, with C·v_{n+½} from it."""
    mass, ku, cv_half, v_half = structure.mass, motion.ku, motion.cv_half, motion.v_half
    ground_mass, influence = structure.ground_mass, structure.influence
    r, dv, v, a_abs = work.r, work.dv, work.v, work.a_abs
    n_dof = mass.size
    n_floors = n_dof // 3
    for f in range(n_floors):
        d = 3 * f
        r[d] = -ground_mass[d] * agx - ku[d] + g[d] - cv_half[d] + fc[d]
        r[d + 1] = -ground_mass[d + 1] * agy - ku[d + 1] + g[d + 1] - cv_half[d + 1] + fc[d + 1]
        r[d + 2] = -ku[d + 2] + g[d + 2] - cv_half[d + 2] + fc[d + 2]
    solve_blocks(step.inverse, structure.dof_start, structure.dof_count, structure.dof_real, r, dv)
    for d in range(n_dof):
        v[d] = v_half[d] + 0.5 * dv[d]
        a_abs[d] = dv[d] / step.dt
    for f in range(n_floors):
        a_abs[3 * f] += influence[3 * f] * agx
        a_abs[3 * f + 1] += influence[3 * f + 1] * agy
    for d in range(n_dof):
        v_half[d] += dv[d]
    storey_matvec(v_half, structure.storey_k, structure.storey_bottom, structure.storey_top, work.z)
    damping_force(v_half, work.z, mass, structure.damping, n_dof, work.cv_next)


@phase
def _step_energy(agx, agy, dt, mass, motion, work, fc):
    """The trapezoidal step of the input, damping and contact work, from the powers at t_n
    (mass: M·ι, the masses the ground drives)
    (C·v_n = ½(C·v_{n−½} + C·v_{n+½}), C being linear)."""
    v, cv_half, cv_next = work.v, motion.cv_half, work.cv_next
    n_dof = mass.size
    p_in = 0.0
    p_damp = 0.0
    p_contact = 0.0
    for f in range(n_dof // 3):
        p_in -= mass[3 * f] * (agx * v[3 * f] + agy * v[3 * f + 1])
    for d in range(n_dof):
        p_damp += 0.5 * v[d] * (cv_half[d] + cv_next[d])
        p_contact -= fc[d] * v[d]
    accumulate_energy(motion.energy, dt, p_in, p_damp, p_contact)


@phase
def _step_output(n, agx, agy, per_output, structure, motion, work, out, contact, yielding):
    """At an output step, the state at t_n into row n / per_output (and the members'), with the
    divergence and energy checks (write_output); at every step the members' peaks. A sleeping
    building's state at t_n is its exact one (sleep.py: output instants are finest-step
    boundaries, where the sleepers' v, a and K·u are written where this reads them)."""
    has_members = yielding.plastic.shape[0] > 0
    if n % per_output == 0:
        e_plastic = 0.0
        if has_members:
            member_states(motion.u, yielding.law, yielding.plastic, n // per_output, yielding.history, yielding.peak)
            e_plastic = plastic_energy_terms(motion.u, yielding.g, yielding.law, yielding.plastic)
        return write_output(n // per_output, motion.u, work.v, work.a_abs, motion.ku, agx, agy, structure.mass,
                            motion.energy, contact.now, contact.force, out, e_plastic)  # fmt: skip
    if has_members:
        member_states(motion.u, yielding.law, yielding.plastic, -1, yielding.history, yielding.peak)
    return STATUS_OK


@phase
def _position_update(n, step, structure, motion, work, yielding):
    """u_{n+1} = u_n + Δt·v_{n+½}, K·u_{n+1} = K·u_n + Δt·z (the ground entries stay zero),
    C·v_{n+½} carried; the members' return map along the step; K·u and the plastic correction
    recomputed from scratch at output steps, so that rounding cannot accumulate. False when a
    displacement passes DIVERGENCE_LIMIT or is not finite."""
    u, ku, cv_half = motion.u, motion.ku, motion.cv_half
    dt = step.dt
    for d in range(structure.mass.size):
        u[d] += dt * motion.v_half[d]
        ku[d] += dt * work.z[d]
        cv_half[d] = work.cv_next[d]
        if not abs(u[d]) <= DIVERGENCE_LIMIT:
            return False
    has_members = yielding.plastic.shape[0] > 0
    if has_members:
        motion.energy[ACC_HYSTERETIC] += update_members(u, yielding.law, yielding.plastic, yielding.g)[0]
    if (n + 1) % step.per_output == 0:
        storey_matvec(u, structure.storey_k, structure.storey_bottom, structure.storey_top, ku)
        if has_members:
            plastic_correction(yielding.law, yielding.plastic, yielding.g)
    return True


@kernel
def advance(n_start, n_stop, step, structure, ground, motion, work, peaks, out, contact, yielding, awake):
    """Advance steps n_start … n_stop − 1 of the CDM (step: records.CdmStep); returns
    (STATUS_OK, n_stop), or (status, m) for the first state u_m (at t_m = m·Δt) that fails a
    check: a displacement that passes DIVERGENCE_LIMIT or is not finite (NaN, ±inf; a
    non-finite velocity or force makes it so within the step) stops the run at the step that
    made it (STATUS_DIVERGED), checked at every step at the cost of one comparison per DOF.

    A step, in its phases: the ground input at t_n; the internal forces K·u_n and C·v_{n−½}
    (carried from the last step); the contact forces (broad phase, narrow phase, impact law);
    the velocity update Δv_n = B⁻¹·r_n and the state at t_n; the energy; the peaks; the
    output; the position update to t_{n+1}. Every building takes them (_advance_all), or,
    where some sleep (records.Awake, sleep.py), the awake ones (_advance_awake)."""
    if awake.n_sleepers[0] == 0:
        return _advance_all(n_start, n_stop, step, structure, ground, motion, work, peaks, out, contact, yielding)
    return _advance_awake(n_start, n_stop, step, structure, ground, motion, work, peaks, out, contact, yielding, awake)


@kernel(**INTERNAL)
def _advance_awake(n_start, n_stop, step, structure, ground, motion, work, peaks, out, contact, yielding, awake):
    """advance for the awake buildings alone: the phases over their runs of floors (a sleeping
    building is propagated exactly by sleep.py). Apart from _advance_all, whose whole-structure
    loops it would otherwise be: with both in one kernel, LLVM's code for the CDM step of two
    buildings was 22 % slower (0.68 against 0.555 µs a step, paper_pounding under the CDM),
    and over one range of buildings these phases took 0.80 µs."""
    dt = step.dt
    for n in range(n_start, n_stop):
        agx, agy = ground_at(n * dt, ground)
        # internal forces K·u_n and C·v_{n−½} are carried in motion.ku, motion.cv_half
        _contact_phase_awake(n, dt, motion, work.dv, contact, awake)
        _velocity_update_awake(agx, agy, step, structure, motion, work, contact.force, awake)
        if contact.storeys.shear_peak.shape[0] > 0:
            track_column_shears(n * dt, agx, agy, motion.u, work.a_abs, contact)
        _step_energy_awake(agx, agy, dt, structure.ground_mass, motion, work, contact.force, awake)
        _step_peaks_awake(motion, work, structure, peaks, awake)
        status = _step_output(n, agx, agy, step.per_output, structure, motion, work, out, contact, yielding)
        if status != STATUS_OK:
            return status, n
        if not _position_update_awake(n, step, structure, motion, work, awake):
            return STATUS_DIVERGED, n + 1
    return STATUS_OK, n_stop


@kernel(**INTERNAL)
def _advance_all(n_start, n_stop, step, structure, ground, motion, work, peaks, out, contact, yielding):
    """advance for every building, each phase over the whole structure."""
    dt = step.dt
    for n in range(n_start, n_stop):
        agx, agy = ground_at(n * dt, ground)
        # internal forces K·u_n and C·v_{n−½} are carried in motion.ku, motion.cv_half
        _contact_phase(n, dt, motion, work.dv, contact)
        _velocity_update(agx, agy, step, structure, motion, work, contact.force, yielding.g)
        if contact.storeys.shear_peak.shape[0] > 0:
            track_column_shears(n * dt, agx, agy, motion.u, work.a_abs, contact)
        _step_energy(agx, agy, dt, structure.ground_mass, motion, work, contact.force)
        update_peaks(motion.u, work.a_abs, structure, work.storey_work, peaks)
        status = _step_output(n, agx, agy, step.per_output, structure, motion, work, out, contact, yielding)
        if status != STATUS_OK:
            return status, n
        if not _position_update(n, step, structure, motion, work, yielding):
            return STATUS_DIVERGED, n + 1
    return STATUS_OK, n_stop
