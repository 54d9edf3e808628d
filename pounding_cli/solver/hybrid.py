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

from .cdm import ACC_FRESH, ACC_HYSTERETIC, STATUS_DIVERGED, STATUS_OK, advance, write_output
from .exact import enter_cdm, exact_point, leave_cdm, propagate_elastic
from .hysteresis import member_states, plastic_energy_terms, update_members, yield_possible_within
from .jit import kernel, phase
from .sleep import catch_up, enter_awake, rebalance, still_needed, wake_all
from .step_levels import finest_step_changing, level_step
from .storey_bodies import finest_level_within, possible_within, ruled_out_within
from .tunables import DIVERGENCE_LIMIT, ENTER_HORIZON, LEAVE_HORIZON

# what the next substep does: exact (substeps of h); CDM at the contact step; CDM at the
# yielding step; exact in finer steps toward a contact that may begin within the substep
MODE_EXACT, MODE_CDM, MODE_CDM_YIELD, MODE_APPROACH = 0, 1, 2, 3
# counters: exact steps (substeps and the approach's shorter ones), CDM steps, hand-overs, the
# step (in CDM steps at the contact step) whose state failed the divergence check (−1 while
# none has), the time propagated exactly, in CDM steps, the CDM steps that sleeping buildings
# did not take (summed over them), how often a building fell asleep and how often one woke
# inside a contact phase (sleep.py), how often a contact phase changed its step (step_levels.py)
CNT_EXACT, CNT_CDM, CNT_SWITCHES, CNT_FAILED_STEP, CNT_EXACT_SPAN, CNT_SLEPT, CNT_SLEEPS, CNT_WAKES = range(8)
CNT_STEP_CHANGES = 8
N_COUNTERS = 9
N_RATES = 7  # rows of exact_point's `rates`


@kernel
def hybrid_advance(k_start, k_stop, grid, structure, ground, contact_step, phase_steps, yield_step, propagators, exact,
                   motion, work, peaks, out, contact, yielding, progress, awake):  # fmt: skip
    """Advance substeps k_start … k_stop − 1 (grid: records.Substeps; phase_steps: the contact
    phases' steps, records.ContactLevels, contact_step its level 0); returns (status,
    substeps done). A displacement that passes DIVERGENCE_LIMIT or is not finite stops the
    run at the substep (or the CDM step) that made it: STATUS_DIVERGED, with that step (in CDM
    steps at the contact step) in progress.counters[CNT_FAILED_STEP]. Where awake.enabled, the
    buildings that cannot touch sleep through the contact phases (sleep.py). At k = grid.end, the
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
            _hand_over_from_exact(contact_soon, may_yield, levels, contact_step, phase_steps, yield_step, structure,
                                  exact, motion, work, progress, awake)  # fmt: skip
        if mode[0] == MODE_CDM_YIELD or levels == 0 or k == grid.end:
            # the CDM through the whole substep, then whether to hand back
            step = level_step(phase_steps, phase_steps.current[0]) if mode[0] == MODE_CDM else yield_step
            status = _cdm_substep(k, grid, step, contact_step, structure, ground, propagators, exact, motion, work,
                                  peaks, out, contact, yielding, progress, awake)  # fmt: skip
            if status != STATUS_OK:
                return status, k
            if k == grid.end:
                return STATUS_OK, k + 1
            continue
        # within the substep, finest step by finest step: exact approach steps, or the CDM
        status, done = _within_substep(k, grid, contact_step, phase_steps, structure, ground, propagators, exact, motion,
                                       work, peaks, out, contact, yielding, progress, awake)  # fmt: skip
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
def _hand_over_from_exact(contact_soon, may_yield, levels, contact_step, phase_steps, yield_step, structure, exact,
                          motion, work, progress, awake):  # fmt: skip
    """Something may happen within the horizon: approach a contact by finer exact steps (where
    there are levels and no member may yield), or hand the exact state at t_k to the CDM, at
    the contact step (level 0 of phase_steps) or at the yielding step."""
    if contact_soon and levels > 0 and not may_yield:
        progress.mode[0] = MODE_APPROACH
        return
    progress.mode[0] = MODE_CDM if contact_soon else MODE_CDM_YIELD
    phase_steps.current[0] = 0
    _enter_cdm(contact_step.dt if contact_soon else yield_step.dt, structure, exact, motion, work, awake)
    progress.counters[CNT_SWITCHES] += 1


@phase
def _enter_cdm(step, structure, exact, motion, work, awake):
    """Hand the exact state of the awake buildings at an instant already accounted for to the
    CDM at `step` s (exact.enter_cdm)."""
    runs = awake.runs
    for i in range(awake.n_runs[0]):
        enter_cdm(step, structure, exact, motion, work, runs[i, 0], runs[i, 1])
    motion.energy[ACC_FRESH] = 1.0  # the instant is already integrated


@phase
def _cdm_substep(k, grid, step, contact_step, structure, ground, propagators, exact, motion, work, peaks, out, contact,
                 yielding, progress, awake):  # fmt: skip
    """The CDM through the whole substep k at `step` (the contact step, or the yielding step);
    at the analysis' end, the state at t_k only. Then, unless at the end, whether to hand back
    to the exact steps: from the contact step once no contact is live or possible within
    LEAVE_HORIZON·h; from the yielding step when a contact may begin within ENTER_HORIZON·h
    (to come back at the contact step) or nothing can yield within LEAVE_HORIZON·h."""
    h = grid.h
    steps = step.per_substep
    counters = progress.counters
    last = k * steps + 1 if k == grid.end else (k + 1) * steps  # at the end: the state at t_k only
    status, failed_at = advance(k * steps, last, step, structure, ground, motion, work, peaks, out, contact, yielding,
                                awake)  # fmt: skip
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
        leave_cdm((k + 1) * h, step, structure, ground, propagators, exact, motion, work, yielding, awake)
        progress.mode[0] = MODE_EXACT
        counters[CNT_SWITCHES] += 1
    return STATUS_OK


@phase
def _within_substep(k, grid, contact_step, phase_steps, structure, ground, propagators, exact, motion, work, peaks, out,
                    contact, yielding, progress, awake):  # fmt: skip
    """Substep k finest step (h/2^L) by finest step: exact steps toward a contact (MODE_APPROACH),
    halving while a contact may begin within ENTER_HORIZON of their length and handing to the
    CDM at the finest level, at the step of the pairs that may touch (phase_steps, step_levels.py);
    or the CDM (MODE_CDM), which changes its step at a finest step's start when those pairs
    change, and hands back at the first finest step at which no contact is live or possible
    within LEAVE_HORIZON of it. Returns (status, substeps done: k + 1 when a displacement
    diverged in an exact step, k when the CDM failed)."""
    levels = propagators.levels.phi.shape[0] - 1
    fine = 1 << levels  # finest exact steps per substep
    q0 = contact_step.per_substep // fine  # CDM steps at the contact step per finest exact step
    coarsest = phase_steps.dt.size - 1
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
                if awake.enabled:  # who sleeps until the substep's end
                    counters[CNT_SLEEPS] += enter_awake(t_pos, max(LEAVE_HORIZON, ENTER_HORIZON * (fine - pos)) * h_fine,
                                                        structure, motion, work, exact, contact, awake)  # fmt: skip
                current = 0
                if coarsest > 0:
                    current = finest_level_within(ENTER_HORIZON * size * h_fine, u, v_exact, a_rel, contact,
                                                  phase_steps.pair_level, coarsest)  # fmt: skip
                phase_steps.current[0] = current
                _enter_cdm(phase_steps.dt[current], structure, exact, motion, work, awake)
                counters[CNT_SWITCHES] += 1
                continue
            propagate_elastic(t_pos, size * h_fine, lev.phi[level], lev.g0[level], lev.g1[level],
                              lev.mean_rows[level], lev.damping_form[level], structure, ground, exact, motion,
                              has_members)  # fmt: skip
            counters[CNT_EXACT] += 1
            counters[CNT_EXACT_SPAN] += size * q0
            pos += size
            exact.gap[0] = size * h_fine
            for d in range(structure.mass.size):
                if not abs(u[d]) <= DIVERGENCE_LIMIT:
                    counters[CNT_FAILED_STEP] = k * contact_step.per_substep + pos * q0
                    return STATUS_DIVERGED, k + 1
            if pos == fine:
                mode[0] = MODE_EXACT  # the state at t_{k+1} is the exact branch's
                break
            exact_point(t + pos * h_fine, exact.gap[0], structure, ground, motion, work, exact, peaks, yielding.g)
            if level > 1 and pos % (2 * size) == 0:
                level -= 1  # try the coarser step: the next pass checks it
            continue
        # MODE_CDM: the next finest step's worth of CDM steps (of the awake buildings; the
        # sleeping ones exactly, sleep.py), at the step of the pairs that may touch
        current = phase_steps.current[0]
        step = level_step(phase_steps, current)
        want = current
        if coarsest > 0:  # finer at once; coarser once the finer pairs are ruled out for longer
            want = finest_level_within(ENTER_HORIZON * h_fine, u, v_half, a_rel, contact, phase_steps.pair_level,
                                       coarsest)  # fmt: skip
            if want > current:
                want = finest_level_within(LEAVE_HORIZON * h_fine, u, v_half, a_rel, contact, phase_steps.pair_level,
                                           coarsest)  # fmt: skip
        if want == current:
            q = step.per_substep // fine
            n0 = (k * fine + pos) * q
            status, failed_at = advance(n0, n0 + q, step, structure, ground, motion, work, peaks, out, contact,
                                        yielding, awake)  # fmt: skip
        else:
            new = level_step(phase_steps, want)
            q = new.per_substep // fine
            status, failed_at = finest_step_changing((k * fine + pos) * (step.per_substep // fine), step, new,
                                                     (k * fine + pos) * q, q, structure, ground, motion, work, peaks,
                                                     out, contact, yielding, awake, phase_steps.saved)  # fmt: skip
            step = new
            phase_steps.current[0] = want
            counters[CNT_STEP_CHANGES] += 1
        if status != STATUS_OK:
            counters[CNT_FAILED_STEP] = failed_at * contact_step.per_substep // step.per_substep
            return status, k
        counters[CNT_CDM] += q
        pos += 1
        t_pos = t + pos * h_fine
        runs = awake.runs
        for i in range(awake.n_runs[0]):
            for d in range(3 * runs[i, 0], 3 * runs[i, 1]):
                a_rel[d] = work.dv[d] / step.dt  # the CDM's acceleration at the last step
        if awake.enabled:
            stay = still_needed(LEAVE_HORIZON * h_fine, motion, exact, contact, awake) != 0 or contact.broad.n_live[0] > 0
            if stay and pos < fine:
                continue
            counters[CNT_SLEPT] += catch_up(t_pos, h_fine, lev, structure, ground, motion, work, exact, peaks, awake,
                                            yielding.g) * q  # fmt: skip
            if stay:  # at the substep's end: who sleeps through the next one
                naps, wakes = rebalance(t_pos, ENTER_HORIZON * grid.h, step, structure, ground, motion, work, exact,
                                        peaks, contact, awake, yielding.g)  # fmt: skip
                counters[CNT_SLEEPS] += naps
                counters[CNT_WAKES] += wakes
                continue
        elif contact.broad.n_live[0] > 0 or not ruled_out_within(LEAVE_HORIZON * h_fine, u, v_half, a_rel, contact):
            continue
        if pos < fine and has_members and yield_possible_within(LEAVE_HORIZON * grid.h, u, v_half, a_rel,
                                                                yielding.law, yielding.plastic):  # fmt: skip
            continue  # members may yield: the exact branch decides at the substep's end
        leave_cdm(t_pos, step, structure, ground, propagators, exact, motion, work, yielding, awake)
        wake_all(awake, contact)
        counters[CNT_SWITCHES] += 1
        if pos == fine:
            mode[0] = MODE_EXACT
            break
        mode[0] = MODE_APPROACH
        level = levels
        exact_point(t_pos, 0.0, structure, ground, motion, work, exact, peaks, yielding.g)
    return STATUS_OK, k + 1
