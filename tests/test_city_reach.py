"""Contact candidates within reach (pounding_cli/city/reach.py, issue 30): which pairs are
kept, that pruning changes no result of the pairs kept, that the default bound holds, and
that a run in which a pruned pair could have touched is repeated with a wider reach."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from pounding_cli.api import execute, prepare
from pounding_cli.city.block import Block, _building, block_buildings, city_document
from pounding_cli.city.reach import excursion_bounds, measured_excursions
from pounding_cli.model import validate_model

BASE = Path(__file__).resolve().parents[1] / "inputs" / "city_block.toml"  # records/ resolve beside it


def _scene(doc):
    return prepare(validate_model(copy.deepcopy(doc), BASE))


def _keys(contact):
    return {(p.body_a, p.floor_a, p.body_b, p.floor_b, p.storey) for p in contact.pairs}


def test_candidates_are_those_of_buildings_within_reach():
    """Against every pair of a 4 × 4 block with floors at different heights (slab–slab and
    slab–storey), filtered by the outlines' distance from shapely, building by building."""
    import shapely

    doc = city_document(block_buildings(Block(rows=4, cols=4, storey_spread=0.3)), "4 x 4", duration=1.0)
    everything = _scene({**doc, "contact": {**doc["contact"], "reach": 1e6}})
    assert everything.contact.near is None, "a reach beyond the block prunes nothing"
    doc["contact"]["reach"] = 0.5
    pruned = _scene(doc)
    shapes = {b.name: shapely.union_all([shapely.Polygon(s) for s in b.slabs]) for b in everything.system.buildings}
    expect = {k for k in _keys(everything.contact) if shapes[k[0]].distance(shapes[k[2]]) <= 0.5}
    assert _keys(pruned.contact) == expect
    assert len(pruned.contact.storeys) > 0, "the case has slab–storey candidates"
    assert pruned.contact.n_pairs < everything.contact.n_pairs / 2


def test_pruning_changes_no_result_of_the_pairs_kept():
    """A 3 × 3 block for 16 s at one Δt: pruned by the default reach and not pruned, every
    building's histories and the kept pairs' contact histories bit for bit."""
    doc = city_document(block_buildings(Block(rows=3, cols=3)), "3 x 3", duration=16.0)
    doc["excitation"]["scale"] = 2.5
    full = _scene({**doc, "contact": {**doc["contact"], "reach": 1e6}})
    doc["analysis"]["dt"] = full.grid.dt
    pruned = _scene(doc)
    assert pruned.contact.near is not None and pruned.grid.dt == full.grid.dt
    a, b = execute(pruned), execute(full)
    assert a.contact.impact_count > 0, "the case pounds"
    for name, bld in a.buildings.items():
        assert bld.displacement.tobytes() == b.buildings[name].displacement.tobytes(), name
    keys_b = {k: i for i, k in enumerate(_keys_list(full.contact))}
    where = [keys_b[k] for k in _keys_list(pruned.contact)]
    assert a.contact.normal_force.tobytes() == np.ascontiguousarray(b.contact.normal_force[:, where]).tobytes()
    assert a.contact.events.size == b.contact.events.size


def _keys_list(contact):
    return [(p.body_a, p.floor_a, p.body_b, p.floor_b, p.storey) for p in contact.pairs]


def test_the_default_bound_holds_without_contact():
    """The modal absolute-sum bound of each building's excursion against the peaks a run
    without contact measures over every step: never below them (1 % for the spectrum's peaks
    taken at the record's samples), and not absurdly above (within 4×)."""
    doc = city_document(block_buildings(Block(rows=2, cols=3)), "2 x 3", duration=20.0)
    doc["contact"] = {"enabled": False}
    scene = _scene(doc)
    result = execute(scene)
    bound = excursion_bounds(scene.system.buildings, scene.ground.acceleration, scene.ground.dt)
    moved = measured_excursions(result, scene.system.buildings)
    assert np.all(bound >= 0.99 * moved), (bound, moved)
    assert np.all(bound <= 4.0 * moved), (bound, moved)


def _trip_doc(reach: float) -> dict:
    """Three 3-storey buildings in a row, a–b 2 cm apart, b–c 15 cm: with a reach of 5 cm the
    pair b–c is pruned, yet b and c each move about 9.5 cm."""
    rng = np.random.default_rng(1)
    buildings = [_building(n, (x, 0.0), 8.0, 8.0, 3, 3.0, rng) for n, x in (("a", 0.0), ("b", 8.02), ("c", 16.17))]
    for b in buildings:
        b["floors"][0]["column_grid"]["section"] = [0.3, 0.3]
    doc = city_document(buildings, "trip the reach check", duration=8.0)
    doc["excitation"]["scale"] = 2.0
    doc["contact"]["reach"] = reach
    return doc


def test_a_pruned_pair_that_could_touch_makes_the_run_repeat_with_a_wider_reach():
    scene = _scene(_trip_doc(0.05))
    assert scene.contact.near == frozenset({(0, 1)}), "b–c pruned"
    result = execute(scene)
    assert result.complete
    assert result.diagnostics["contact_reach_reruns"] == 1
    warning = next(w for w in result.warnings if w["field"] == "contact.reach")
    assert "'b' and 'c'" in warning["message"] and "ran again with a reach of" in warning["message"]
    wider = result.diagnostics["contact_reach_m"]
    direct = execute(_scene(_trip_doc(wider)))
    for name, bld in result.buildings.items():
        assert bld.displacement.tobytes() == direct.buildings[name].displacement.tobytes(), name


def test_a_reach_that_holds_is_not_rerun():
    result = execute(_scene(_trip_doc(0.2)))
    assert result.diagnostics["contact_reach_reruns"] == 0
    assert not [w for w in result.warnings if w["field"] == "contact.reach"]


def test_a_block_that_would_not_fit_is_refused_with_its_estimate(tmp_path):
    """The memory estimate counts the candidates within reach (what the run stores) and refuses
    before the time loop, exit 2, naming the estimate; no file is written."""
    import os
    import subprocess
    import sys

    import tomli_w

    doc = city_document(block_buildings(Block(rows=4, cols=4)), "4 x 4", record_dir=str(BASE.parent / "records"))
    model = tmp_path / "block.toml"
    model.write_text(tomli_w.dumps(doc))
    scene = _scene(doc)
    env = {**os.environ, "POUND_MAX_MEMORY_GB": "0.05"}
    done = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(tmp_path / "out.h5")],
                          capture_output=True, text=True, env=env)  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert f"{scene.contact.n_pairs} contact pairs" in done.stderr and "POUND_MAX_MEMORY_GB" in done.stderr
    assert "MiB" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "out.h5").exists()


def test_near_level_pairs_are_the_all_pairs_loops_within_reach_in_its_order():
    """_near_level_pairs against every floor of every building against every other, kept
    where the two buildings are a `near` pair: the same pairs, in the same order (the order of
    the contact arrays, which the solver sums forces in)."""
    from pounding_cli.assembly.contact import _near_level_pairs
    from pounding_cli.assembly.levels import LEVEL_TOLERANCE

    rng = np.random.default_rng(30)

    class B:
        def __init__(self, z):
            self.elevation = z
            self.n_floors = z.size

    for _ in range(50):
        blds = [B(np.cumsum(rng.choice([3.0, 3.0005, 3.5, 4.0], size=rng.integers(1, 8)))) for _ in range(rng.integers(2, 7))]
        near = {(i, j) for i in range(len(blds)) for j in range(i + 1, len(blds)) if rng.random() < 0.5}
        flat = [(b, f, bld) for b, bld in enumerate(blds) for f in range(bld.elevation.size)]
        brute = [(ia, ib) for ia, (ba, fa, a) in enumerate(flat) for ib, (bb, fb, b) in enumerate(flat)
                 if bb > ba and (ba, bb) in near and abs(a.elevation[fa] - b.elevation[fb]) < LEVEL_TOLERANCE]  # fmt: skip
        assert _near_level_pairs(blds, near) == brute
