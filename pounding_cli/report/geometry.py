"""Plan geometry of a run, rebuilt from the resolved model stored in its result file.

The file holds the floors' mass centres but not the slab outlines; the model JSON (root
attribute ``model``) holds the outlines in building coordinates. They are turned into
global outlines by the same assembly the solver used (:func:`pounding_cli.assembly.assemble`
on the model validated again), so the report draws exactly what was integrated.

A floor is a rigid diaphragm: a point p of its outline at rest moves to
c + u + R(θ)(p − c), c its mass centre at rest, (u_x, u_y, θ) its displacement relative to
the ground (m, m, rad). Obstacles move with the ground, so in this relative frame they stay.
All lengths in m, global axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .load import Run

LEVEL_TOLERANCE = 1e-3
"""Floors whose elevations differ by less than this (m) are at one level (as the solver)."""


@dataclass(frozen=True)
class Slab:
    """One floor diaphragm at rest."""

    building: str
    floor: int  # 1-based, bottom up
    elevation: float  # m
    outline: np.ndarray  # (n, 2) counter-clockwise, global, m
    centre: np.ndarray  # (2,) mass centre at rest, global, m


@dataclass(frozen=True)
class Obstacle:
    """A fixed obstacle: outline (global, m) and the elevations it spans (m)."""

    name: str
    outline: np.ndarray
    bottom: float
    top: float

    def meets(self, z: float) -> bool:
        """Whether a floor at elevation z (m) meets it."""
        return self.bottom - LEVEL_TOLERANCE <= z <= self.top + LEVEL_TOLERANCE


@dataclass(frozen=True)
class PlanGeometry:
    """Every slab and obstacle of a run, and the levels (distinct floor elevations)."""

    slabs: list[Slab]
    obstacles: list[Obstacle]

    @property
    def levels(self) -> list[float]:
        """Distinct floor elevations from the ground up, m; level k (1-based) is levels[k-1]."""
        out: list[float] = []
        for z in sorted(s.elevation for s in self.slabs):
            if not out or z - out[-1] > LEVEL_TOLERANCE:
                out.append(z)
        return out

    def at_level(self, z: float) -> tuple[list[Slab], list[Obstacle]]:
        """The slabs and obstacles at elevation z (m)."""
        slabs = [s for s in self.slabs if abs(s.elevation - z) <= LEVEL_TOLERANCE]
        return slabs, [o for o in self.obstacles if o.meets(z)]

    def slab(self, building: str, floor: int) -> Slab:
        """The slab of `building`'s floor `floor` (1-based)."""
        for s in self.slabs:
            if s.building == building and s.floor == floor:
                return s
        raise KeyError(f"no floor {floor} in building {building!r}")

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower-left and upper-right corners of everything at rest, m."""
        points = np.concatenate([s.outline for s in self.slabs] + [o.outline for o in self.obstacles])
        return points.min(axis=0), points.max(axis=0)


def plan_geometry(run: Run) -> PlanGeometry:
    """The slabs and obstacles of `run`, from its stored model (InputError if it no longer
    validates, e.g. written by a newer pound)."""
    from ..assembly import assemble
    from ..model import validate_model

    try:
        loaded = validate_model(run.model, run.path)
        system = assemble(loaded)
    except InputError as exc:
        raise InputError(f"the model stored in the file does not validate: {exc}", file=run.path) from None
    slabs = []
    for b in system.buildings:
        stored = run.result.buildings.get(b.name)
        centres = stored.mass_centre if stored is not None else b.mass_centre
        for f in range(b.n_floors):
            slabs.append(Slab(b.name, f + 1, float(b.elevation[f]), b.slabs[f], np.asarray(centres[f], dtype=float)))
    obstacles = []
    for o in loaded.model.all_obstacles():
        bottom, top = o.elevation if isinstance(o.elevation, tuple) else (o.elevation, o.elevation)
        obstacles.append(Obstacle(o.name, _counter_clockwise(np.asarray(o.polygon, dtype=float)), float(bottom), float(top)))
    return PlanGeometry(slabs, obstacles)


def _counter_clockwise(poly: np.ndarray) -> np.ndarray:
    x, y = poly[:, 0], poly[:, 1]
    area2 = float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return poly if area2 >= 0 else poly[::-1]


def moved(slab: Slab, u: np.ndarray, magnify: float = 1.0) -> np.ndarray:
    """The outline of `slab` displaced by u = (u_x, u_y, θ) (m, m, rad) times `magnify`."""
    ux, uy, theta = magnify * np.asarray(u, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    rel = slab.outline - slab.centre
    return slab.centre + np.array([ux, uy]) + rel @ np.array([[c, s], [-s, c]])


def point_displacement(slab: Slab, u: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Displacement (m) of the point `point` (global, m) carried by `slab` moving by u."""
    ux, uy, theta = np.asarray(u, dtype=float)
    rel = np.asarray(point, dtype=float) - slab.centre
    c, s = np.cos(theta), np.sin(theta)
    return np.array([ux + (c - 1) * rel[0] - s * rel[1], uy + s * rel[0] + (c - 1) * rel[1]])


def storey_displacement_at(run: Run, geometry: PlanGeometry, building: str, storey: int, xi: float, t: float) -> np.ndarray:
    """(u_x, u_y, θ) at time t (s) of a storey's outline struck at ξ, referred to the mass centre
    of the floor above it (1-based storey): (1 − s)·T·q_below + s·q_above with
    s = 3ξ² − 2ξ³ (theory §10, "Floors at different heights"; the ground below storey 1)."""
    from ..assembly.storey_contact import storey_shape

    s = storey_shape(xi)
    above = displacement_at(run, building, storey, t)
    if storey == 1:
        return s * above
    below = displacement_at(run, building, storey - 1, t)
    d = geometry.slab(building, storey).centre - geometry.slab(building, storey - 1).centre
    carried = np.array([below[0] - below[2] * d[1], below[1] + below[2] * d[0], below[2]])
    return (1 - s) * carried + s * above


def displacement_at(run: Run, building: str, floor: int, t: float) -> np.ndarray:
    """(u_x, u_y, θ) of a floor (1-based) at time t (s), linear between stored samples."""
    u = run.result.buildings[building].displacement[:, floor - 1, :]
    time = run.result.time
    return np.array([np.interp(t, time, u[:, k]) for k in range(3)])


def nice_magnification(run: Run, geometry: PlanGeometry, fraction: float = 0.05) -> float:
    """A round factor (1, 2, 5 × 10^k) that draws the run's largest peak floor displacement
    at about `fraction` of the plan's size; 1 if nothing moved."""
    peak = max((float(np.hypot(b.peak_displacement[:, 0], b.peak_displacement[:, 1]).max(initial=0.0))
                for b in run.result.buildings.values()), default=0.0)  # fmt: skip
    lo, hi = geometry.extent()
    size = float(np.max(hi - lo))
    if peak <= 0 or size <= 0:
        return 1.0
    target = fraction * size / peak
    if target <= 1:
        return 1.0
    exponent = np.floor(np.log10(target))
    for step in (5, 2, 1):
        if step * 10**exponent <= target:
            return float(step * 10**exponent)
    return float(10**exponent)
