"""Per-building stepping: while the CDM integrates a contact, the buildings that cannot touch
anything sleep, propagated exactly instead (docs/theory.md, "Buildings that sleep").

In a block of a hundred buildings, two to six are in contact at a time; the CDM at the contact
step (a few µs) would carry all of them. Buildings are coupled only by contact (their M, K
and C are block-diagonal, sleep is refused where damping links or yielding members are), so
the CDM's step of one building is the same whatever the others do, and a building none of
whose pairs can touch within the horizon can be taken apart:

- At every finest exact step h/2^L of a contact phase (where hybrid._within_substep already
  asks whether the contact is over) each building is looked at: it must be carried by the
  CDM when one of its pairs may touch within LEAVE_HORIZON·h/2^L (contact_pairs_needed, the
  test that ends the contact phase, pair by pair).
- A sleeping building is propagated exactly over each finest step (propagate, with its own
  state-transition matrix; its exact work goes to the account directly), and at the step's
  end takes its exact point (exact.exact_motion: forces, accelerations, peaks, and the crests
  between the two exact states). Its v, a and K·u are written where the CDM's output reads
  them: output instants are substep boundaries, so every building is seen at the same t.
- Falling asleep at t_b: the CDM's state hands over as at the end of a contact phase
  (v_b = v_{b−½} + Δv_b/2), and the trapezoid's last half interval of the building,
  ½Δt·P_b, is added to the account (the half at t_{b−1} is in the CDM's stored power).
- Waking at t_b: the exact state hands over as at the start of a contact phase
  (v_{b−½} = v_b − Δt/2·a_b), and the building's power at t_b is taken out of the CDM's stored
  power: its work up to t_b was counted exactly.

A scene whose buildings all stay needed runs as without it, bit for bit: the runs of awake
buildings are then one range, summed in the order the whole structure always was.
"""

from __future__ import annotations

import numpy as np

from .cdm import ACC_DAMPING, ACC_INPUT, ACC_P_DAMPING, ACC_P_INPUT, ACC_STEP_DAMPING, ACC_STEP_INPUT, ground_at
from .exact import cdm_state_at, enter_cdm, exact_motion, propagate
from .jit import INTERNAL, kernel
from .records import Awake
from .storey_bodies import needed_within


def awake_record(
    enabled: bool,
    floor_start: np.ndarray,
    column_storey: np.ndarray,
    gauge_first: np.ndarray,
    body_floor: np.ndarray,
    storey_above: np.ndarray,
) -> Awake:
    """Every building awake. floor_start (n_buildings + 1,): first floor of each building;
    column_storey: each column's storey (storey by storey); gauge_first (n_storeys + 1,): each
    storey's first force gauge; body_floor: each contact body's floor, n_floors + 1 + k for
    the virtual floor of struck storey k, whose floor above is storey_above[k], −1 for an
    obstacle (a moat wall: it belongs to no building)."""
    n_b = floor_start.size - 1
    n_floors = int(floor_start[-1])
    floor_building = np.repeat(np.arange(n_b), np.diff(floor_start))
    floor = np.asarray(body_floor, dtype=np.int64)
    above = np.asarray(storey_above, dtype=np.int64)
    floor = np.array([above[f - n_floors - 1] if f > n_floors else f for f in floor], dtype=np.int64)
    owner = np.where(floor >= 0, floor_building[np.maximum(floor, 0)], -1) if floor.size else floor  # −1: an obstacle
    column_start = np.searchsorted(column_storey, floor_start).astype(np.int64)
    gauge_start = np.asarray(gauge_first, dtype=np.int64)[floor_start]
    runs = np.zeros((max(n_b, 1), 8), dtype=np.int64)  # one run: every building (set_runs)
    runs[0] = (0, n_floors, 0, column_start[-1], 0, gauge_start[-1], 0, n_b)
    return Awake(int(enabled), np.asarray(floor_start, dtype=np.int64), column_start, gauge_start,
                 owner.astype(np.int64), np.ones(n_b, dtype=np.int64), np.ones(n_b, dtype=np.int64),
                 np.zeros(1), np.zeros(n_b, dtype=np.int64),
                 runs, np.ones(1, dtype=np.int64), np.zeros(n_b, dtype=np.int64), np.zeros(1, dtype=np.int64))


@kernel(**INTERNAL)
def set_runs(awake):
    """awake.runs and the sleepers' list from awake.flag."""
    flag, fs, cs, gs, runs = awake.flag, awake.floor_start, awake.column_start, awake.gauge_start, awake.runs
    n_b = flag.size
    n_runs = 0
    n_sleepers = 0
    b = 0
    while b < n_b:
        if flag[b] == 0:
            awake.sleepers[n_sleepers] = b
            n_sleepers += 1
            b += 1
            continue
        e = b + 1
        while e < n_b and flag[e] != 0:
            e += 1
        runs[n_runs, 0] = fs[b]
        runs[n_runs, 1] = fs[e]
        runs[n_runs, 2] = cs[b]
        runs[n_runs, 3] = cs[e]
        runs[n_runs, 4] = gs[b]
        runs[n_runs, 5] = gs[e]
        runs[n_runs, 6] = b
        runs[n_runs, 7] = e
        n_runs += 1
        b = e
    awake.n_runs[0] = n_runs
    awake.n_sleepers[0] = n_sleepers


@kernel(**INTERNAL)
def wake_all(awake, contact):
    """Every building awake, and the broad phase on its own again (the contact phase is over:
    the exact branch takes them all)."""
    contact.broad.n_phase[0] = -1
    if awake.n_sleepers[0] > 0:
        awake.flag[:] = 1
        set_runs(awake)


@kernel(**INTERNAL)
def _show_exact(b, motion, work, exact, awake):
    """A sleeping building's exact velocity where the CDM's output (work.v) and the contact
    bounds (motion.v_half) read it."""
    for d in range(3 * awake.floor_start[b], 3 * awake.floor_start[b + 1]):
        work.v[d] = exact.v[d]
        motion.v_half[d] = exact.v[d]


@kernel(**INTERNAL)
def _point(t, gap, smooth, b, structure, ground, motion, work, exact, peaks, awake, g):
    """exact_motion of building b at t (smooth: over an exact step of `gap` s from its last)."""
    fs, cs, gs = awake.floor_start, awake.column_start, awake.gauge_start
    exact_motion(t, gap, smooth, structure, ground, motion, work, exact, peaks, g, fs[b], fs[b + 1], cs[b], cs[b + 1],
                 gs[b], gs[b + 1])  # fmt: skip
    _show_exact(b, motion, work, exact, awake)


@kernel(**INTERNAL)
def enter_awake(t, horizon, structure, motion, work, exact, contact, awake):
    """At the hand-over to the CDM at an exact point at t: which buildings it carries (those
    with a pair that may touch within `horizon` s; all of them if none is found). The sleepers'
    exact velocities are shown where the CDM reads them. Returns how many sleep."""
    count = needed_within(horizon, motion.u, exact.v, exact.a_rel, contact, awake.body_building, awake.everyone,
                          awake.need, True)  # fmt: skip
    for b in range(awake.flag.size):
        awake.flag[b] = 1 if count <= 0 else awake.need[b]
    set_runs(awake)
    for i in range(awake.n_sleepers[0]):
        _show_exact(awake.sleepers[i], motion, work, exact, awake)
    awake.time[0] = t
    return awake.n_sleepers[0]


@kernel(**INTERNAL)
def _sleepers_step(t, h, lev, level, structure, ground, motion, work, exact, peaks, awake, g):
    """The sleeping buildings from t to t + h exactly (propagator level `level` of lev), their
    exact work into the account, and their exact point at t + h."""
    n = awake.n_sleepers[0]
    acc = motion.energy
    propagate(t, h, motion.u, exact.v, lev.phi[level], lev.g0[level], lev.g1[level], lev.mean_rows[level],
              lev.damping_form[level], awake.sleepers, n, structure.dof_start, structure.dof_count, structure.ground_mass,
              ground, exact.x, exact.y, acc)  # fmt: skip
    acc[ACC_INPUT] += acc[ACC_STEP_INPUT]
    acc[ACC_DAMPING] += acc[ACC_STEP_DAMPING]
    for i in range(n):
        _point(t + h, h, True, awake.sleepers[i], structure, ground, motion, work, exact, peaks, awake, g)


@kernel(**INTERNAL)
def catch_up(t, h_fine, lev, structure, ground, motion, work, exact, peaks, awake, g):
    """The sleeping buildings from awake.time to t (a whole number of finest steps h_fine later,
    within one substep), in the fewest exact steps of the approach levels (lev: level j steps
    h/2^j = 2^(L − j)·h_fine), each with its exact point (peaks between included). Returns
    the finest steps they slept, summed over them."""
    slept = 0
    if awake.n_sleepers[0] > 0:
        levels = lev.phi.shape[0] - 1
        left = int(round((t - awake.time[0]) / h_fine))
        slept = left * awake.n_sleepers[0]
        now = awake.time[0]
        for level in range(levels + 1):
            size = 1 << (levels - level)
            while left >= size:
                _sleepers_step(now, size * h_fine, lev, level, structure, ground, motion, work, exact, peaks, awake, g)
                now += size * h_fine
                left -= size
    awake.time[0] = t
    return slept


@kernel(**INTERNAL)
def still_needed(horizon, motion, exact, contact, awake):
    """How many pairs of awake buildings may touch within `horizon` s at a finest-step boundary
    of a contact phase (from the CDM's state; a sleeping building's pairs cannot touch before
    the substep's end, where rebalance looks at them)."""
    return needed_within(horizon, motion.u, motion.v_half, exact.a_rel, contact, awake.body_building, awake.flag,
                         awake.need, False)  # fmt: skip


@kernel(**INTERNAL)
def rebalance(t, horizon, step, structure, ground, motion, work, exact, peaks, contact, awake, g):
    """At a substep boundary t of a contact phase, every building's state at t (catch_up): the
    buildings with a pair that may touch within `horizon` s are carried by the CDM, the others
    sleep until the next boundary; those that change hand over (the module docstring).
    Returns how many fell asleep and how many woke."""
    count = needed_within(horizon, motion.u, motion.v_half, exact.a_rel, contact, awake.body_building, awake.everyone,
                          awake.need, True)  # fmt: skip
    flag, need, fs = awake.flag, awake.need, awake.floor_start
    if count < 0:
        need[:] = 1
    acc = motion.energy
    agx, agy = ground_at(t, ground)
    mass, v, cv = structure.mass, exact.v, work.cv_next
    changed = False
    naps = 0
    wakes = 0
    for b in range(flag.size):
        if flag[b] == need[b]:
            continue
        f0 = fs[b]
        f1 = fs[b + 1]
        if flag[b] == 1:  # falls asleep: the CDM's last half interval, then its exact point
            p_in, p_damp = cdm_state_at(agx, agy, step, structure, motion, work, exact, g, f0, f1, b, b + 1)
            acc[ACC_INPUT] += 0.5 * step.dt * p_in
            acc[ACC_DAMPING] += 0.5 * step.dt * p_damp
            _point(t, 0.0, False, b, structure, ground, motion, work, exact, peaks, awake, g)
            flag[b] = 0
            naps += 1
        else:  # wakes: its power at t is out of the CDM's next trapezoid (counted exactly)
            p_in = 0.0
            p_damp = 0.0
            for d in range(3 * f0, 3 * f1, 3):
                p_in -= structure.ground_mass[d] * (agx * v[d] + agy * v[d + 1])
            for d in range(3 * f0, 3 * f1):
                p_damp += v[d] * cv[d]
            acc[ACC_P_INPUT] -= p_in
            acc[ACC_P_DAMPING] -= p_damp
            enter_cdm(step.dt, structure, exact, motion, work, f0, f1)
            flag[b] = 1
            wakes += 1
        changed = True
    if changed:
        set_runs(awake)
    awake.time[0] = t
    return naps, wakes
