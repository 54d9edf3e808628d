"""A contact step per CDM phase (solver/step_levels.py): each pair's own likely contact sets
the step of the phases in which it may touch, the step changes inside a phase (in contact or
not) exactly as the CDM restarted from the same state would take it, and a pair that meets a
stiffer contact than its step allows repeats the run at the step it needs."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from pounding_cli.api import execute, prepare
from pounding_cli.bench.metrics import compare
from pounding_cli.solver.records import CdmStep
from pounding_cli.solver.step_levels import contact_levels
from pounding_cli.solver.tunables import RERUN_MARGIN

ROOT = Path(__file__).resolve().parents[1]
MISMATCHED = ROOT / "pounding_cli" / "bench" / "scenes" / "mismatched_floors.toml"
PAPER = ROOT / "inputs" / "paper_pounding.toml"


def _levels(q0: int, fine: int, yield_per_substep: int, ratio, n_pairs: int = 2):
    step = CdmStep(1e-3 / (q0 * fine), np.zeros((1, 3, 3)), 4 * q0 * fine, q0 * fine)
    return contact_levels(step, fine, yield_per_substep, lambda dt: np.full((1, 3, 3), dt), ratio, n_pairs, 3)


def test_levels_halve_the_steps_per_finest_step_down_to_the_structures_own():
    """q0 = 12 contact steps a finest step: the levels take 12, 6, 3, 2, 1 (⌈12/2^ℓ⌉, each a
    whole number of steps in a finest step); a pair belongs to the coarsest whose step is at
    most its ratio times the contact step (12/q ≤ ratio), and the levels end at the coarsest
    any pair uses. The structure's own step bounds them: with the yielding step's 3 steps a
    finest step, no level takes fewer."""
    lv = _levels(12, 128, 66, [1.0, 1.9, 2.0, 4.5, 6.0, 14.2], 6)
    assert list(lv.pair_level) == [0, 0, 1, 2, 3, 4]
    assert list(lv.per_substep // 128) == [12, 6, 3, 2, 1]
    np.testing.assert_allclose(lv.dt, lv.dt[0] * 12 / np.array([12, 6, 3, 2, 1]), rtol=1e-15)
    assert list(lv.per_output) == [4 * q * 128 for q in (12, 6, 3, 2, 1)]
    np.testing.assert_array_equal(lv.inverse[2], np.full((1, 3, 3), lv.dt[2]))  # each level's own blocks
    bounded = _levels(12, 128, 3 * 128, [1.0, 14.2])
    assert list(bounded.per_substep // 128) == [12, 6, 3] and list(bounded.pair_level) == [0, 2]
    assert list(_levels(12, 128, 66, [1.0, 1.5]).per_substep // 128) == [12]  # nobody coarser: one level
    assert list(_levels(12, 128, 66, None).per_substep // 128) == [12]


def _single_level(scene):
    """The scene with every pair expecting the contact step's ω: every phase at the contact step."""
    contact = scene.contact
    return dataclasses.replace(scene, contact=dataclasses.replace(
        contact, pair_omega=np.full(contact.n_pairs, contact.omega_step)))  # fmt: skip


def test_mismatched_floors_step_by_the_pairs_that_touch():
    """The bench scene with floors at different heights: its stiffest candidate (a slab 0.5 m
    above the neighbour's floor, ω 1,914 rad/s) sets the contact step but never touches, while
    its soft slab–storey contacts (ω 135–442 rad/s) take the phases. With a step per phase it
    takes a sixth of the CDM steps (measured 19,154 against 111,972), changing the step inside
    its phases (8 times), and its results agree with the run at the contact step throughout: the
    same impacts, peak deflections and the peak force to 2e-5 (measured 2.5e-6 and 4.5e-7; the
    single-level run is within 2.7e-8 of the bench's converged reference, docs/bench.md, so the
    difference is the level run's own error, that of CONTACT_DT_FRACTION of each pair's own
    2/ω), and the energy balance within 1e-6 of the input (measured 1.7e-7), as every bench
    scene's. A change of step that left out the half-step velocity's correction
    (step_levels.change_step) gave 1.3e-4 and peaks off by 1.1e-3: both checks catch it."""
    scene = prepare(MISMATCHED)
    levels = execute(scene)
    single = execute(_single_level(scene))
    d, s = levels.diagnostics, single.diagnostics
    assert d["contact_reruns"] == 0 and s["contact_reruns"] == 0
    assert s["step_changes"] == 0 and d["step_changes"] > 0
    assert d["cdm_steps"] < s["cdm_steps"] / 4
    assert levels.contact.impact_count == single.contact.impact_count > 0
    errors = compare(levels, single)
    assert errors.peak_deflection < 2e-5 and errors.peak_force < 2e-5
    assert levels.balance_error_ratio <= 1e-6


def test_a_pair_that_meets_a_stiffer_contact_than_its_step_repeats_the_run(monkeypatch):
    """The mismatched scene's pair that strikes the low building's third storey (ξ = 1/3, ω
    1,055 rad/s, at the contact step) told it is eight times softer: it takes the coarsest
    level, its contacts are met at a step too long for them, the run repeats once with that
    pair's ω raised to what it met (the other pairs and the contact step unchanged), and the
    result is the run prepared with those ω, bit for bit."""
    from pounding_cli import api

    seen = []
    observed = api.observed_pair_omega
    monkeypatch.setattr(api, "observed_pair_omega", lambda c, events: seen.append(observed(c, events)) or seen[-1])
    scene = prepare(MISMATCHED)
    contact = scene.contact
    (soft,) = [p for p, info in enumerate(contact.pairs) if (info.floor_a, info.storey) == (2, 3)]
    omega = contact.pair_omega.copy()
    omega[soft] /= 8
    told = dataclasses.replace(scene, contact=dataclasses.replace(contact, pair_omega=omega))
    result = execute(told)
    d = result.diagnostics
    assert d["contact_reruns"] == 1
    assert d["dt"] == scene.grid.dt
    assert d["contact_omega_seen"] <= RERUN_MARGIN * d["contact_omega_step"]
    met = seen[0]  # what the first attempt met, pair by pair
    assert met[soft] > RERUN_MARGIN * omega[soft]
    direct = dataclasses.replace(scene, contact=dataclasses.replace(contact, pair_omega=np.maximum(omega, met)))
    again = execute(direct)
    assert again.diagnostics["contact_reruns"] == 0
    for name, building in result.buildings.items():
        np.testing.assert_array_equal(building.interstorey_deflection, again.buildings[name].interstorey_deflection)
    assert result.contact.peak_force == again.contact.peak_force


def test_validate_shows_the_steps_the_run_takes(monkeypatch):
    """`pound validate --json` gives each pair's phase step multiple without loading the
    time loop (solver/step_plan.py); the run's own levels (the solver's record, from the
    propagators it built) are the same, pair by pair; and the text says it in one line."""
    import json

    from typer.testing import CliRunner

    from pounding_cli.cli import app
    from pounding_cli.solver import integrate

    runner = CliRunner()
    info = json.loads(runner.invoke(app, ["validate", str(MISMATCHED), "--json"]).stdout)
    multiples = [p["phase_step_multiple"] for p in info["contact"]["pairs"]]
    taken = []
    simulate = integrate.simulate
    monkeypatch.setattr(integrate, "simulate", lambda *a, **k: taken.append(simulate(*a, **k)) or taken[-1])
    execute(prepare(MISMATCHED))
    np.testing.assert_allclose(multiples, taken[0].pair_dt_ratio, rtol=1e-12)
    assert max(multiples) > 1 and min(multiples) == 1
    text = runner.invoke(app, ["validate", str(MISMATCHED)], env={"COLUMNS": "200"}).stdout
    assert "contact phases step by the pairs that may touch in them" in text
    assert "contact phases" not in runner.invoke(app, ["validate", str(PAPER)], env={"COLUMNS": "200"}).stdout


def test_sleeping_buildings_and_steps_that_change_together():
    """The bench's row of five with the middle building's storeys 3.4 m: its two neighbours'
    slabs strike its storeys (slab–storey pairs 3.6–28 times softer than the slab–slab ones at
    the row's ends), buildings sleep through the phases that do not need them, and the phases
    change their step with sleepers about (step_levels.change_step acts on the awake buildings
    alone). Against the same run at the contact step throughout (measured: 27 changes, 100
    sleeps; 118,343 CDM steps against 828,333): the same impacts, peaks within 2e-5 (measured
    7.2e-6, each contact's own error at its step, as above), energy balance within 1e-6 of the
    input (measured 1.7e-8)."""
    import copy

    from pounding_cli.model import read_document, validate_model

    path = ROOT / "pounding_cli" / "bench" / "scenes" / "row_of_5.toml"
    doc = copy.deepcopy(read_document(path))
    doc["buildings"][2]["floors"][0]["height"] = 3.4
    scene = prepare(validate_model(doc, path))
    levels = execute(scene)
    single = execute(_single_level(scene))
    d = levels.diagnostics
    assert d["step_changes"] > 0 and d["sleeps"] > 0 and d["contact_reruns"] == 0
    assert d["cdm_steps"] < single.diagnostics["cdm_steps"] / 3
    assert levels.contact.impact_count == single.contact.impact_count > 0
    errors = compare(levels, single)
    assert errors.peak_deflection < 2e-5 and errors.peak_force < 2e-5
    assert levels.balance_error_ratio <= 1e-6
