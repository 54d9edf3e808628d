"""The hybrid's approach levels (solver/hybrid.py): toward a possible contact the exact
propagation halves its step down to a few CDM steps, so the CDM runs only around the impacts.

Two things are checked. The test that decides it, contact_ruled_out_within, is sound: when
it rules a contact out within H, no two outlines overlap at any time within H of a motion at
the velocities and accelerations it was given (shapely decides the overlap, independently).
And the levels change nothing but the cost: the run with them follows the run without them
(the CDM over whole substeps around each impact) to 10⁻⁶ of each component's peak, with the
same impacts starting at the same CDM step, in a third of the CDM steps or fewer.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import Polygon

from pounding_cli import api as pound
from pounding_cli.model import read_document, validate_model
from pounding_cli.solver import step_plan
from pounding_cli.solver.contact import contact_possible_within, contact_ruled_out_within

from conftest import INPUTS
from test_broad_phase import CASES, _kernel_arguments, _random_states, _scene

SCENES = Path(__file__).resolve().parents[1] / "pounding_cli" / "bench" / "scenes"


def _outline(contact, body: int, u: np.ndarray) -> Polygon:
    """Body's displaced outline, turned rigidly about its mass centre, in numpy."""
    points = contact.body_poly[body, : contact.body_nv[body]]
    f = contact.body_floor[body]
    if f < 0:
        return Polygon(points)
    g = contact.body_centre[body]
    c, s = np.cos(u[3 * f + 2]), np.sin(u[3 * f + 2])
    d = points - g
    return Polygon(g + u[3 * f : 3 * f + 2] + np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]]))


def _some_pair_overlaps(contact, u: np.ndarray) -> bool:
    return any(_outline(contact, a, u).intersection(_outline(contact, b, u)).area > 0.0
               for a, b in zip(contact.pair_a, contact.pair_b))  # fmt: skip


@pytest.mark.parametrize("case", ["paper example", "rotated building", "isolated, moat walls", "row of 5"])
def test_a_contact_ruled_out_does_not_happen_within_the_horizon(case):
    """Random states with the displacements scaled down to the gaps (so that outlines are
    near each other and often overlap): ruled out within H ⇒ no overlap at u + v·τ + ½·a·τ²
    (rotations alike) for τ in [0, H]; an overlap now is never ruled out; and the test is
    tighter than the widened boxes (it rules out some states they cannot). Sweep and prune
    finds the candidate pairs as testing every pair does: the same answer."""
    path, _, edit, _ = CASES[case]
    contact = _scene(path, 1.0, edit).contact
    _, sweep, every = _kernel_arguments(contact)
    n_dof = 3 * (contact.body_floor.max() + 1)
    rng = np.random.default_rng(17)
    ruled_out = tighter = overlapping = 0
    for u, v, a, horizon in _random_states(n_dof, rng, 600):
        if np.isnan(u).any():
            continue
        u, v, a, horizon = 0.05 * u, 0.05 * v, 0.05 * a, 0.1 * horizon
        u[2:n_dof:3] *= 10.0  # turns of up to a few mrad: where the boxes widen most
        if _some_pair_overlaps(contact, u):
            overlapping += 1
            assert not contact_ruled_out_within(0.0, u, v, a, every)
            continue
        answer = contact_ruled_out_within(horizon, u, v, a, every)
        assert contact_ruled_out_within(horizon, u, v, a, sweep) == answer, "sweep and prune"
        if not answer:
            continue
        ruled_out += 1
        tighter += contact_possible_within(horizon, u, v, a, every)
        for tau in np.linspace(0.0, horizon, 9):
            assert not _some_pair_overlaps(contact, u + v * tau + 0.5 * a * tau**2)
    print(f"{overlapping} overlapping, {ruled_out} ruled out, {tighter} of them not by the boxes")
    assert overlapping > 20 and ruled_out > 20, "both kinds of state are tested"
    assert tighter > 0, "some states the boxes cannot rule out are ruled out"


@pytest.mark.parametrize("path, duration, saving", [(INPUTS / "paper_pounding.toml", 16.0, 3.0),
                                                    (SCENES / "corner.toml", None, 2.5),
                                                    (SCENES / "row_of_5.toml", 10.0, 3.0)])  # fmt: skip
def test_the_approach_levels_change_nothing_but_the_cost(path, duration, saving, monkeypatch):
    """Histories within 10⁻⁶ of each component's peak: the runs differ only in where the CDM
    takes over and hands back (each hand-over second-order consistent, so the difference is
    of order (ω·Δt)² ≈ 10⁻⁷ at the contact step); the same impacts, starting within 10⁻³ of a
    contact step of each other (located inside the step, so they move with the trajectories).
    The levels take `saving` × fewer CDM steps: less in the corner scene, whose contact step
    follows its soft corner contacts (60 CDM steps per substep, so two levels whose finest
    step is 15 CDM steps, against 416 and five levels in the paper's buildings)."""
    doc = copy.deepcopy(read_document(path))
    if duration is not None:
        doc["analysis"]["duration"] = duration
    model = validate_model(doc, path)
    with_levels = pound.run_model(model)
    monkeypatch.setattr(step_plan, "APPROACH_MIN_STEPS", 10**9)  # no level: the CDM for whole substeps
    without = pound.run_model(model)
    assert with_levels.contact.impact_count == without.contact.impact_count > 0
    starts = with_levels.contact.events["t_start"], without.contact.events["t_start"]
    assert np.abs(starts[0] - starts[1]).max() <= 1e-3 * with_levels.diagnostics["dt"]
    for name, b in without.buildings.items():
        peak = np.abs(b.displacement).max(axis=(0, 1))
        difference = np.abs(with_levels.buildings[name].displacement - b.displacement).max(axis=(0, 1))
        assert np.all(difference <= 1e-6 * peak), name
    d, d0 = with_levels.diagnostics, without.diagnostics
    assert d["contact_steps"] == d0["contact_steps"]
    assert saving * d["cdm_steps"] <= d0["cdm_steps"]
    assert d["exact_steps_of_dt"] + d["cdm_steps"] == d0["exact_steps_of_dt"] + d0["cdm_steps"]
