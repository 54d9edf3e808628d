"""Floors at different heights (issue 23, first slice): which slab meets which storey of a
neighbour, at what ξ and at what clear distance, base_elevation, and the refusals and warnings
around them. Checked against a plain loop over the levels written here (not the code's sorted
search), shapely's distances, and hand-computed levels."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from pounding_cli.api import describe, prepare
from pounding_cli.assembly.levels import LEVEL_TOLERANCE, neighbours
from pounding_cli.errors import InputError

from conftest import example_doc, load_doc, model_doc, square_building


def _pair(h_left: float = 3.0, h_right: float = 3.0, gap: float = 0.05, storeys=(4, 3), base=(0.0, 0.0), **analysis) -> dict:
    left = square_building("left", storeys=storeys[0])
    right = square_building("right", storeys=storeys[1], origin=(8.0 + gap, 0.0))
    for b, h, z0 in ((left, h_left, base[0]), (right, h_right, base[1])):
        b["floors"][0]["height"] = h
        b["base_elevation"] = z0
    return model_doc(left, right, **analysis)


def _crossings_by_loop(scene) -> list[tuple[int, int, int, int, float]]:
    """(slab building, slab floor, struck building, storey, ξ) by walking every level: the
    reference for storey_crossings."""
    out = []
    buildings = scene.system.buildings
    for a, slabs in enumerate(buildings):
        for b, struck in enumerate(buildings):
            if a == b:
                continue
            levels = [struck.base_elevation, *struck.elevation]
            for f, z in enumerate(slabs.elevation):
                if any(abs(z - lv) < LEVEL_TOLERANCE for lv in levels):
                    continue
                for j in range(1, len(levels)):
                    if levels[j - 1] < z < levels[j]:
                        out.append((a, f, b, j, (z - levels[j - 1]) / (levels[j] - levels[j - 1])))
    return out


@pytest.mark.parametrize("h_right, base_right", [(3.2, 0.0), (3.5, 0.0), (3.0, 1.3), (2.7, -0.4), (3.0, 0.0)])
def test_crossings_are_every_slab_inside_a_neighbours_storey(h_right: float, base_right: float) -> None:
    """Each slab strictly inside a storey of the other building, and no other, is a crossing,
    with ξ = (z − z_below)/h to rounding (1e-12: one subtraction and one division of levels of
    a few metres). Equal storeys at one base give none (the slab–slab case)."""
    scene = prepare(load_doc(_pair(h_right=h_right, base=(0.0, base_right))))
    found = [(c.building, c.floor, c.struck, c.storey, c.xi) for c in scene.contact.crossings]
    expected = _crossings_by_loop(scene)
    assert [f[:4] for f in found] == [e[:4] for e in expected]
    assert np.allclose([f[4] for f in found], [e[4] for e in expected], rtol=0, atol=1e-12)
    assert all(0 < f[4] < 1 for f in found)
    if h_right == 3.0 and base_right == 0.0:
        assert found == [] and scene.contact.n_pairs == 3


def test_the_issues_case_3_2_m_storeys() -> None:
    """The shipped example with the right building's storeys 3.2 m (the issue's report): no
    floors share a level, and every slab of one below the other's roof meets a storey."""
    doc = example_doc()
    doc["buildings"][1]["floors"][0]["height"] = 3.2
    info = describe(load_doc(doc))["contact"]
    assert {p["kind"] for p in info["pairs"]} == {"slab-storey"} and len(info["pairs"]) == 6  # every one simulated
    assert all(c["simulated"] for c in info["storey_crossings"])
    rows = [(c["body_a"], c["floor_a"], c["body_b"], c["storey_b"], round(c["xi"], 12)) for c in info["storey_crossings"]]
    assert rows == [("left", 1, "right", 1, round(3.0 / 3.2, 12)), ("left", 2, "right", 2, round(2.8 / 3.2, 12)),
                    ("left", 3, "right", 3, round(2.6 / 3.2, 12)), ("right", 1, "left", 2, round(0.2 / 3.0, 12)),
                    ("right", 2, "left", 3, round(0.4 / 3.0, 12)), ("right", 3, "left", 4, round(0.6 / 3.0, 12))]  # fmt: skip
    # the left roof at 12 m is above the right's roof (9.6 m): it meets nothing
    assert all(c["floor_a"] != 4 for c in info["storey_crossings"])
    # clear distance at rest: the gap along x between the 8 m slab and the right building's origin
    gap = doc["buildings"][1]["origin"][0] - 8.0
    assert all(abs(c["clear_distance_m"] - gap) < 1e-12 for c in info["storey_crossings"])
    assert info["unmet_neighbours"] == []


def test_levels_within_a_millimetre_stay_slab_to_slab() -> None:
    """The right building's ground 0.5 mm up keeps the three slab–slab pairs (LEVEL_TOLERANCE
    is 1 mm); 2 mm up makes them slab–storey crossings at ξ close to 1 and 0."""
    near = prepare(load_doc(_pair(base=(0.0, 0.0005))))
    assert near.contact.n_pairs == 3 and near.contact.crossings == []
    off = prepare(load_doc(_pair(base=(0.0, 0.002))))
    assert off.contact.n_pairs == 6 and {p.kind for p in off.contact.pairs} == {"slab-storey"}
    xis = sorted(round(c.xi, 9) for c in off.contact.crossings)
    # left floors 1-3 just below right floors 1-3: ξ = (3k − (3(k−1) + 0.002))/3; right floors just above left's
    assert xis == sorted([round(0.002 / 3.0, 9)] * 3 + [round(2.998 / 3.0, 9)] * 3)


def test_base_elevation_shifts_every_level() -> None:
    """A building on a 3 m podium: its floors are at 6, 9, 12 m, so its floor k meets the
    other's floor k + 1 slab to slab; describe() gives its height from its own ground."""
    info = describe(load_doc(_pair(base=(0.0, 3.0))))
    pairs = [(p["floor_a"], p["floor_b"], p["elevation_m"]) for p in info["contact"]["pairs"]]
    assert pairs == [(2, 1, 6.0), (3, 2, 9.0), (4, 3, 12.0)]
    right = info["buildings"][1]
    assert right["base_elevation_m"] == 3.0 and right["height_m"] == 9.0
    assert all(p["clear_distance_m"] == pytest.approx(0.05, abs=1e-12) for p in info["contact"]["pairs"])


def test_clear_distance_is_shapelys_for_a_rotated_neighbour() -> None:
    """A neighbour turned by −10° about its origin (its corner nearest the other): the clear distance of each candidate is
    shapely's distance between the two outlines at rest."""
    doc = _pair(h_right=3.2, gap=0.5)
    doc["buildings"][1]["rotation"] = -10.0
    scene = prepare(load_doc(doc))
    info = describe(load_doc(doc))["contact"]["storey_crossings"]
    assert info
    for row, c in zip(info, scene.contact.crossings):
        a, b = scene.system.buildings[c.building], scene.system.buildings[c.struck]
        expected = shapely.Polygon(a.slabs[c.floor]).distance(shapely.Polygon(b.slabs[c.storey - 1]))
        assert row["clear_distance_m"] == expected


def test_neighbours_that_cannot_meet_are_named() -> None:
    """A 2-storey building whose roof (6 m) is the ground of its neighbour: nothing can meet,
    though they stand 5 cm apart. describe() names them; pound validate warns on stderr."""
    doc = _pair(storeys=(2, 3), base=(0.0, 6.0))
    info = describe(load_doc(doc))["contact"]
    assert info["pairs"] == [] and info["storey_crossings"] == []
    assert info["unmet_neighbours"] == [{"building_a": "left", "building_b": "right", "distance_m": pytest.approx(0.05, abs=1e-12)}]
    # 3 m apart: not neighbours (NEAR = 1 m), no warning
    far = describe(load_doc(_pair(storeys=(2, 3), base=(0.0, 6.0), gap=3.0)))["contact"]
    assert far["unmet_neighbours"] == []


def test_validate_lists_crossings_and_warns_of_unmet_neighbours(tmp_path: Path) -> None:
    doc = _pair(h_right=3.2)
    path = tmp_path / "m.json"
    path.write_text(json.dumps(_absolute_records(doc)))
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "slab–storey" in proc.stdout and "right storey 1" in proc.stdout
    assert "floor–storey" in proc.stdout and "not yet simulate" not in proc.stderr
    # what the model leaves out is said where it applies (the struck columns' own mass), and
    # only there
    assert "without a material density are massless" in proc.stdout and "give their material a density" in proc.stdout
    aligned = tmp_path / "aligned.json"
    aligned.write_text(json.dumps(_absolute_records(_pair())))
    plain = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(aligned)], capture_output=True, text=True)
    assert plain.returncode == 0 and "slab–slab" in plain.stdout and "massless" not in plain.stdout
    doc = _pair(storeys=(2, 3), base=(0.0, 6.0))
    path.write_text(json.dumps(_absolute_records(doc)))
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "buildings 'left' and 'right' are 0.05 m apart in plan, but no floor of one" in proc.stderr
    # a plausibility warning like the others: named by its field, and an error with --strict
    assert f"{path}: buildings[1].base_elevation: buildings 'left' and 'right'" in proc.stderr
    strict = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", "--strict", str(path)],
                            capture_output=True, text=True)  # fmt: skip
    assert strict.returncode == 2 and "buildings[1].base_elevation" in strict.stderr


def _absolute_records(doc: dict) -> dict:
    rec = doc["excitation"]["record"]
    for key in ("L", "T"):
        if key in rec:
            rec[key]["file"] = str((load_doc(doc).folder / rec[key]["file"]).resolve())
    return doc


def test_a_building_wholly_below_a_neighbours_ground_is_refused() -> None:
    """Its roof (6 m) below the other's ground (7 m), 5 cm apart: it would face a foundation
    pound does not model; exit 2 naming base_elevation. 5 m apart it is accepted."""
    with pytest.raises(InputError) as refused:
        prepare(load_doc(_pair(storeys=(2, 3), base=(0.0, 7.0))))
    assert refused.value.field == "buildings[1].base_elevation" and "wholly below the ground" in str(refused.value)
    assert prepare(load_doc(_pair(storeys=(2, 3), base=(0.0, 7.0), gap=5.0))).contact.crossings == []


def test_a_slab_inside_a_neighbours_storey_at_rest_is_refused() -> None:
    """The 3.2 m building overlapping the other by 10 cm: its slabs overlap the other's
    storeys at rest (no floors share a level, so the slab–slab check alone passed it)."""
    with pytest.raises(InputError) as refused:
        prepare(load_doc(_pair(h_right=3.2, gap=-0.1)))
    assert "overlaps the storey beneath floor" in str(refused.value) and refused.value.field == "buildings[1].origin"


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e5", "\"3\""])
def test_base_elevation_must_be_a_finite_number_in_range(tmp_path: Path, value: str) -> None:
    """TOML nan and inf, a value beyond ±10 km, and a string: exit 2 naming the field."""
    text = (Path(__file__).parents[1] / "inputs" / "paper_pounding.toml").read_text()
    text = text.replace('name = "right"\n', f'name = "right"\nbase_elevation = {value}\n')
    path = tmp_path / "m.toml"
    path.write_text(text)
    (tmp_path / "records").symlink_to(Path(__file__).parents[1] / "inputs" / "records")
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "buildings[1].base_elevation" in proc.stderr and str(path) in proc.stderr


def test_neighbours_are_shapelys_within_a_metre() -> None:
    """neighbours() (an STRtree query) against every pair's shapely distance: a row of four
    buildings 0.05, 0.9, 1.2 m apart has neighbours (0, 1) and (1, 2) only."""
    gaps = [0.05, 0.9, 1.2]
    blds, x = [], 0.0
    for k in range(4):
        blds.append(square_building(f"b{k}", origin=(x, 0.0)))
        x += 8.0 + (gaps[k] if k < 3 else 0.0)
    scene = prepare(load_doc(model_doc(*blds)))
    found = neighbours(scene.system.buildings)
    assert [(i, j) for i, j, _ in found] == [(0, 1), (1, 2)]
    assert [d for _, _, d in found] == pytest.approx(gaps[:2], abs=1e-12)


def test_a_run_simulates_and_logs_slab_to_storey_impacts(tmp_path: Path) -> None:
    """The issue's case (the right building's storeys 3.2 m instead of 3.0 m, 5 cm apart):
    the run simulates the slab–storey candidates, says nothing of them on stderr, counts them
    in its diagnostics and logs its impacts with the storey struck and ξ."""
    path = tmp_path / "m.json"
    doc = _pair(h_right=3.2, gap=0.01, duration=8.0)
    path.write_text(json.dumps(_absolute_records(doc)))
    out = tmp_path / "o.h5"
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(path), "-o", str(out)],
                          capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "not yet simulate" not in proc.stderr
    from pounding_cli.results import read_hdf5

    result = read_hdf5(out)
    assert result.diagnostics["storey_pairs"] == 6
    assert [b.base_elevation for b in result.buildings.values()] == [0.0, 0.0]
    pairs = result.contact.pairs  # the left slabs strike storeys 1–3 of the right, the right's storeys 2–4 of the left
    assert sorted(pairs["storey_b"]) == [1, 2, 2, 3, 3, 4]
    events = result.contact.events
    assert events.size > 0 and (events["storey_b"] > 0).all()
    for e in events:  # ξ of the struck storey: (z − z_below)/h from the levels themselves
        h = 3.2 if e["body_b"] == "right" else 3.0
        assert e["xi"] == pytest.approx((e["elevation"] - h * (e["storey_b"] - 1)) / h, abs=1e-12)


def test_a_moat_shields_the_isolation_storey() -> None:
    """The shipped isolated building's base slab (0.5 m) lies inside its neighbour's first
    storey, but it stands in a moat whose wall is between them: no crossing. Without the moat
    wall the base slab meets that storey at ξ = 0.5/3.5."""
    import tomllib

    doc = tomllib.loads((Path(__file__).parents[1] / "inputs" / "isolated_moat.toml").read_text())
    assert prepare(load_doc(doc)).contact.crossings == []
    del doc["buildings"][0]["isolation"]["moat"]
    crossings = prepare(load_doc(doc)).contact.crossings
    assert [(c.building, c.floor, c.struck, c.storey) for c in crossings] == [(0, 0, 1, 1)]
    assert crossings[0].xi == pytest.approx(0.5 / 3.5, abs=1e-12)
