"""Sweep and prune (solver/broad_phase.py) against the all-pairs broad phase: the same pairs,
so the same run, bit for bit; and the same answer to "may a contact begin within the
horizon" on any state."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from pounding_cli.bench.crossover import EVERY_PAIR
from pounding_cli.api import prepare
from pounding_cli.bench.stability import _row
from pounding_cli.model import read_document, validate_model
from pounding_cli.solver import simulate
from pounding_cli.solver.broad_phase import pair_groups, pairs_to_visit, sweep_arrays
from pounding_cli.solver.contact import contact_possible_within
from pounding_cli.solver.integrate import bounding_boxes, contact_state

from conftest import INPUTS
from free_bodies import free_slabs, square

SCENES = Path(__file__).resolve().parents[1] / "pounding_cli" / "bench" / "scenes"

# (model, duration s covering the first impacts, edit, integrator: None = the scene's own, 0 = CDM)

CASES = {
    "paper example": (INPUTS / "paper_pounding.toml", 15.0, None, None),
    "row of 5": (SCENES / "row_of_5.toml", 10.0, None, None),
    "row of 5, CDM": (SCENES / "row_of_5.toml", 8.0, None, 0),
    "isolated, moat walls": (INPUTS / "isolated_moat.toml", 13.0, None, None),
    "rotated building": (SCENES / "corner.toml", 14.2, None, None),
    "row of 20": (SCENES / "row_of_5.toml", 10.0, _row(20), None),
}


def _scene(path: Path, duration: float, edit=None):
    doc = copy.deepcopy(read_document(path))
    if edit is not None:
        doc = edit(doc)
    doc["analysis"]["duration"] = duration
    doc.setdefault("contact", {})["reach"] = EVERY_PAIR  # every pair of a level: the broad phase's own test
    return prepare(validate_model(doc, path))


def _run(scene, sweep: bool, substep: int | None):
    grid = scene.grid
    return simulate(
        scene.system, scene.ground.acceleration, scene.ground.dt, grid.dt, grid.stride, grid.n_steps,
        contact=scene.contact, substep=grid.substep if substep is None else substep, sweep=sweep,
    )  # fmt: skip


def _assert_identical(a, b):
    assert a.status == b.status == "complete"
    assert np.array_equal(a.displacement, b.displacement)
    assert np.array_equal(a.velocity, b.velocity)
    assert np.array_equal(a.contact, b.contact)
    assert np.array_equal(a.events, b.events, equal_nan=True)
    assert np.array_equal(a.energy, b.energy)
    assert (a.events_total, a.contact_steps, a.steps, a.switches) == (b.events_total, b.contact_steps, b.steps, b.switches)


@pytest.mark.parametrize("case", list(CASES))
def test_sweep_and_prune_gives_the_all_pairs_run_bit_for_bit(case):
    path, duration, edit, substep = CASES[case]
    scene = _scene(path, duration, edit)
    every_pair = _run(scene, False, substep)
    assert every_pair.events_total > 0, "the scene must reach its first impacts"
    _assert_identical(every_pair, _run(scene, True, substep))


def test_an_episode_ends_when_the_boxes_part_in_one_step():
    """Square slabs face to face rebound: their boxes are the outlines, so the first step
    without overlap has the boxes apart and sweep and prune does not return the pair; it is
    still visited (it was in contact), its episode ends and its current values return to 0."""
    structure, contact = free_slabs([square(4.0, (0.0, 0.0)), square(4.0, (4.001, 0.0)), square(4.0, (0.0, 9.0))])
    velocity = np.array([0.5, 0, 0, -0.5, 0, 0, 0, 0, 0])
    n = 1500
    runs = [simulate(structure, np.zeros((2, 2)), 1.0, 2e-5, 10, n, contact=contact, initial_velocity=velocity,
                     sweep=sweep) for sweep in (False, True)]  # fmt: skip
    _assert_identical(*runs)
    events = runs[1].events
    assert events.shape[0] == 1 and np.isfinite(events[0, 2]), "one episode, ended"
    assert np.all(runs[1].contact[-1] == 0.0)


def test_pairs_are_grouped_by_level_with_an_obstacle_in_every_level_it_spans():
    # two buildings of three floors (bodies 0–2 and 3–5), an obstacle (6) spanning all levels
    pair_a = np.array([0, 1, 2, 0, 1, 2, 3, 4, 5])
    pair_b = np.array([3, 4, 5, 6, 6, 6, 6, 6, 6])
    body_floor = np.array([0, 1, 2, 3, 4, 5, -1])
    groups = sorted(pair_groups(pair_a, pair_b, body_floor))
    assert groups == [[0, 3, 6], [1, 4, 7], [2, 5, 8]]
    box = np.array([[0, 0, 1, 1]] * 3 + [[2, 0, 3, 1]] * 3 + [[1, -1, 2, 0]], dtype=float)
    broad = sweep_arrays(pair_a, pair_b, body_floor, box, sweep=True)
    starts, bodies, axes, index = broad.group_start, broad.group_body, broad.group_axis, broad.index
    assert starts.tolist() == [0, 3, 6, 9] and axes.tolist() == [0, 0, 0]
    assert sorted(bodies.tolist()) == [0, 1, 2, 3, 4, 5, 6, 6, 6]
    found = sorted(int(p) for p in index if p >= 0)
    assert found == sorted(2 * list(range(9))), "each pair once in its group's matrix (twice: symmetric)"


def _kernel_arguments(contact):
    """(rest boxes, the time loop's contact record with sweep and prune, the same testing
    every pair: records.Contact)."""
    n_dof = 3 * (int(contact.body_floor.max()) + 1)
    sweep = contact_state(contact, n_dof, sweep=True)
    every = contact_state(contact, n_dof, sweep=False)
    return sweep.bodies.box, sweep, every


def _random_states(n_dof: int, rng: np.random.Generator, count: int):
    """States from at rest to far apart: displacements, velocities, accelerations, some NaN."""
    for k in range(count):
        scale = 10.0 ** rng.uniform(-4, 0.5)
        u = np.zeros(n_dof + 3)
        v = np.zeros(n_dof + 3)
        a = np.zeros(n_dof + 3)
        u[:n_dof] = scale * rng.standard_normal(n_dof)
        u[2:n_dof:3] *= 0.01  # rotations
        v[:n_dof] = 10 * scale * rng.standard_normal(n_dof)
        a[:n_dof] = 100 * scale * rng.standard_normal(n_dof)
        if k % 97 == 0:
            u[rng.integers(n_dof)] = np.nan
        yield u, v, a, 10.0 ** rng.uniform(-4, -1)


def _boxes_meet_every_pair(u, contact, box):
    """The displaced boxes' overlap test for every pair, in numpy."""
    floor = contact.body_floor
    moving = floor >= 0
    d = np.zeros((floor.size, 3))
    d[moving] = u[3 * floor[moving, None] + np.arange(3)]
    r = np.abs(d[:, 2]) * contact.body_radius
    lo = box[:, :2] + d[:, :2] - r[:, None]
    hi = box[:, 2:] + d[:, :2] + r[:, None]
    a, b = contact.pair_a, contact.pair_b
    return np.all(~(hi[a] < lo[b]) & ~(hi[b] < lo[a]), axis=1)


@pytest.mark.parametrize("case", ["row of 20", "isolated, moat walls", "rotated building"])
def test_sweep_finds_exactly_the_pairs_whose_boxes_meet(case):
    path, _, edit, _ = CASES[case]
    contact = _scene(path, 1.0, edit).contact
    box, sweep, _ = _kernel_arguments(contact)
    rng = np.random.default_rng(5)
    for u, _, _, _ in _random_states(3 * (contact.body_floor.max() + 1), rng, 400):
        if np.isnan(u).any():
            continue
        n = pairs_to_visit(u, sweep.bodies, sweep.broad)
        assert sweep.broad.hits[:n].tolist() == np.flatnonzero(_boxes_meet_every_pair(u, contact, box)).tolist()


@pytest.mark.parametrize("case", ["row of 20", "isolated, moat walls", "rotated building", "row of 5"])
def test_contact_possible_within_gives_the_all_pairs_answer(case):
    path, _, edit, _ = CASES[case]
    contact = _scene(path, 1.0, edit).contact
    _, sweep, every = _kernel_arguments(contact)
    rng = np.random.default_rng(11)
    answers = []
    for u, v, a, horizon in _random_states(3 * (contact.body_floor.max() + 1), rng, 2000):
        expected = contact_possible_within(horizon, u, v, a, every)
        answer = contact_possible_within(horizon, u, v, a, sweep)
        if np.isnan(u).any():
            assert answer, "a state gone bad: assume a contact may begin (hand over to the CDM, which stops)"
        else:
            assert answer == expected
            answers.append(expected)
    assert 0.1 < np.mean(answers) < 0.9, "both answers are tested"


@pytest.mark.parametrize("case, sweeps", [("paper example", False), ("isolated, moat walls", False),
                                          ("row of 5", True), ("row of 20", True)])  # fmt: skip
def test_the_cheaper_broad_phase_is_chosen(case, sweeps):
    """Sweep and prune from 1.5 candidate pairs per group member (a row of 4 buildings and
    more); below, the all-pairs loop, which has no set-up per step."""
    path, _, edit, _ = CASES[case]
    contact = _scene(path, 1.0, edit).contact
    groups = sweep_arrays(contact.pair_a, contact.pair_b, contact.body_floor, bounding_boxes(contact)).group_axis
    assert (groups.size > 0) == sweeps
