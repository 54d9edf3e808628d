"""The hybrid integrator: exact steps while nothing can touch or yield, the central difference
method (CDM) around impacts and yield events.

A substep h divides the record's sample interval, so the ground acceleration is linear
within it. What a substep does depends on what may happen within its horizon:

- nothing can touch or yield within 2h: it is taken exactly (propagate: the state-transition
  matrices of propagator.py, with the exact work of the ground and the damping over it; the
  peaks between two exact states are exact too, peaks.py). Where nothing can within 2·2h and
  no sample falls inside, two substeps are taken as one (Φ of 2h);
- a contact may begin within 2h: the exact steps halve, h/2, h/4, … h/2^L (the approach
  levels), while the outlines could touch within two of them, and hand the state to the CDM
  at the contact step Δt only at the finest level; the CDM hands it back at the first h/2^L
  at which every contact is over and none can begin within 4·h/2^L;
- only a member may yield within 2h: the CDM runs through the substep at the yielding step
  (the structure's own fraction of its stability limit), and hands back at a substep
  boundary when a contact may begin (to re-enter at the contact step) or nothing can yield
  within 4h.

Hand-overs (second-order consistent): exact → CDM at t_k: v_{k−½} = v_k − (Δt/2)·a_k, a_k
from the equation of motion (no contact force: none is possible yet); CDM → exact at t_n:
v_n = v_{n−½} + Δv_n/2, Δv_n from one more CDM residual. A change of CDM step goes through
the exact state at a substep boundary: the two hand-overs back to back. Energy keeps one
account across both: each hand-over closes the interval it ends and marks the instant as
counted; exact steps add their exact work, the CDM the trapezoidal rule's.

The horizons and the sampling are tunables (tunables.py: ENTER_HORIZON, LEAVE_HORIZON,
HYBRID_SAMPLING, YIELD_SAMPLING); the arguments are the records of records.py.
"""

from __future__ import annotations

from .cdm import (
    ACC_DAMPING,
    ACC_FRESH,
    ACC_HYSTERETIC,
    ACC_INPUT,
    ACC_STEP_DAMPING,
    ACC_STEP_INPUT,
    STATUS_DIVERGED,
    STATUS_OK,
    accumulate_energy,
    advance,
    damping_force,
    ground_at,
    solve_blocks,
    storey_matvec,
    storey_matvec_pair,
    write_output,
)
from .storey_bodies import possible_within, ruled_out_within
from .hysteresis import member_states, plastic_correction, plastic_energy_terms, update_members, yield_possible_within
from .jit import INTERNAL, REASSOCIATE, kernel, phase
from .peaks import peaks_between, settle_crests, update_peaks
from .tunables import DIVERGENCE_LIMIT, ENTER_HORIZON, LEAVE_HORIZON

# what the next substep does: exact (substeps of h); CDM at the contact step; CDM at the
# yielding step; exact in finer steps toward a contact that may begin within the substep
MODE_EXACT, MODE_CDM, MODE_CDM_YIELD, MODE_APPROACH = 0, 1, 2, 3
# counters: exact steps (substeps and the approach's shorter ones), CDM steps, hand-overs, the
# step (in CDM steps at the contact step) whose state failed the divergence check (−1 while
# none has), and the time propagated exactly, in CDM steps
CNT_EXACT, CNT_CDM, CNT_SWITCHES, CNT_FAILED_STEP, CNT_EXACT_SPAN = range(5)
N_COUNTERS = 5
N_RATES = 7  # rows of exact_point's `rates`


@kernel
def hybrid_advance(k_start, k_stop, grid, structure, ground, contact_step, yield_step, propagators, exact, motion,
                   work, peaks, out, contact, yielding, progress):  # fmt: skip
    """Advance substeps k_start … k_stop − 1 (grid: records.Substeps); returns (status,
    substeps done). A displacement that passes DIVERGENCE_LIMIT or is not finite stops the
    run at the substep (or the CDM step) that made it: STATUS_DIVERGED, with that step (in CDM
    steps at the contact step) in progress.counters[CNT_FAILED_STEP]. At k = grid.end, the
    end of the analysis, only the state at t_k is taken (output, peaks): nothing is
    integrated past it.

    Each substep, by the mode the last one left (progress.mode):
    1. exact: the state at t_k (members, forces, energy, peaks, output); then, by what may
       happen within the horizon, one or two exact substeps, or a hand-over;
    2. CDM through the whole substep (at the yielding step, or where there are no approach
       levels, or at the end), and whether to hand back;
    3. within the substep, finest step by finest step: exact approach steps, or the CDM."""
    levels = propagators.levels.phi.shape[0] - 1
    mode = progress.mode
    counters = progress.counters
    skip = False  # the last substep was a double one: this k is already passed
    for k in range(k_start, k_stop):
        if skip:
            skip = False
            continue
        if mode[0] == MODE_EXACT:
            # the exact state at t_k: members, forces, energy, peaks, output
            status, yielded = _state_at_substep(k, grid, structure, ground, exact, motion, work, peaks, out, contact,
                                                yielding)  # fmt: skip
            if status != STATUS_OK:
                counters[CNT_FAILED_STEP] = k * contact_step.per_substep
                return status, k
            if k == grid.end:
                return STATUS_OK, k + 1
            # nothing can touch or yield within the horizon: one or two exact substeps
            span, contact_soon, may_yield = _free_span(k, k_stop, yielded, grid, propagators, exact, motion, contact,
                                                       yielding)  # fmt: skip
            if span > 0:
                if not _propagate_free(k, span, grid, contact_step, structure, ground, propagators, exact, motion,
                                       yielding, counters):  # fmt: skip
                    return STATUS_DIVERGED, k + span
                skip = span == 2
                continue
            # something may: approach by finer exact steps, or hand over to the CDM
            _hand_over_from_exact(contact_soon, may_yield, levels, contact_step, yield_step, structure, exact, motion,
                                  work, progress)  # fmt: skip
        if mode[0] == MODE_CDM_YIELD or levels == 0 or k == grid.end:
            # the CDM through the whole substep, then whether to hand back
            step = contact_step if mode[0] == MODE_CDM else yield_step
            status = _cdm_substep(k, grid, step, contact_step, structure, ground, propagators, exact, motion, work,
                                  peaks, out, contact, yielding, progress)  # fmt: skip
            if status != STATUS_OK:
                return status, k
            if k == grid.end:
                return STATUS_OK, k + 1
            continue
        # within the substep, finest step by finest step: exact approach steps, or the CDM
        status, done = _within_substep(k, grid, contact_step, structure, ground, propagators, exact, motion, work,
                                       peaks, out, contact, yielding, progress)  # fmt: skip
        if status != STATUS_OK:
            return status, done
    return STATUS_OK, k_stop


@phase
def _state_at_substep(k, grid, structure, ground, exact, motion, work, peaks, out, contact, yielding):
    """The exact state at t_k: the members' return map (elastic unless the last substep
    overshot the yield surface), forces, accelerations, energy and peaks (exact_point), the
    members' states, and the output at an output substep. Returns (status, members that
    yielded)."""
    yielded = 0
    has_members = yielding.plastic.shape[0] > 0
    if has_members:
        dissipated, yielded = update_members(motion.u, yielding.law, yielding.plastic, yielding.g)
        motion.energy[ACC_HYSTERETIC] += dissipated
    agx, agy = exact_point(k * grid.h, exact.gap[0], structure, ground, motion, work, exact, peaks, yielding.g)
    output = k % grid.per_output == 0
    e_plastic = 0.0
    if has_members:
        member_states(motion.u, yielding.law, yielding.plastic, k // grid.per_output if output else -1,
                      yielding.history, yielding.peak)  # fmt: skip
        e_plastic = plastic_energy_terms(motion.u, yielding.g, yielding.law, yielding.plastic)
    if output:
        return write_output(k // grid.per_output, motion.u, exact.v, work.a_abs, motion.ku, agx, agy,
                            structure.mass, motion.energy, contact.now, contact.force, out, e_plastic), yielded  # fmt: skip
    return STATUS_OK, yielded


@phase
def _free_span(k, k_stop, yielded, grid, propagators, exact, motion, contact, yielding):
    """How many substeps from t_k can be taken exactly at once: 2 where two fit (a propagator
    of 2h exists, no output sample, record sample, call's end or the analysis' end falls
    inside them) and nothing can touch or yield within ENTER_HORIZON·2h; else 1 where nothing
    can within ENTER_HORIZON·h; else 0. Returns (span, a contact may begin, a member may
    yield)."""
    h = grid.h
    has_pairs = contact.law.a.size > 0
    has_members = yielding.plastic.shape[0] > 0
    u, v, a_rel = motion.u, exact.v, exact.a_rel
    double = (propagators.double.phi.shape[0] > 0 and k + 2 <= min(k_stop, grid.end) and (k + 1) % grid.per_output != 0
              and (k + 1) % grid.per_record != 0 and yielded == 0
              and not (has_pairs and possible_within(ENTER_HORIZON * 2.0 * h, u, v, a_rel, contact))
              and not (has_members and yield_possible_within(ENTER_HORIZON * 2.0 * h, u, v, a_rel, yielding.law,
                                                             yielding.plastic)))  # fmt: skip
    if double:
        return 2, False, False
    contact_soon = has_pairs and possible_within(ENTER_HORIZON * h, u, v, a_rel, contact)
    may_yield = has_members and (yielded > 0 or yield_possible_within(ENTER_HORIZON * h, u, v, a_rel, yielding.law,
                                                                      yielding.plastic))  # fmt: skip
    return (0 if contact_soon or may_yield else 1), contact_soon, may_yield


@phase
def _propagate_free(k, span, grid, contact_step, structure, ground, propagators, exact, motion, yielding, counters):
    """Take `span` (1 or 2) substeps from t_k exactly. False when a displacement passes
    DIVERGENCE_LIMIT or is not finite (the run stops at the substep that made it: a non-finite
    velocity makes the displacement so within the same substep, propagate mixes them)."""
    h = grid.h
    has_members = yielding.plastic.shape[0] > 0
    if span == 2:
        p = propagators.double
        propagate_elastic(k * h, 2.0 * h, p.phi, p.g0, p.g1, p.mean_rows, p.damping_form, structure, ground, exact,
                          motion, has_members)  # fmt: skip
    else:
        p = propagators.levels
        propagate_elastic(k * h, h, p.phi[0], p.g0[0], p.g1[0], p.mean_rows[0], p.damping_form[0], structure, ground,
                          exact, motion, has_members)  # fmt: skip
    exact.gap[0] = span * h
    counters[CNT_EXACT] += 1
    counters[CNT_EXACT_SPAN] += span * contact_step.per_substep
    u = motion.u
    for d in range(structure.mass.size):
        if not abs(u[d]) <= DIVERGENCE_LIMIT:
            counters[CNT_FAILED_STEP] = (k + span) * contact_step.per_substep
            return False
    return True


@phase
def _hand_over_from_exact(contact_soon, may_yield, levels, contact_step, yield_step, structure, exact, motion, work,
                          progress):  # fmt: skip
    """Something may happen within the horizon: approach a contact by finer exact steps (where
    there are levels and no member may yield), or hand the exact state at t_k to the CDM, at
    the contact step or at the yielding step."""
    if contact_soon and levels > 0 and not may_yield:
        progress.mode[0] = MODE_APPROACH
        return
    progress.mode[0] = MODE_CDM if contact_soon else MODE_CDM_YIELD
    _enter_cdm(contact_step.dt if contact_soon else yield_step.dt, structure, exact, motion, work)
    progress.counters[CNT_SWITCHES] += 1


@phase
def _cdm_substep(k, grid, step, contact_step, structure, ground, propagators, exact, motion, work, peaks, out, contact,
                 yielding, progress):  # fmt: skip
    """The CDM through the whole substep k at `step` (the contact step, or the yielding step);
    at the analysis' end, the state at t_k only. Then, unless at the end, whether to hand back
    to the exact steps: from the contact step once no contact is live or possible within
    LEAVE_HORIZON·h; from the yielding step when a contact may begin within ENTER_HORIZON·h
    (to come back at the contact step) or nothing can yield within LEAVE_HORIZON·h."""
    h = grid.h
    steps = step.per_substep
    counters = progress.counters
    last = k * steps + 1 if k == grid.end else (k + 1) * steps  # at the end: the state at t_k only
    status, failed_at = advance(k * steps, last, step, structure, ground, motion, work, peaks, out, contact, yielding)
    if status != STATUS_OK:
        counters[CNT_FAILED_STEP] = failed_at * contact_step.per_substep // steps  # in contact steps
        return status
    if k == grid.end:
        return STATUS_OK
    counters[CNT_CDM] += steps
    u, v_half, a_rel = motion.u, motion.v_half, exact.a_rel
    for d in range(structure.mass.size):
        a_rel[d] = work.dv[d] / step.dt  # the CDM's acceleration at the last step
    if progress.mode[0] == MODE_CDM:  # leave once no contact is possible; the exact branch then decides
        leave = contact.broad.n_live[0] == 0 and not possible_within(  # (contact_forces counts live pairs)
            LEAVE_HORIZON * h, u, v_half, a_rel, contact)  # fmt: skip
    else:  # leave when a contact may begin (to come back at the contact step) or nothing can yield
        leave = (contact.law.a.size > 0 and possible_within(ENTER_HORIZON * h, u, v_half, a_rel, contact)
                 ) or not yield_possible_within(LEAVE_HORIZON * h, u, v_half, a_rel, yielding.law,
                                                yielding.plastic)  # fmt: skip
    if leave:
        _leave_cdm((k + 1) * h, step, structure, ground, propagators, exact, motion, work, yielding)
        progress.mode[0] = MODE_EXACT
        counters[CNT_SWITCHES] += 1
    return STATUS_OK


@phase
def _within_substep(k, grid, step, structure, ground, propagators, exact, motion, work, peaks, out, contact, yielding,
                    progress):  # fmt: skip
    """Substep k finest step (h/2^L) by finest step: exact steps toward a contact (MODE_APPROACH),
    halving while a contact may begin within ENTER_HORIZON of their length and handing to the
    CDM at the contact step at the finest level; or the CDM (MODE_CDM), which hands back at the
    first finest step at which no contact is live or possible within LEAVE_HORIZON of it.
    Returns (status, substeps done: k + 1 when a displacement diverged in an exact step, k
    when the CDM failed)."""
    levels = propagators.levels.phi.shape[0] - 1
    fine = 1 << levels  # finest exact steps per substep
    q = step.per_substep // fine  # CDM steps per finest exact step
    h_fine = grid.h / fine
    t = k * grid.h
    has_members = yielding.plastic.shape[0] > 0
    mode = progress.mode
    counters = progress.counters
    u, v_exact, a_rel, v_half = motion.u, exact.v, exact.a_rel, motion.v_half
    lev = propagators.levels
    pos = 0  # finest exact steps done in this substep
    level = 1
    while pos < fine:
        t_pos = t + pos * h_fine
        if mode[0] == MODE_APPROACH:
            size = fine >> level
            if not ruled_out_within(ENTER_HORIZON * size * h_fine, u, v_exact, a_rel, contact):
                if level < levels:
                    level += 1
                    continue
                mode[0] = MODE_CDM
                _enter_cdm(step.dt, structure, exact, motion, work)
                counters[CNT_SWITCHES] += 1
                continue
            propagate_elastic(t_pos, size * h_fine, lev.phi[level], lev.g0[level], lev.g1[level],
                              lev.mean_rows[level], lev.damping_form[level], structure, ground, exact, motion,
                              has_members)  # fmt: skip
            counters[CNT_EXACT] += 1
            counters[CNT_EXACT_SPAN] += size * q
            pos += size
            exact.gap[0] = size * h_fine
            for d in range(structure.mass.size):
                if not abs(u[d]) <= DIVERGENCE_LIMIT:
                    counters[CNT_FAILED_STEP] = k * step.per_substep + pos * q
                    return STATUS_DIVERGED, k + 1
            if pos == fine:
                mode[0] = MODE_EXACT  # the state at t_{k+1} is the exact branch's
                break
            exact_point(t + pos * h_fine, exact.gap[0], structure, ground, motion, work, exact, peaks, yielding.g)
            if level > 1 and pos % (2 * size) == 0:
                level -= 1  # try the coarser step: the next pass checks it
            continue
        # MODE_CDM: the next finest step's worth of CDM steps
        n0 = k * step.per_substep + pos * q
        status, failed_at = advance(n0, n0 + q, step, structure, ground, motion, work, peaks, out, contact, yielding)
        if status != STATUS_OK:
            counters[CNT_FAILED_STEP] = failed_at
            return status, k
        counters[CNT_CDM] += q
        pos += 1
        for d in range(structure.mass.size):
            a_rel[d] = work.dv[d] / step.dt  # the CDM's acceleration at the last step
        if contact.broad.n_live[0] > 0 or not ruled_out_within(LEAVE_HORIZON * h_fine, u, v_half, a_rel,
                                                                       contact):  # fmt: skip
            continue
        if pos < fine and has_members and yield_possible_within(LEAVE_HORIZON * grid.h, u, v_half, a_rel,
                                                                yielding.law, yielding.plastic):  # fmt: skip
            continue  # members may yield: the exact branch decides at the substep's end
        t_pos = t + pos * h_fine
        _leave_cdm(t_pos, step, structure, ground, propagators, exact, motion, work, yielding)
        counters[CNT_SWITCHES] += 1
        if pos == fine:
            mode[0] = MODE_EXACT
            break
        mode[0] = MODE_APPROACH
        level = levels
        exact_point(t_pos, 0.0, structure, ground, motion, work, exact, peaks, yielding.g)
    return STATUS_OK, k + 1


@kernel(**INTERNAL)
def exact_state(t, structure, ground, motion, work, exact, g):
    """K·u, C·v and the accelerations (absolute into work.a_abs, relative into exact.a_rel) at
    time t from the exact state (motion.u, exact.v) and the members' plastic correction g.
    Returns the ground acceleration (X, Y) at t."""
    u, v, ku, kv, cv, a_abs, a_rel = motion.u, exact.v, motion.ku, exact.kv, work.cv_next, work.a_abs, exact.a_rel
    mass = structure.mass
    agx, agy = ground_at(t, ground)
    n_dof = mass.size
    storey_matvec_pair(u, v, structure.storey_k, structure.storey_bottom, structure.storey_top, ku, kv)
    damping_force(v, kv, mass, structure.damping, n_dof, cv)
    for d in range(n_dof):
        a_abs[d] = -(ku[d] - g[d] + cv[d]) / mass[d]
    for d in range(0, n_dof, 3):
        a_rel[d] = a_abs[d] - agx
        a_rel[d + 1] = a_abs[d + 1] - agy
        a_rel[d + 2] = a_abs[d + 2]
    return agx, agy


@kernel(**INTERNAL)
def exact_point(t, gap, structure, ground, motion, work, exact, peaks, g):
    """Everything the exact propagation owes the state (u, v) it reached at t: forces and
    accelerations (exact_state), the energy account over the `gap` s since the last state
    accounted for (over an exact step, the work propagate left in acc[ACC_STEP_INPUT] and
    acc[ACC_STEP_DAMPING], exact; else trapezoidal), the peaks. When that last state was the
    previous exact point (an open account: no hand-over since), the peaks include those of
    the step between (peaks_between, from what exact.kept and exact.between hold of that
    state); for the accelerations' it needs their first two rates:
    ȧ = −M⁻¹(K·v + C·a_rel) (the ground's own rate drops out: a_abs depends on u and v
    alone), left in rates[2], and
    ä = −M⁻¹(K·a_rel + C·ȧ_rel) with ȧ_rel = ȧ − ȧ_g, whose part without the ground's rate ȧ_g
    is left in rates[3] (rates[0], rates[1], rates[4]: K·a_rel, C·a_rel, C·ȧ; rates[5],
    rates[6] hold M⁻¹·C·e_X and M⁻¹·C·e_Y, e the floors' unit translations, which carry the
    rest: integrate.ground_rate_response). The crests peaks_between lists are valued
    exactly (settle_crests) from the motion's derivatives at t (state_series). Returns the
    ground acceleration (X, Y) at t."""
    acc = motion.energy
    u, v, cv, a_abs, a_rel, rates = motion.u, exact.v, work.cv_next, work.a_abs, exact.a_rel, exact.rates
    mass, storey_k, bottom, top = structure.mass, structure.storey_k, structure.storey_bottom, structure.storey_top
    smooth = gap > 0.0 and acc[ACC_FRESH] == 0.0
    agx, agy = exact_state(t, structure, ground, motion, work, exact, g)
    n_dof = mass.size
    storey_matvec(a_rel, storey_k, bottom, top, rates[0])
    damping_force(a_rel, rates[0], mass, structure.damping, n_dof, rates[1])
    for d in range(n_dof):
        rates[2, d] = -(exact.kv[d] + rates[1, d]) / mass[d]
    storey_matvec(rates[2], storey_k, bottom, top, rates[3])
    damping_force(rates[2], rates[3], mass, structure.damping, n_dof, rates[4])
    for d in range(n_dof):
        rates[3, d] = -(rates[0, d] + rates[4, d]) / mass[d]
    # the ground acceleration's rate over the step (linear within it: steps never cross a
    # record sample), which the peaks' second derivatives of the accelerations need
    a0x = a0y = sx = sy = 0.0
    if smooth:
        a0x, a0y = ground_at(t - gap, ground)
        sx = (agx - a0x) / gap
        sy = (agy - a0y) / gap
    p_in = 0.0
    p_damp = 0.0
    for d in range(0, n_dof, 3):
        p_in -= mass[d] * (agx * v[d] + agy * v[d + 1])
    for d in range(n_dof):
        p_damp += v[d] * cv[d]
    if smooth:  # the exact step's own work (propagate), then the powers for a later trapezoid
        acc[ACC_INPUT] += acc[ACC_STEP_INPUT]
        acc[ACC_DAMPING] += acc[ACC_STEP_DAMPING]
        accumulate_energy(acc, 0.0, p_in, p_damp, 0.0)
    else:
        accumulate_energy(acc, gap, p_in, p_damp, 0.0)
    update_peaks(u, a_abs, structure, work.storey_work, peaks)
    n_crests = peaks_between(gap, smooth, u, a_abs, sx, sy, structure, exact, work.storey_work, peaks)
    if n_crests > 0:
        crest = exact.crest
        state_series(u, v, a_rel, sx, sy, structure, crest.series, crest.series_k)
        settle_crests(gap, n_crests, agx, agy, sx, sy, structure, crest, peaks)
    return agx, agy


@kernel(**INTERNAL)
def state_series(u, v, a_rel, sx, sy, structure, series, series_k):
    """The exact motion's derivatives at a state reached by exact propagation: series[j] =
    u⁽ʲ⁾ for j = 0 … R − 1 (R = series.shape[0]), from u, v, a_rel and the ground acceleration's
    rate (sx, sy) m/s³ over the step: u⁽ʲ⁺²⁾ = −M⁻¹(K·u⁽ʲ⁾ + C·u⁽ʲ⁺¹⁾) − ι·a_g⁽ʲ⁾ for j ≥ 1,
    where a_g⁽ʲ⁾ is the rate for j = 1 and 0 after (a_g is linear within the step; the members'
    plastic correction is constant and drops out). series_k: work (2, n_dof + 3)."""
    mass, storey_k, bottom, top = structure.mass, structure.storey_k, structure.storey_bottom, structure.storey_top
    n_dof = mass.size
    for d in range(n_dof):
        series[0, d] = u[d]
        series[1, d] = v[d]
        series[2, d] = a_rel[d]
    storey_matvec(series[1], storey_k, bottom, top, series_k[1])
    for j in range(1, series.shape[0] - 2):
        # series_k[(j + 1) % 2] = K·u⁽ʲ⁺¹⁾; series_k[j % 2] holds K·u⁽ʲ⁾ from the last order
        storey_matvec(series[j + 1], storey_k, bottom, top, series_k[(j + 1) % 2])
        damping_force(series[j + 1], series_k[(j + 1) % 2], mass, structure.damping, n_dof, series[j + 2])
        for d in range(n_dof):
            series[j + 2, d] = -(series_k[j % 2, d] + series[j + 2, d]) / mass[d]
        for d in range(n_dof, series.shape[1]):  # the ground's row (damping links may write it)
            series[j + 2, d] = 0.0
        if j == 1:
            for d in range(0, n_dof, 3):
                series[3, d] -= sx
                series[3, d + 1] -= sy


@kernel(fastmath=REASSOCIATE, **INTERNAL)
def propagate(t, h, u, v, phi, g0, g1, mean_rows, damping_form, dof_start, dof_count, mass, ground, x, y, acc):
    """(u, v) at t + h from (u, v) at t, exactly, building by building, and the exact work
    over the step of the ground, into acc[ACC_STEP_INPUT], and of the damping, into
    acc[ACC_STEP_DAMPING], J (propagator.py: from z₀ = (u, v, a₀, Δa), the mean rows r and the
    damping form G of each building). x (2·n_max + 4), y (2·n_max): scratch."""
    a0x, a0y = ground_at(t, ground)
    a1x, a1y = ground_at(t + h, ground)
    dx = a1x - a0x
    dy = a1y - a0y
    w_in = 0.0
    w_damp = 0.0
    for b in range(dof_start.size):
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
    """propagate() of the exact state (motion.u, exact.v) over h about the static offset
    exact.u_static of the members' plastic deflections (the work is the same: the offset is
    constant), with the propagator (phi, g0, g1, mean_rows, damping_form) of that step."""
    u, u_static = motion.u, exact.u_static
    if has_members:
        for d in range(u_static.size):
            u[d] -= u_static[d]
    propagate(t, h, u, exact.v, phi, g0, g1, mean_rows, damping_form, structure.dof_start, structure.dof_count,
              structure.mass, ground, exact.x, exact.y, motion.energy)  # fmt: skip
    if has_members:
        for d in range(u_static.size):
            u[d] += u_static[d]


@kernel(**INTERNAL)
def _enter_cdm(step, structure, exact, motion, work):
    """Hand the exact state at an instant already accounted for to the CDM at `step` s:
    v_{−½} = v − (Δt/2)·a (no contact force: none is possible yet), C·v_{−½}."""
    mass, v_half, dv, a_rel = structure.mass, motion.v_half, work.dv, exact.a_rel
    n_dof = mass.size
    for d in range(n_dof):
        v_half[d] = exact.v[d] - 0.5 * step * a_rel[d]
        dv[d] = step * a_rel[d]
    storey_matvec(v_half, structure.storey_k, structure.storey_bottom, structure.storey_top, work.z)
    damping_force(v_half, work.z, mass, structure.damping, n_dof, motion.cv_half)
    motion.energy[ACC_FRESH] = 1.0  # the instant is already integrated


@kernel(**INTERNAL)
def _leave_cdm(t, step, structure, ground, propagators, exact, motion, work, yielding):
    """Hand the CDM's state at t back to the exact propagation: v_n = v_{n−½} + Δv_n/2 (no
    contact force), the energy account closed up to t_n; with yielding members, their static
    offset u_static = K⁻¹·g for their plastic deflections."""
    if yielding.plastic.shape[0] > 0:
        plastic_correction(yielding.law, yielding.plastic, yielding.g)
        solve_blocks(propagators.k_inverse, structure.dof_start, structure.dof_count, yielding.g, exact.u_static)
    mass, u, ku, g, r, dv = structure.mass, motion.u, motion.ku, yielding.g, work.r, work.dv
    v_half, cv_half, v_exact, cv = motion.v_half, motion.cv_half, exact.v, work.cv_next
    n_dof = mass.size
    agx, agy = ground_at(t, ground)
    storey_matvec(u, structure.storey_k, structure.storey_bottom, structure.storey_top, ku)
    for d in range(0, n_dof, 3):
        r[d] = -mass[d] * agx - ku[d] + g[d] - cv_half[d]
        r[d + 1] = -mass[d + 1] * agy - ku[d + 1] + g[d + 1] - cv_half[d + 1]
        r[d + 2] = -ku[d + 2] + g[d + 2] - cv_half[d + 2]
    solve_blocks(step.inverse, structure.dof_start, structure.dof_count, r, dv)
    for d in range(n_dof):
        v_exact[d] = v_half[d] + 0.5 * dv[d]
    storey_matvec(v_exact, structure.storey_k, structure.storey_bottom, structure.storey_top, exact.kv)
    damping_force(v_exact, exact.kv, mass, structure.damping, n_dof, cv)
    p_in = 0.0
    p_damp = 0.0
    for d in range(0, n_dof, 3):
        p_in -= mass[d] * (agx * v_exact[d] + agy * v_exact[d + 1])
    for d in range(n_dof):
        p_damp += v_exact[d] * cv[d]
    accumulate_energy(motion.energy, step.dt, p_in, p_damp, 0.0)
    motion.energy[ACC_FRESH] = 1.0  # t_n is integrated; the exact loop starts from here
