"""Relative placement (issue 24 §1): `place = {beside, side, gap, align, offset, rotation}`.

The clear distance at rest of a placed building to its neighbour is checked against shapely's
distance between the assembled global outlines (every slab of one against every slab of the
other), to 1e-12 m: the placement is solved in closed form (the exit of a line from a grown
Minkowski difference), and the outlines are a rotation and a translation of coordinates of
10–30 m, so the distance carries only rounding (~1e-14 m). The Minkowski difference itself is
checked against shapely's convex hull of all vertex differences.
"""

from __future__ import annotations

import copy
import itertools
from pathlib import Path

import numpy as np
import pytest
import shapely

from pounding_cli.api import prepare
from pounding_cli.assembly import assemble
from pounding_cli.errors import InputError
from pounding_cli.gap.minkowski import line_exit, minkowski_difference
from pounding_cli.gap.placement import rotation_matrix

from conftest import load_doc, model_doc, square_building

RNG = np.random.default_rng(24)


def _convex(n: int, radius: float, centre=(0.0, 0.0)) -> np.ndarray:
    """A random convex polygon: n sorted angles on an ellipse, counter-clockwise."""
    angles = np.sort(RNG.uniform(0, 2 * np.pi, n))
    ax, ay = radius * RNG.uniform(0.5, 1.0, 2)
    return np.column_stack([centre[0] + ax * np.cos(angles), centre[1] + ay * np.sin(angles)])


def test_minkowski_difference_is_the_hull_of_vertex_differences() -> None:
    """A ⊖ B equals shapely's convex hull of every a_i − b_j: same area to 1e-12 relative and
    symmetric difference of area ≤ 1e-12 of it, for 50 random pairs of convex polygons."""
    for _ in range(50):
        a, b = _convex(RNG.integers(3, 9), 5.0), _convex(RNG.integers(3, 9), 3.0, centre=(1.0, -2.0))
        ours = shapely.Polygon(minkowski_difference(a, b))
        hull = shapely.MultiPoint([tuple(p - q) for p in a for q in b]).convex_hull
        assert ours.is_valid
        assert abs(ours.area - hull.area) <= 1e-12 * hull.area
        assert ours.symmetric_difference(hull).area <= 1e-12 * hull.area


def test_line_exit_is_where_the_distance_reaches_the_growth() -> None:
    """At the exit the point is `grow` from the polygon (shapely, to 1e-12 m), and a millimetre
    further along it is farther; a line that misses the grown polygon has no exit."""
    poly = _convex(7, 4.0)
    shape = shapely.Polygon(poly)
    for grow in (0.0, 0.05, 1.3):
        for angle in np.linspace(0, 2 * np.pi, 13):
            d = np.array([np.cos(angle), np.sin(angle)])
            p = RNG.uniform(-1, 1, 2)
            t = line_exit(poly, p, d, grow)
            assert t is not None
            assert abs(shape.distance(shapely.Point(*(p + t * d))) - grow) <= 1e-12
            assert shape.distance(shapely.Point(*(p + (t + 1e-3) * d))) > grow
    assert line_exit(poly, np.array([0.0, 50.0]), np.array([1.0, 0.0]), 1.0) is None


def _placed(right: dict, left: dict | None = None, *more: dict) -> dict:
    """Two (or more) buildings, `right` placed as its `place` says."""
    left = left or square_building("left", storeys=2)
    right.pop("origin", None)
    right.pop("rotation", None)
    return model_doc(left, right, *more)


def _clearance(system, a: str, b: str) -> float:
    """shapely's smallest distance between every outline of building a and every one of b."""
    by_name = {bld.name: bld for bld in system.buildings}
    return min(shapely.Polygon(p).distance(shapely.Polygon(q)) for p in by_name[a].slabs for q in by_name[b].slabs)


def _in_frame(system, name: str, frame: str) -> np.ndarray:
    """Every outline vertex of building `name` in the local axes of building `frame`."""
    by_name = {bld.name: bld for bld in system.buildings}
    ref = by_name[frame]
    origin = ref.slabs[0][0]  # the frame's first slab vertex is its local (0, 0) in these models
    turn = rotation_matrix(np.degrees(ref.rotation))
    return np.concatenate([(p - origin) @ turn for p in by_name[name].slabs])


SIDES = ("+x", "-x", "+y", "-y")


@pytest.mark.parametrize("side, align, neighbour_turn, turn", [
    *((s, a, 0.0, 0.0) for s in SIDES for a in ("min", "centre", "max")),
    ("+x", "centre", 30.0, 0.0), ("-y", "min", -65.0, 0.0), ("+y", "centre", 0.0, 17.0), ("-x", "max", 120.0, -40.0),
])  # fmt: skip
def test_the_clear_distance_at_rest_is_the_gap(side: str, align: str, neighbour_turn: float, turn: float) -> None:
    """Every side and alignment, a rotated neighbour, a building turned against its neighbour:
    the smallest distance between the outlines is `gap` (1e-12 m, shapely); the building lies on
    the stated side (its outlines beyond the neighbour's along the side's axis, when parallel);
    and, when parallel, the extents along the other axis line up as `align` says (1e-12 m)."""
    gap = 0.05
    left = square_building("left", storeys=2, rotation=neighbour_turn, origin=(3.0, -2.0))
    right = square_building("right", size=6.0, storeys=3)
    right["place"] = {"beside": "left", "side": side, "gap": gap, "align": align, "rotation": turn}
    system = assemble(load_doc(_placed(right, left)))
    assert abs(_clearance(system, "left", "right") - gap) <= 1e-12
    if turn == 0.0:
        mine, theirs = _in_frame(system, "right", "left"), _in_frame(system, "left", "left")
        axis, sign = (0 if side[1] == "x" else 1), (1.0 if side[0] == "+" else -1.0)
        beyond = sign * (mine[:, axis].min() - theirs[:, axis].max()) if sign > 0 else sign * (mine[:, axis].max() - theirs[:, axis].min())
        assert abs(beyond - gap) <= 1e-12
        other = 1 - axis
        lo = mine[:, other].min() - theirs[:, other].min()
        hi = mine[:, other].max() - theirs[:, other].max()
        mid = 0.5 * (lo + hi)
        assert abs({"min": lo, "max": hi, "centre": mid}[align]) <= 1e-12


def test_irregular_outlines_and_setbacks_keep_the_gap() -> None:
    """A neighbour with a hexagonal first floor and a smaller upper slab, the placed building a
    triangle over a pentagon, turned 23°, with an offset: the smallest distance over every pair
    of their slabs is the gap (1e-12 m)."""
    left = square_building("left", storeys=1)
    left["floors"].append({**copy.deepcopy(left["floors"][0]), "slab": [[1, 1], [7, 1], [7, 7], [1, 7]],
                           "column_grid": {"x": [1, 4, 7], "y": [1, 4, 7], "section": [0.35, 0.35], "material": "concrete", "prefix": "D"}})
    left["floors"][0]["slab"] = [[0, 0], [8, 0], [9.5, 4], [8, 8], [0, 8], [-1, 4]]
    right = square_building("right", storeys=1)
    right["floors"][0]["slab"] = [[0, 0], [8, 0], [9, 5], [4, 9], [-1, 5]]
    right["floors"][0]["column_grid"].update(x=[1, 4, 7], y=[1, 3, 5])
    right["floors"].append({**copy.deepcopy(right["floors"][0]), "slab": [[0, 0], [8, 0], [4, 8.5]],
                            "column_grid": {"x": [2, 4, 6], "y": [1, 2, 3], "section": [0.35, 0.35], "material": "concrete", "prefix": "D"}})
    right["place"] = {"beside": "left", "side": "+x", "gap": 0.137, "align": "centre", "offset": 1.5, "rotation": 23.0}
    system = assemble(load_doc(_placed(right, left)))
    assert abs(_clearance(system, "left", "right") - 0.137) <= 1e-12


def test_a_chain_resolves_in_order_and_keeps_each_gap() -> None:
    """C beside B beside A, listed C first: each gap holds (1e-12 m); the paper's pair placed
    5 cm apart puts the right building's origin at x = 8.05 m (to 1e-12 m)."""
    a = square_building("A", storeys=2)
    b = square_building("B", size=6.0, storeys=2)
    c = square_building("C", size=4.0, storeys=1)
    for x in (b, c):
        x.pop("origin"), x.pop("rotation")
    b["place"] = {"beside": "A", "side": "+x", "gap": 0.05}
    c["place"] = {"beside": "B", "side": "+y", "gap": 0.2, "align": "max"}
    system = assemble(load_doc(model_doc(c, b, a)))
    assert abs(_clearance(system, "A", "B") - 0.05) <= 1e-12
    assert abs(_clearance(system, "B", "C") - 0.2) <= 1e-12
    assert abs(system.buildings[1].slabs[0][0][0] - 8.05) <= 1e-12


def test_the_gap_is_an_ordinary_sweep_path(tmp_path: Path) -> None:
    """`buildings.right.place.gap` swept over three values: each case resolves to its gap."""
    from pounding_cli.model import read_document
    from pounding_cli.sweep.plan import plan_sweep

    from conftest import INPUTS

    doc = read_document(INPUTS / "paper_pounding.toml")
    right = doc["buildings"][1]
    del right["origin"]
    right["place"] = {"beside": "left", "side": "+x", "gap": 0.05}
    for key in ("L", "T"):
        doc["excitation"]["record"][key]["file"] = str(INPUTS / doc["excitation"]["record"][key]["file"])
    import tomli_w

    (tmp_path / "base.toml").write_bytes(tomli_w.dumps(doc).encode())
    (tmp_path / "gaps.sweep.toml").write_text('base = "base.toml"\n[parameters]\n"buildings.right.place.gap" = [0.02, 0.1, 0.3]\n')
    plan = plan_sweep(tmp_path / "gaps.sweep.toml")
    for case, gap in zip(plan.cases, (0.02, 0.1, 0.3)):
        system = assemble(load_doc(case.document))
        assert abs(_clearance(system, "left", "right") - gap) <= 1e-12


@pytest.mark.parametrize("change, field, words", [
    ({"origin": [9.0, 0.0]}, "buildings[1].origin", "give either 'origin' or 'place', not both"),
    ({"rotation": 10.0}, "buildings[1].rotation", "give either 'rotation' or 'place', not both"),
    ({"place": {"beside": "nobody", "side": "+x", "gap": 0.05}}, "buildings[1].place.beside", "unknown building 'nobody'"),
    ({"place": {"beside": "right", "side": "+x", "gap": 0.05}}, "buildings[1].place.beside", "cannot be placed beside itself"),
    ({"place": {"beside": "left", "side": "+x", "gap": -0.05}}, "buildings[1].place.gap", "greater than or equal to 0"),
    ({"place": {"beside": "left", "side": "x", "gap": 0.05}}, "buildings[1].place.side", "'+x', '-x', '+y' or '-y'"),
    ({"place": {"beside": "left", "side": "+x", "gap": 0.05, "offset": 30.0}}, "buildings[1].place",
     "passes beside it: its outlines never come within 0.05 m"),
])  # fmt: skip
def test_bad_placements_name_the_field(change: dict, field: str, words: str) -> None:
    right = square_building("right")
    right.pop("origin"), right.pop("rotation")
    right["place"] = {"beside": "left", "side": "+x", "gap": 0.05}
    right.update(change)
    with pytest.raises(InputError) as refused:
        load_doc(model_doc(square_building("left"), right))
    assert field in str(refused.value) and words in str(refused.value), str(refused.value)


def test_a_cycle_of_references_is_named_once() -> None:
    """a beside b beside c beside a: one message, at the first building, naming the cycle."""
    bs = [square_building(n) for n in "abc"]
    for b, other in zip(bs, "bca"):
        b.pop("origin"), b.pop("rotation")
        b["place"] = {"beside": other, "side": "+x", "gap": 0.05}
    with pytest.raises(InputError) as refused:
        load_doc(model_doc(*bs))
    text = str(refused.value)
    assert text.count("cycle") == 1 and "buildings[0].place.beside: a cycle of place references: a → b → c → a" in text


def test_a_placed_model_runs_as_the_same_model_placed_by_origin() -> None:
    """The paper's right building placed 5 cm beside the left one prepares the same outlines
    as the one at origin (8 + 0.05, 0) m (to 1e-12 m)."""
    placed = square_building("right", storeys=3)
    placed.pop("origin"), placed.pop("rotation")
    placed["place"] = {"beside": "left", "side": "+x", "gap": 0.05}
    by_origin = square_building("right", storeys=3, origin=(8.05, 0.0))
    left = square_building("left", storeys=2)
    for p, q in zip(*(assemble(load_doc(model_doc(left, r))).buildings[1].slabs for r in (placed, by_origin))):
        np.testing.assert_allclose(p, q, rtol=0, atol=1e-12)
    assert prepare(load_doc(model_doc(left, placed))).contact.n_pairs == 2


def test_a_placed_models_result_validates_again(tmp_path: Path) -> None:
    """A result file keeps a placed building's `place` and leaves out the origin it fixes, so
    that the stored model validates again, to the same outlines: `pound report`'s plan view
    rebuilds the geometry from it (placing it by origin and place both was an input error)."""
    import json

    from pounding_cli.api import run_model
    from pounding_cli.report import open_run
    from pounding_cli.report.geometry import plan_geometry

    placed = square_building("right", storeys=3)
    placed.pop("origin"), placed.pop("rotation")
    placed["place"] = {"beside": "left", "side": "+x", "gap": 0.05}
    loaded = load_doc(model_doc(square_building("left", storeys=2), placed, duration=0.2))
    run_model(loaded, output=tmp_path / "placed.h5")
    run = open_run(tmp_path / "placed.h5")
    stored = json.loads(run.result.model_json)["buildings"][1]
    assert stored["place"]["gap"] == 0.05 and "origin" not in stored
    geometry = plan_geometry(run)
    np.testing.assert_allclose(geometry.slab("right", 1).outline, assemble(loaded).buildings[1].slabs[0], rtol=0, atol=1e-12)
