"""`pound validate` shows the geometry at rest (issue 24 §1): per candidate the clear distance,
its direction and the closest points, in text and --json; --plot draws plan and elevation.

The closest points are checked against shapely independently of how they were found: each lies
on its outline (distance to the boundary ≤ 1e-12 m), their distance is the clear distance
(1e-12 m), and the direction is their unit difference (1e-12).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely
from typer.testing import CliRunner

from pounding_cli.api import describe, prepare
from pounding_cli.cli import app
from pounding_cli.gap.rest_plot import rest_figure, view_axis

from conftest import INPUTS, load_doc, model_doc, square_building


def _turned_pair() -> dict:
    """A building placed 7 cm beside a neighbour turned 35°, the placed one turned 10° more,
    and a third one 3 m up on a podium: slab–slab and slab–storey candidates at skew angles."""
    left = square_building("left", storeys=3, rotation=35.0, origin=(2.0, 1.0))
    right = square_building("right", size=6.0, storeys=2)
    right.pop("origin"), right.pop("rotation")
    right["place"] = {"beside": "left", "side": "+x", "gap": 0.07, "align": "centre", "rotation": 10.0}
    right["floors"][0]["height"] = 3.4
    return model_doc(left, right)


def test_closest_points_lie_on_the_outlines_at_the_clear_distance() -> None:
    info = describe(load_doc(_turned_pair()))["contact"]
    rows = info["pairs"] + info["storey_crossings"]
    assert rows and info["storey_crossings"]
    scene = prepare(load_doc(_turned_pair()))
    slabs = {b.name: b.slabs for b in scene.system.buildings}
    for row in rows:
        a = shapely.Polygon(slabs[row["body_a"]][row["floor_a"] - 1])
        b = shapely.Polygon(slabs[row["body_b"]][(row["floor_b"] if "floor_b" in row else row["storey_b"]) - 1])
        pa, pb = (np.array(p) for p in row["closest_points_m"])
        assert a.exterior.distance(shapely.Point(pa)) <= 1e-12 and b.exterior.distance(shapely.Point(pb)) <= 1e-12
        assert abs(np.hypot(*(pb - pa)) - row["clear_distance_m"]) <= 1e-12
        assert abs(row["clear_distance_m"] - a.distance(b)) <= 1e-12
        np.testing.assert_allclose(row["direction_x_y"], (pb - pa) / np.hypot(*(pb - pa)), rtol=0, atol=1e-12)


def test_validate_prints_direction_and_closest_points(tmp_path: Path) -> None:
    """The text table has the direction column (+x for the shipped pair, whose gap is along X) and
    the closest points; --json carries the same rows."""
    runner = CliRunner()
    text = runner.invoke(app, ["validate", str(INPUTS / "paper_pounding.toml")])
    assert text.exit_code == 0, text.output
    assert "towards" in text.output and "closest points (m)" in text.output and "(8, 0) → (8.05, 0)" in text.output
    as_json = runner.invoke(app, ["validate", "--json", str(INPUTS / "paper_pounding.toml")])
    pairs = json.loads(as_json.stdout)["contact"]["pairs"]
    assert all(p["direction_x_y"] == [1.0, 0.0] for p in pairs)


def test_validate_plot_draws_plan_and_elevation(tmp_path: Path) -> None:
    """--plot writes the figure; its plan dimensions the 7 cm gap and names both buildings, its
    elevation spans from the ground to the taller roof (9 m) and marks the slab–storey
    candidates with their ξ."""
    scene = prepare(load_doc(_turned_pair()))
    contact = describe(load_doc(_turned_pair()))["contact"]
    fig = rest_figure(scene.system, [], contact)
    plan, elevation = fig.axes
    texts = [t.get_text() for t in plan.texts]
    assert "left" in texts and "right" in texts and "0.07 m" in texts
    marks = {t.get_text() for t in elevation.texts}
    assert {f"ξ = {c['xi']:.2f}" for c in contact["storey_crossings"]} <= marks
    low, high = elevation.get_ylim()
    assert low < 0.0 and high > 9.0
    out = tmp_path / "rest.png"
    result = CliRunner().invoke(app, ["validate", str(INPUTS / "paper_pounding.toml"), "--plot", str(out)])
    assert result.exit_code == 0 and out.stat().st_size > 10_000


def test_the_elevation_looks_across_the_axis_the_buildings_spread_along() -> None:
    """Two buildings side by side along Y are seen across Y."""
    left = square_building("left")
    right = square_building("right")
    right.pop("origin"), right.pop("rotation")
    right["place"] = {"beside": "left", "side": "+y", "gap": 0.05}
    assert view_axis(prepare(load_doc(model_doc(left, right))).system) == 1


@pytest.mark.parametrize("target", ["kobe_jma.record.toml", "pounding_angle_gap.sweep.toml"])
def test_plot_is_for_models_only(target: str, tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["validate", str(INPUTS / target), "--plot", str(tmp_path / "x.png")])
    assert result.exit_code == 2 and "--plot draws a model's geometry at rest" in result.output
    assert not (tmp_path / "x.png").exists()
