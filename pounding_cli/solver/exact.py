"""The exact branch of the hybrid integrator (hybrid.py), compiled: the exact state-transition
steps, the state reached by them (forces, accelerations, energy, peaks), and the hand-overs to
and from the CDM.

Each kernel that works on the floors takes a range of them, f0 … f1 − 1, that covers whole
buildings (floors, storeys and columns are numbered building by building): the whole
structure, or, where buildings sleep (sleep.py), the buildings taken apart from the CDM. Over
the whole structure the sums run in the order they always did, so the results are the same
bit for bit.
"""

from __future__ import annotations

from .cdm import (
    ACC_DAMPING,
    ACC_FRESH,
    ACC_INPUT,
    ACC_STEP_DAMPING,
    ACC_STEP_INPUT,
    accumulate_energy,
    damping_force_range,
    ground_at,
    solve_listed,
    storey_matvec_pair_range,
    storey_matvec_range,
)
from .hysteresis import plastic_correction
from .jit import INTERNAL, REASSOCIATE, kernel, phase
from .peaks import peaks_between, settle_crests, update_peaks_range


@kernel(**INTERNAL)
def exact_state(t, structure, ground, motion, work, exact, g, f0, f1):
    """K·u, C·v and the accelerations (absolute into work.a_abs, relative into exact.a_rel) at
    time t from the exact state (motion.u, exact.v) and the members' plastic correction g, on
    the floors f0 … f1 − 1. Returns the ground acceleration (X, Y) at t."""
    u, v, ku, kv, cv, a_abs, a_rel = motion.u, exact.v, motion.ku, exact.kv, work.cv_next, work.a_abs, exact.a_rel
    mass = structure.mass
    agx, agy = ground_at(t, ground)
    d0, d1 = 3 * f0, 3 * f1
    storey_matvec_pair_range(u, v, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, ku, kv)
    damping_force_range(v, kv, mass, structure.damping, d0, d1, cv)
    for d in range(d0, d1):
        a_abs[d] = -(ku[d] - g[d] + cv[d]) / mass[d]
    influence = structure.influence
    for d in range(d0, d1, 3):
        a_rel[d] = a_abs[d] - influence[d] * agx
        a_rel[d + 1] = a_abs[d + 1] - influence[d + 1] * agy
        a_rel[d + 2] = a_abs[d + 2]
    return agx, agy


@kernel(**INTERNAL)
def exact_point(t, gap, structure, ground, motion, work, exact, peaks, g):
    """Everything the exact propagation owes the state (u, v) it reached at t, for the whole
    structure: its motion (exact_motion) and the energy account over the `gap` s since the
    last state accounted for (over an exact step, the work propagate left in
    acc[ACC_STEP_INPUT] and acc[ACC_STEP_DAMPING], exact; else trapezoidal). When that last
    state was the previous exact point (an open account: no hand-over since), the peaks include
    those of the step between. Returns the ground acceleration (X, Y) at t."""
    acc = motion.energy
    v, cv, mass = exact.v, work.cv_next, structure.mass
    smooth = gap > 0.0 and acc[ACC_FRESH] == 0.0
    agx, agy = exact_motion(t, gap, smooth, structure, ground, motion, work, exact, peaks, g, 0, mass.size // 3, 0,
                            structure.column_storey.size, 0, peaks.gauges.storey.size)  # fmt: skip
    n_dof = mass.size
    p_in = 0.0
    p_damp = 0.0
    ground_mass = structure.ground_mass
    for d in range(0, n_dof, 3):
        p_in -= ground_mass[d] * (agx * v[d] + agy * v[d + 1])
    for d in range(n_dof):
        p_damp += v[d] * cv[d]
    if smooth:  # the exact step's own work (propagate), then the powers for a later trapezoid
        acc[ACC_INPUT] += acc[ACC_STEP_INPUT]
        acc[ACC_DAMPING] += acc[ACC_STEP_DAMPING]
        accumulate_energy(acc, 0.0, p_in, p_damp, 0.0)
    else:
        accumulate_energy(acc, gap, p_in, p_damp, 0.0)
    return agx, agy


@phase
def exact_motion(t, gap, smooth, structure, ground, motion, work, exact, peaks, g, f0, f1, c0, c1, g0, g1):
    """The state (u, v) reached at t by exact propagation, on the buildings whose floors are
    f0 … f1 − 1 (columns c0 … c1 − 1, force gauges g0 … g1 − 1): forces and accelerations
    (exact_state), and the peaks; if `smooth`, the `gap` s since the previous state of these
    buildings was an exact step, and the peaks include those of the step between
    (peaks_between, from what exact.kept and exact.between hold of that state). For the
    accelerations' it needs their first two rates: ȧ = −M⁻¹(K·v + C·a_rel) (the ground's own
    rate drops out: a_abs depends on u and v alone), left in rates[2], and
    ä = −M⁻¹(K·a_rel + C·ȧ_rel) with ȧ_rel = ȧ − ȧ_g, whose part without the ground's rate ȧ_g
    is left in rates[3] (rates[0], rates[1], rates[4]: K·a_rel, C·a_rel, C·ȧ; rates[5],
    rates[6] hold M⁻¹·C·e_X and M⁻¹·C·e_Y, e the floors' unit translations, which carry the
    rest: integrate.ground_rate_response). The crests peaks_between lists are valued
    exactly (settle_crests) from the motion's derivatives at t (state_series). Returns the
    ground acceleration (X, Y) at t."""
    u, a_abs, a_rel, rates = motion.u, work.a_abs, exact.a_rel, exact.rates
    mass, storey_k, bottom, top = structure.mass, structure.storey_k, structure.storey_bottom, structure.storey_top
    d0, d1 = 3 * f0, 3 * f1
    agx, agy = exact_state(t, structure, ground, motion, work, exact, g, f0, f1)
    storey_matvec_range(a_rel, storey_k, bottom, top, f0, f1, rates[0])
    damping_force_range(a_rel, rates[0], mass, structure.damping, d0, d1, rates[1])
    for d in range(d0, d1):
        rates[2, d] = -(exact.kv[d] + rates[1, d]) / mass[d]
    storey_matvec_range(rates[2], storey_k, bottom, top, f0, f1, rates[3])
    damping_force_range(rates[2], rates[3], mass, structure.damping, d0, d1, rates[4])
    for d in range(d0, d1):
        rates[3, d] = -(rates[0, d] + rates[4, d]) / mass[d]
    # the ground acceleration's rate over the step (linear within it: steps never cross a
    # record sample), which the peaks' second derivatives of the accelerations need
    sx = sy = 0.0
    if smooth:
        a0x, a0y = ground_at(t - gap, ground)
        sx = (agx - a0x) / gap
        sy = (agy - a0y) / gap
    update_peaks_range(u, a_abs, structure, work.storey_work, peaks, f0, f1, c0, c1, g0, g1)
    n_crests = peaks_between(gap, smooth, u, a_abs, sx, sy, structure, exact, work.storey_work, peaks, f0, f1, g0, g1)
    if n_crests > 0:
        crest = exact.crest
        state_series(u, exact.v, a_rel, sx, sy, structure, crest.series, crest.series_k, f0, f1)
        settle_crests(gap, n_crests, agx, agy, sx, sy, structure, crest, peaks)
    return agx, agy


@kernel(**INTERNAL)
def state_series(u, v, a_rel, sx, sy, structure, series, series_k, f0, f1):
    """The exact motion's derivatives at a state reached by exact propagation, on the floors
    f0 … f1 − 1: series[j] = u⁽ʲ⁾ for j = 0 … R − 1 (R = series.shape[0]), from u, v, a_rel and
    the ground acceleration's rate (sx, sy) m/s³ over the step: u⁽ʲ⁺²⁾ = −M⁻¹(K·u⁽ʲ⁾ + C·u⁽ʲ⁺¹⁾)
    − ι·a_g⁽ʲ⁾ for j ≥ 1, where a_g⁽ʲ⁾ is the rate for j = 1 and 0 after (a_g is linear within
    the step; the members' plastic correction is constant and drops out). series_k: work
    (2, n_dof + 3)."""
    mass, storey_k, bottom, top = structure.mass, structure.storey_k, structure.storey_bottom, structure.storey_top
    n_dof = mass.size
    d0, d1 = 3 * f0, 3 * f1
    for d in range(d0, d1):
        series[0, d] = u[d]
        series[1, d] = v[d]
        series[2, d] = a_rel[d]
    storey_matvec_range(series[1], storey_k, bottom, top, f0, f1, series_k[1])
    for j in range(1, series.shape[0] - 2):
        # series_k[(j + 1) % 2] = K·u⁽ʲ⁺¹⁾; series_k[j % 2] holds K·u⁽ʲ⁾ from the last order
        storey_matvec_range(series[j + 1], storey_k, bottom, top, f0, f1, series_k[(j + 1) % 2])
        damping_force_range(series[j + 1], series_k[(j + 1) % 2], mass, structure.damping, d0, d1, series[j + 2])
        for d in range(d0, d1):
            series[j + 2, d] = -(series_k[j % 2, d] + series[j + 2, d]) / mass[d]
        for d in range(n_dof, series.shape[1]):  # the ground's row (damping links may write it)
            series[j + 2, d] = 0.0
        if j == 1:
            for d in range(d0, d1, 3):
                series[3, d] -= structure.influence[d] * sx
                series[3, d + 1] -= structure.influence[d + 1] * sy


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def propagate(t, h, u, v, phi, g0, g1, mean_rows, damping_form, blocks, n_blocks, dof_start, dof_count, mass, ground, x,
              y, acc):  # fmt: skip
    """(u, v) at t + h from (u, v) at t, exactly, for the buildings blocks[0 … n_blocks − 1]
    one by one, and their exact work
    over the step of the ground, into acc[ACC_STEP_INPUT], and of the damping, into
    acc[ACC_STEP_DAMPING], J (propagator.py: from z₀ = (u, v, a₀, Δa), the mean rows r and the
    damping form G of each building). mass: M·ι, the masses the ground drives (the translations
    S = ιᵀ·M·u). x (2·n_max + 4), y (2·n_max): scratch."""
    a0x, a0y = ground_at(t, ground)
    a1x, a1y = ground_at(t + h, ground)
    dx = a1x - a0x
    dy = a1y - a0y
    w_in = 0.0
    w_damp = 0.0
    for k in range(n_blocks):
        b = blocks[k]
        d0 = dof_start[b]
        n = dof_count[b]
        for i in range(n):
            x[i] = u[d0 + i]
            x[n + i] = v[d0 + i]
        x[2 * n] = a0x
        x[2 * n + 1] = a0y
        x[2 * n + 2] = dx
        x[2 * n + 3] = dy
        # the damping's work z₀ᵀ·G·z₀ (G symmetric: the upper triangle, twice) and the means
        # S̄ of the mass-weighted translations over the step
        mean_x = 0.0
        mean_y = 0.0
        for i in range(2 * n + 4):
            row = 0.5 * damping_form[b, i, i] * x[i]
            for j in range(i + 1, 2 * n + 4):
                row += damping_form[b, i, j] * x[j]
            w_damp += 2.0 * x[i] * row
            mean_x += mean_rows[b, 0, i] * x[i]
            mean_y += mean_rows[b, 1, i] * x[i]
        s0x = 0.0
        s0y = 0.0
        for i in range(0, n, 3):
            s0x += mass[d0 + i] * x[i]
            s0y += mass[d0 + i + 1] * x[i + 1]
        for i in range(2 * n):
            acc_i = g0[b, i, 0] * a0x + g0[b, i, 1] * a0y + g1[b, i, 0] * dx + g1[b, i, 1] * dy
            for j in range(2 * n):
                acc_i += phi[b, i, j] * x[j]
            y[i] = acc_i
        s1x = 0.0
        s1y = 0.0
        for i in range(0, n, 3):
            s1x += mass[d0 + i] * y[i]
            s1y += mass[d0 + i + 1] * y[i + 1]
        w_in -= a0x * (s1x - s0x) + dx * (s1x - mean_x) + a0y * (s1y - s0y) + dy * (s1y - mean_y)
        for i in range(n):
            u[d0 + i] = y[i]
            v[d0 + i] = y[n + i]
    acc[ACC_STEP_INPUT] = w_in
    acc[ACC_STEP_DAMPING] = w_damp


@kernel(**INTERNAL)
def propagate_elastic(t, h, phi, g0, g1, mean_rows, damping_form, structure, ground, exact, motion, has_members):
    """propagate() of every building's exact state (motion.u, exact.v) over h about the static
    offset exact.u_static of the members' plastic deflections (the work is the same: the offset
    is constant), with the propagator (phi, g0, g1, mean_rows, damping_form) of that step."""
    u, u_static = motion.u, exact.u_static
    if has_members:
        for d in range(u_static.size):
            u[d] -= u_static[d]
    propagate(t, h, u, exact.v, phi, g0, g1, mean_rows, damping_form, structure.buildings, structure.buildings.size,
              structure.dof_start, structure.dof_count, structure.ground_mass, ground, exact.x, exact.y,
              motion.energy)  # fmt: skip
    if has_members:
        for d in range(u_static.size):
            u[d] += u_static[d]


@kernel(**INTERNAL)
def enter_cdm(step, structure, exact, motion, work, f0, f1):
    """Hand the exact state of the floors f0 … f1 − 1 at an instant already accounted for to the
    CDM at `step` s: v_{−½} = v − (Δt/2)·a (no contact force: none is possible yet),
    C·v_{−½}."""
    mass, v_half, dv, a_rel = structure.mass, motion.v_half, work.dv, exact.a_rel
    d0, d1 = 3 * f0, 3 * f1
    for d in range(d0, d1):
        v_half[d] = exact.v[d] - 0.5 * step * a_rel[d]
        dv[d] = step * a_rel[d]
    storey_matvec_range(v_half, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, work.z)
    damping_force_range(v_half, work.z, mass, structure.damping, d0, d1, motion.cv_half)


@kernel(**INTERNAL)
def leave_cdm(t, step, structure, ground, propagators, exact, motion, work, yielding, awake):
    """Hand the CDM's state at t of the awake buildings (records.Awake; all of them unless
    some sleep) back to the exact propagation (cdm_state_at), the energy account closed up to
    t_n; with yielding members, their static offset u_static = K⁻¹·g for their plastic
    deflections."""
    if yielding.plastic.shape[0] > 0:
        plastic_correction(yielding.law, yielding.plastic, yielding.g)
        solve_listed(propagators.k_inverse, structure.dof_start, structure.dof_count, structure.dof_count, structure.buildings,
                     structure.buildings.size, yielding.g, exact.u_static)  # fmt: skip
    agx, agy = ground_at(t, ground)
    runs = awake.runs
    p_in = 0.0
    p_damp = 0.0
    for i in range(awake.n_runs[0]):
        pi, pd = cdm_state_at(agx, agy, step, structure, motion, work, exact, yielding.g, runs[i, 0], runs[i, 1],
                              runs[i, 6], runs[i, 7])  # fmt: skip
        p_in += pi
        p_damp += pd
    accumulate_energy(motion.energy, step.dt, p_in, p_damp, 0.0)
    motion.energy[ACC_FRESH] = 1.0  # t_n is integrated; the exact loop starts from here


@kernel(**INTERNAL)
def cdm_state_at(agx, agy, step, structure, motion, work, exact, g, f0, f1, b0, b1):
    """The exact branch's state of the CDM's at t_n, on the floors f0 … f1 − 1 of the buildings
    b0 … b1 − 1: v_n = v_{n−½} + Δv_n/2 into exact.v (Δv_n from one more residual, with no
    contact force), K·u_n afresh, K·v_n and C·v_n. Returns the input and damping power at t_n
    (W) of those buildings, in the order the whole structure's always summed them."""
    mass, u, ku, r, dv = structure.mass, motion.u, motion.ku, work.r, work.dv
    v_half, cv_half, v_exact, cv = motion.v_half, motion.cv_half, exact.v, work.cv_next
    d0, d1 = 3 * f0, 3 * f1
    storey_matvec_range(u, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, ku)
    for d in range(d0, d1, 3):
        r[d] = -structure.ground_mass[d] * agx - ku[d] + g[d] - cv_half[d]
        r[d + 1] = -structure.ground_mass[d + 1] * agy - ku[d + 1] + g[d + 1] - cv_half[d + 1]
        r[d + 2] = -ku[d + 2] + g[d + 2] - cv_half[d + 2]
    solve_listed(step.inverse, structure.dof_start, structure.dof_count, structure.dof_real, structure.buildings[b0:],
                 b1 - b0, r, dv)
    for d in range(d0, d1):
        v_exact[d] = v_half[d] + 0.5 * dv[d]
    storey_matvec_range(v_exact, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, exact.kv)
    damping_force_range(v_exact, exact.kv, mass, structure.damping, d0, d1, cv)
    p_in = 0.0
    p_damp = 0.0
    for d in range(d0, d1, 3):
        p_in -= structure.ground_mass[d] * (agx * v_exact[d] + agy * v_exact[d + 1])
    for d in range(d0, d1):
        p_damp += v_exact[d] * cv[d]
    return p_in, p_damp
