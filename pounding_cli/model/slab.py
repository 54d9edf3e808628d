"""Validation of slab polygons: convex, simple, non-degenerate, returned counter-clockwise.

shapely is the geometry oracle here; the time loop never calls it.
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import AfterValidator, Field

from .base import Real

Point = tuple[float, float]


def _fmt(p: Point) -> str:
    return f"({p[0]:g}, {p[1]:g})"


def signed_area(vertices: list[Point]) -> float:
    """Shoelace signed area, m²: positive when the vertices run counter-clockwise."""
    n = len(vertices)
    return 0.5 * sum(
        vertices[i][0] * vertices[(i + 1) % n][1] - vertices[(i + 1) % n][0] * vertices[i][1]
        for i in range(n)
    )


def convex_polygon(
    vertices: list[Point],
    what: str = "the slab polygon",
    body: str = "slab",
    why: str = "pound models each floor diaphragm as one convex polygon",
) -> list[Point]:
    """Check an outline and return it counter-clockwise.

    Accepts either orientation and collinear vertices; rejects repeated vertices, zero area,
    self-intersection and reflex corners, each with a message that says where. The messages
    name the outline by `what` ("the slab polygon", "the outline of obstacle 'wall'") and
    `body` ("slab", "obstacle"), and say by `why` why it must be convex.
    """
    import shapely

    pts = [(float(x), float(y)) for x, y in vertices]
    if len(pts) >= 4 and pts[0] == pts[-1]:
        pts = pts[:-1]  # a closing vertex repeated, as GIS files write it
    if len(pts) < 3:
        raise ValueError(f"{what} needs at least 3 vertices [x, y] in m, got {len(pts)}")
    size = max(max(abs(x), abs(y)) for x, y in pts) or 1.0
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        if math.dist(p, q) <= 1e-9 * size:
            raise ValueError(
                f"vertices {i + 1} and {(i + 1) % len(pts) + 1} coincide at {_fmt(p)}; "
                "give each corner once"
            )
    x0, y0 = pts[0]
    if all(
        abs((b[0] - x0) * (c[1] - y0) - (b[1] - y0) * (c[0] - x0)) <= 1e-12 * size * size
        for b, c in zip(pts[1:], pts[2:])
    ):
        raise ValueError(f"{what} has zero area (all vertices on one line)")
    polygon = shapely.Polygon(pts)
    if not polygon.is_valid:
        raise ValueError(
            f"{what} is not simple ({shapely.is_valid_reason(polygon)}); "
            f"list the corners in order around the {body}"
        )
    if signed_area(pts) < 0:
        pts.reverse()
    n = len(pts)
    for i in range(n):
        a, b, c = pts[i - 1], pts[i], pts[(i + 1) % n]
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        if cross < -1e-12 * size * size:
            raise ValueError(
                f"{what} is not convex: the corner at {_fmt(b)} points inwards; {why}"
            )
    return pts


Outline = Annotated[list[tuple[Real, Real]], Field(min_length=3, max_length=10_000)]
"""A polygon [[x, y], ...] in m, not yet checked (see convex_polygon)."""

SlabPolygon = Annotated[Outline, AfterValidator(convex_polygon)]
"""A convex polygon [[x, y], ...] in m, either orientation; stored counter-clockwise."""
