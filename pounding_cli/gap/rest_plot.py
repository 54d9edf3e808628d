"""`pound validate --plot FILE`: the geometry at rest, in plan and in elevation.

Left, the plan: every building's outlines at rest (each slab, thin; the buildings' names at
their footprint's centroid), obstacles hatched, and the gap of every two neighbouring
buildings (footprints within 1 m: assembly/levels.neighbours) dimensioned between the closest
points of their footprints (gap.rest.shapes_clearance), in m.

Right, the elevation: the buildings side by side as seen across the axis (global X or Y)
along which they spread the most, each drawn over its plan extent along that axis from its
ground (base_elevation) to its roof, a line at each floor. Slab–slab candidates are marked
where the levels meet, slab–storey candidates at the slab's level with ξ: with mismatched
floors this is the view a user checks first. Lengths in m.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..report.style import colour, figure
from .rest import shapes_clearance

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def rest_figure(system: Any, obstacles: list[Any], contact: dict[str, Any]) -> "Figure":
    """The figure of an assembled System's buildings at rest, the model's obstacles, and the
    candidates of describe()'s "contact" entry."""
    fig = figure(11.0, 5.0)
    plan, side = fig.subplots(1, 2, width_ratios=[1.1, 1.0])
    _plan(plan, system, obstacles)
    _elevation(side, system, contact)
    return fig


def _footprint(building: Any) -> Any:
    import shapely

    return shapely.union_all([shapely.Polygon(p) for p in building.slabs])


def _plan(ax: "Axes", system: Any, obstacles: list[Any]) -> None:
    from matplotlib.patches import Polygon

    from ..assembly.levels import neighbours

    for k, building in enumerate(system.buildings):
        for slab in building.slabs:
            ax.add_patch(Polygon(slab, closed=True, fill=True, alpha=0.12, ec=colour(k), fc=colour(k), lw=0.8))
        centre = _footprint(building).centroid
        ax.annotate(building.name, (centre.x, centre.y), ha="center", va="center", color=colour(k), weight="bold")
    for obstacle in obstacles:
        ax.add_patch(Polygon(np.asarray(obstacle.polygon), closed=True, fill=False, hatch="///", ec="0.4", lw=0.6))
    for i, j, _ in neighbours(system.buildings):
        gap = shapes_clearance(_footprint(system.buildings[i]), _footprint(system.buildings[j]))
        (xa, ya), (xb, yb) = gap.point_a, gap.point_b
        ax.annotate("", (xb, yb), (xa, ya), arrowprops={"arrowstyle": "<->", "color": "k", "lw": 0.8, "shrinkA": 0, "shrinkB": 0})
        ax.annotate(f"{gap.distance:.4g} m", (0.5 * (xa + xb), 0.5 * (ya + yb)), xytext=(4, 4),
                    textcoords="offset points", fontsize=8)  # fmt: skip
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.08)
    ax.set_xlabel("X (m)")
    ax.set_ylabel("Y (m)")
    ax.set_title("plan at rest (gaps between footprints)", fontsize=10)
    ax.grid(True, lw=0.3)


def view_axis(system: Any) -> int:
    """0 (global X) or 1 (Y): the axis along which the buildings' footprint centroids spread
    the most; the elevation looks across it."""
    centres = np.array([[c.x, c.y] for c in (_footprint(b).centroid for b in system.buildings)])
    return int(np.argmax(np.ptp(centres, axis=0))) if len(centres) > 1 else 0


def _elevation(ax: "Axes", system: Any, contact: dict[str, Any]) -> None:
    axis = view_axis(system)
    where = {}
    for k, building in enumerate(system.buildings):
        xy = np.concatenate(building.slabs)
        lo, hi = float(xy[:, axis].min()), float(xy[:, axis].max())
        where[building.name] = (lo, hi)
        levels = building.levels
        ax.fill_between([lo, hi], levels[0], levels[-1], color=colour(k), alpha=0.12, lw=0)
        ax.plot([lo, lo], [levels[0], levels[-1]], color=colour(k), lw=0.8)
        ax.plot([hi, hi], [levels[0], levels[-1]], color=colour(k), lw=0.8)
        for z in levels:
            ax.plot([lo, hi], [z, z], color=colour(k), lw=1.6 if z != levels[0] else 0.6)
        ax.annotate(building.name, (0.5 * (lo + hi), levels[-1]), xytext=(0, 3), textcoords="offset points",
                    ha="center", va="bottom", color=colour(k), weight="bold")  # fmt: skip
    marked = False
    for p in contact.get("pairs", []):
        if p["floor_b"] and p["body_a"] in where and p["body_b"] in where:
            x = _between(where[p["body_a"]], where[p["body_b"]])
            ax.plot([x], [p["elevation_m"]], "o", color="k", ms=4, label=None if marked else "slab–slab candidate")
            marked = True
    struck = False
    for c in contact.get("storey_crossings", []):
        x = _between(where[c["body_a"]], where[c["body_b"]])
        ax.plot([x], [c["elevation_m"]], "v", color="tab:red", ms=6, label=None if struck else "slab–storey candidate")
        ax.annotate(f"ξ = {c['xi']:.2f}", (x, c["elevation_m"]), xytext=(5, -10), textcoords="offset points",
                    fontsize=7, color="tab:red")  # fmt: skip
        struck = True
    if marked or struck:
        ax.legend(loc="lower right", fontsize=8)
    ax.set_xlabel(f"{'XY'[axis]} (m)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"elevation at rest, seen across {'XY'[axis]}", fontsize=10)
    ax.margins(0.08)
    ax.grid(True, lw=0.3)


def _between(a: tuple[float, float], b: tuple[float, float]) -> float:
    """Where two extents meet along the view axis: the middle of the gap (or overlap) between
    the nearer ends."""
    if a[1] <= b[0]:
        return 0.5 * (a[1] + b[0])
    if b[1] <= a[0]:
        return 0.5 * (b[1] + a[0])
    return 0.5 * (max(a[0], b[0]) + min(a[1], b[1]))
