"""Resolving relative placement: the origin and rotation of a building placed beside another.

A building B with ``place = {beside = A, side, gap, align, offset, rotation}`` is solved in
A's own frame (A's local axes, where A's outlines are its slabs as written):

1. B's outlines are turned by `rotation` (degrees, from A's x axis);
2. along A's other axis e (y for sides ±x, x for ±y) B is shifted so that the extents of the
   two buildings' outlines line up as `align` says, then by `offset`;
3. along the side's direction d (+x: A's +x axis, …) B is slid in from afar until the
   smallest distance between any of its outlines and any of A's is `gap`: for every pair of
   outlines, the largest t with dist(A_i, B_j + p + t·d) = gap is where the line p + t·d
   leaves A_i ⊖ B_j grown by `gap` (minkowski.line_exit); B stops at the largest of these,
   where one pair is exactly `gap` apart and every other pair at least that (the distance of
   two convex outlines grows along the line past its exit).

B's origin is then A's origin plus A's rotation applied to that translation, and its rotation
A's plus `rotation`. A chain (C beside B beside A) resolves in order. The clear distance at
rest equals `gap` to rounding (tests/test_placement.py holds it to 1e-12 m against shapely).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .minkowski import line_exit, minkowski_difference

if TYPE_CHECKING:
    from pathlib import Path

    from ..model.building import Building
    from ..model.root import PoundModel

SIDES = {"+x": (0, 1.0), "-x": (0, -1.0), "+y": (1, 1.0), "-y": (1, -1.0)}
"""side → (axis along which B slides in, sign): 0 is the neighbour's x axis, 1 its y."""


def rotation_matrix(degrees: float) -> np.ndarray:
    """2×2 counter-clockwise rotation by `degrees`."""
    phi = math.radians(degrees)
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s], [s, c]])


def local_outlines(building: "Building") -> list[np.ndarray]:
    """Every outline of a building in its own coordinates, m: each floor entry's slab (a
    repeated floor once) and an isolated building's base slab."""
    slabs = [floor.slab for floor in building.floors]
    if building.isolation is not None:
        slabs.append(building.isolation.slab)
    return [np.asarray(s, dtype=float) for s in slabs]


def slide_in(fixed: list[np.ndarray], moving: list[np.ndarray], place) -> np.ndarray | None:  # type: ignore[no-untyped-def]
    """The translation (m, in the fixed building's frame) that puts the `moving` outlines
    (already turned) `place.gap` clear of the `fixed` ones on `place.side`, aligned by
    `place.align` and `place.offset`; None where the line of approach passes them by."""
    axis, sign = SIDES[place.side]
    d = np.zeros(2)
    d[axis] = sign
    other = 1 - axis
    lo_f, hi_f = min(p[:, other].min() for p in fixed), max(p[:, other].max() for p in fixed)
    lo_m, hi_m = min(p[:, other].min() for p in moving), max(p[:, other].max() for p in moving)
    shift = {"min": lo_f - lo_m, "max": hi_f - hi_m, "centre": 0.5 * (lo_f + hi_f) - 0.5 * (lo_m + hi_m)}[place.align]
    p = np.zeros(2)
    p[other] = shift + place.offset
    exits = [line_exit(minkowski_difference(a, b), p, d, place.gap) for a in fixed for b in moving]
    found = [t for t in exits if t is not None]
    return p + max(found) * d if found else None


def resolve_placements(model: "PoundModel", source: "str | Path") -> "PoundModel":
    """The model with every placed building's origin and rotation solved (its `place` kept,
    for the record); the model itself where nothing is placed. References were checked
    (placement_problems); a placement whose line of approach misses the neighbour is an
    InputError naming the building's `place`."""
    if all(b.place is None for b in model.buildings):
        return model
    index = {b.name: k for k, b in enumerate(model.buildings)}
    resolved: dict[int, "Building"] = {}

    def resolve(k: int) -> "Building":
        if k in resolved:
            return resolved[k]
        building = model.buildings[k]
        if building.place is None:
            resolved[k] = building
            return building
        place = building.place
        neighbour = resolve(index[place.beside])
        turn = rotation_matrix(place.rotation)
        moving = [p @ turn.T for p in local_outlines(building)]
        shift = slide_in(local_outlines(neighbour), moving, place)
        if shift is None:
            raise InputError(
                f"building {building.name!r} slid in along {place.side} of {neighbour.name!r} (align = "
                f"{place.align!r}, offset = {place.offset:g} m) passes beside it: its outlines never come within "
                f"{place.gap:g} m of the neighbour's; change align or offset so that the two face each other",
                file=source, field=f"buildings[{k}].place",
            )  # fmt: skip
        origin = np.asarray(neighbour.origin, dtype=float) + rotation_matrix(neighbour.rotation) @ shift
        resolved[k] = building.model_copy(update={"origin": (float(origin[0]), float(origin[1])),
                                                  "rotation": neighbour.rotation + place.rotation})  # fmt: skip
        return resolved[k]

    buildings = [resolve(k) for k in range(len(model.buildings))]
    return model.model_copy(update={"buildings": buildings})
