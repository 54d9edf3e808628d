"""Slab polygon properties against closed forms and shapely; slab validation."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from numpy.testing import assert_allclose

from pounding_cli.assembly.polygon import polar_moment_about_centroid, polygon_area, polygon_centroid
from pounding_cli.model.slab import convex_polygon

SHAPES = {
    "rectangle": [(0, 0), (16, 0), (16, 8), (0, 8)],
    "offset triangle": [(1, 2), (7, 3), (2, 9)],
    "hexagon": [(np.cos(a) + 3, np.sin(a) - 1) for a in np.linspace(0, 2 * np.pi, 7)[:-1]],
    "skew quad": [(0, 0), (10, -1), (12, 5), (1, 7)],
}


@pytest.mark.parametrize("name", SHAPES)
def test_area_and_centroid_match_shapely(name):
    v = np.array(SHAPES[name], dtype=float)
    poly = shapely.Polygon(v)
    # shoelace sums of a handful of vertices: exact to rounding
    assert_allclose(polygon_area(v), poly.area, rtol=1e-13, err_msg=name)
    assert_allclose(polygon_centroid(v), [poly.centroid.x, poly.centroid.y], rtol=1e-13, atol=1e-13, err_msg=name)


def test_polar_moment_closed_forms():
    # rectangle a×b: (a b³ + b a³)/12 about the centroid, wherever it is placed
    a, b = 16.0, 8.0
    rect = np.array([(5, 5), (5 + a, 5), (5 + a, 5 + b), (5, 5 + b)], dtype=float)
    assert_allclose(polar_moment_about_centroid(rect), a * b * (a * a + b * b) / 12, rtol=1e-12)
    # right triangle with legs a, b: I_x + I_y about the centroid = a b (a² + b²)/36
    tri = np.array([(0, 0), (a, 0), (0, b)], dtype=float)
    assert_allclose(polar_moment_about_centroid(tri), a * b * (a * a + b * b) / 36, rtol=1e-12)
    # regular hexagon of side s: J = (5√3/8) s⁴
    hexagon = np.array(SHAPES["hexagon"], dtype=float)
    assert_allclose(polar_moment_about_centroid(hexagon), 5 * np.sqrt(3) / 8, rtol=1e-12)


def test_slab_returned_counter_clockwise():
    cw = [(0, 0), (0, 8), (8, 8), (8, 0)]
    ccw = convex_polygon(cw)
    assert polygon_area(np.array(ccw)) > 0
    assert set(ccw) == set(cw)


def test_slab_accepts_collinear_vertex_and_closing_repeat():
    assert len(convex_polygon([(0, 0), (4, 0), (8, 0), (8, 8), (0, 8)])) == 5
    assert len(convex_polygon([(0, 0), (8, 0), (8, 8), (0, 8), (0, 0)])) == 4


@pytest.mark.parametrize(
    "vertices, words",
    [
        ([(0, 0), (8, 0), (8, 4), (4, 4), (4, 8), (0, 8)], "not convex"),
        ([(0, 0), (8, 8), (8, 0), (0, 8)], "not simple"),
        ([(0, 0), (4, 0), (8, 0)], "zero area"),
        ([(0, 0), (8, 0), (8, 0), (0, 8)], "coincide"),
        ([(0, 0), (8, 0)], "at least 3"),
    ],
)
def test_slab_rejections(vertices, words):
    with pytest.raises(ValueError, match=words):
        convex_polygon(vertices)


@pytest.mark.parametrize(
    "slab, eccentricity, accepted",
    [
        ([(0, 0), (8, 0), (8, 8), (0, 8)], (4.0, 0.0), True),  # on the edge x = 8: a limit case, allowed
        ([(0, 0), (8, 0), (8, 8), (0, 8)], (4.01, 0.0), False),  # 1 cm beyond it
        ([(0, 0), (12, 0), (0, 6)], (2.5, 1.5), False),  # centroid (4, 2) + e = (6.5, 3.5): in the bounding box, not the triangle
        ([(0, 0), (12, 0), (0, 6)], (1.5, 0.5), True),  # (5.5, 2.5): inside
    ],
)
def test_mass_centre_must_lie_on_the_slab(slab, eccentricity, accepted):
    """The mass of a floor lies on its convex slab, so its mass centre (slab centroid +
    eccentricity) must lie within the outline; the boundary itself is allowed."""
    from pydantic import ValidationError

    from pounding_cli.model import Floor

    grid = {"x": [0.0], "y": [0.0], "section": [0.3, 0.3], "material": "c"}
    floor = {"height": 3.0, "slab": slab, "mass": 1e4, "eccentricity": eccentricity, "column_grid": grid}
    if accepted:
        assert Floor.model_validate(floor).eccentricity == eccentricity
    else:
        with pytest.raises(ValidationError, match="outside the slab") as err:
            Floor.model_validate(floor)
        assert err.value.errors()[0]["loc"] == ("eccentricity",)
