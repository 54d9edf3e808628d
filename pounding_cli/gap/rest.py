"""The geometry at rest of two outlines: their clear distance, its direction and closest points.

shapely's shortest_line gives the closest points p_a on outline A and p_b on outline B; the
clear distance is |p_b − p_a| (m) and the direction the unit vector from p_a to p_b, global
axes: the way B would have to move to open the gap further, and the way A and B approach
each other when the gap closes. Where the outlines touch (distance 0) the direction is not
defined and is None.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Clearance:
    """Two outlines at rest: how far apart, in which direction, between which points."""

    distance: float  # m
    point_a: tuple[float, float]  # closest point on outline A, global m
    point_b: tuple[float, float]  # closest point on outline B, global m
    direction: tuple[float, float] | None  # unit vector from point_a to point_b; None where they touch

    def as_dict(self) -> dict[str, object]:
        """The JSON fields of pound validate's candidate rows."""
        return {"clear_distance_m": self.distance, "direction_x_y": list(self.direction) if self.direction else None,
                "closest_points_m": [list(self.point_a), list(self.point_b)]}  # fmt: skip


def clearance(poly_a: np.ndarray, poly_b: np.ndarray) -> Clearance:
    """The Clearance of outline A (n, 2) to outline B (m, 2), global m."""
    import shapely

    return shapes_clearance(shapely.Polygon(poly_a), shapely.Polygon(poly_b))


def shapes_clearance(a: Any, b: Any) -> Clearance:
    """The Clearance of two shapely geometries (footprints: unions of outlines), global m."""
    import shapely

    (xa, ya), (xb, yb) = shapely.shortest_line(a, b).coords
    distance = float(a.distance(b))
    length = float(np.hypot(xb - xa, yb - ya))
    direction = ((xb - xa) / length, (yb - ya) / length) if distance > 0 else None
    return Clearance(distance, (float(xa), float(ya)), (float(xb), float(yb)), direction)


def compass(direction: tuple[float, float] | None) -> str:
    """A direction as text for tables: "+x", "−y" along an axis, else its angle from +X."""
    if direction is None:
        return "—"
    x, y = direction
    for name, (ax, ay) in (("+x", (1, 0)), ("−x", (-1, 0)), ("+y", (0, 1)), ("−y", (0, -1))):
        if abs(x - ax) < 1e-9 and abs(y - ay) < 1e-9:
            return name
    return f"{np.degrees(np.arctan2(y, x)):.1f}°"
