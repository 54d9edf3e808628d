"""Where the floors of one building meet another: at the neighbour's floor (slab–slab) or
between its floors (slab–storey).

A slab at elevation z meets a neighbour whose own floor lies within LEVEL_TOLERANCE of z at
that floor (slab–slab, the paper's scope). Otherwise, where z lies strictly inside one of the
neighbour's storeys, z_below < z < z_above, the slab meets that storey at

    ξ = (z − z_below) / h,   h = z_above − z_below,

0 at the floor below (or the neighbour's ground) and 1 at the floor above. The storey's
outline there is the slab of the floor above it (the façade of a shear-type storey follows
its columns, which stand under that slab); it moves with the floors' motion interpolated by
the fixed-fixed column shape s(ξ) = 3ξ² − 2ξ³ (docs/theory.md, "Floors at different heights").
A slab within LEVEL_TOLERANCE of the neighbour's ground meets neither: it faces the
neighbour's foundation, which pound does not model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .building import BuildingArrays

LEVEL_TOLERANCE = 1e-3
"""Floors (and obstacles) whose elevations differ by less than this (m) are at one level."""

NEAR = 1.0
"""Two buildings whose outlines at rest come within this (m) of each other in plan are
neighbours: they should have a contact candidate, and are named in a warning if they have
none (their floors at levels where nothing can meet)."""


@dataclass(frozen=True)
class StoreyCrossing:
    """A slab that lies between two floors of a neighbour: it can strike that storey."""

    building: int  # index of the slab's building
    floor: int  # 0-based floor of the slab in its building
    struck: int  # index of the struck building
    storey: int  # 1-based storey of the struck building: between its floors storey − 1 (0: its ground) and storey
    elevation: float  # the slab's elevation, m
    xi: float  # (z − z_below)/h, in (0, 1)
    height: float  # h, the storey's height, m


def storey_crossings(buildings: list[BuildingArrays], pits: frozenset[int] = frozenset(),
                     near: set[tuple[int, int]] | None = None) -> list[StoreyCrossing]:  # fmt: skip
    """Every slab of every building that lies inside a storey of another building, ordered by
    slab building, slab floor, struck building. A slab within LEVEL_TOLERANCE of a floor of
    the neighbour is slab–slab instead, and one within it of the neighbour's ground (or not
    above it, or above its roof) meets nothing of that building. `pits`: the buildings whose
    isolation storey stands in a moat; the moat wall shields their base slab (floor 1) and their
    isolation storey (storey 1) from the neighbours, so neither is a crossing. `near`: the
    building pairs (i, j), i < j, within reach (city/reach.py); None: every two buildings."""
    others = _others(len(buildings), near)
    out = []
    for a, slabs in enumerate(buildings):
        for b in others[a]:
            struck = buildings[b]
            levels = struck.levels
            for f, z in enumerate(slabs.elevation):
                if not levels[0] + LEVEL_TOLERANCE <= z <= levels[-1] - LEVEL_TOLERANCE or (f == 0 and a in pits):
                    continue
                above = int(np.searchsorted(levels, z, side="right"))  # levels[above − 1] ≤ z < levels[above]
                below_z, above_z = float(levels[above - 1]), float(levels[above])
                if z - below_z < LEVEL_TOLERANCE or above_z - z < LEVEL_TOLERANCE:
                    continue  # at a floor of the neighbour: slab–slab
                if above == 1 and b in pits:
                    continue
                h = above_z - below_z
                out.append(StoreyCrossing(a, f, b, above, float(z), float((z - below_z) / h), h))
    return out


def _others(n: int, near: set[tuple[int, int]] | None) -> list[list[int]]:
    """For each building, the others it may meet, ascending: all, or its pairs in `near`."""
    if near is None:
        return [[b for b in range(n) if b != a] for a in range(n)]
    out: list[list[int]] = [[] for _ in range(n)]
    for i, j in near:
        out[i].append(j)
        out[j].append(i)
    return [sorted(o) for o in out]


def facing_crossings(crossings: list[StoreyCrossing]) -> list[bool]:
    """For each crossing, whether it faces another the other way: the floor of the struck storey
    nearest the slab (the one above if ξ ≥ ½, else below) lies in turn inside a storey of the
    slab's building, with the slab as the nearest floor of that storey. Two slabs at nearby
    levels, each between the other's floors, then strike each other's storeys: two contacts at
    one interface, which as the levels meet (ξ → 1 and ξ → 0) become the one slab–slab contact
    (assembly/contact.py shares the law between them)."""
    def faced(c: StoreyCrossing) -> tuple[int, int]:
        return c.struck, c.storey - 1 if c.xi >= 0.5 else c.storey - 2  # (building, 0-based floor)

    facing = {}  # a slab lies inside at most one storey of each neighbour
    for c in crossings:
        facing[(c.building, c.floor, c.struck)] = faced(c)
    out = []
    for c in crossings:
        b, g = faced(c)
        out.append(g >= 0 and facing.get((b, g, c.building)) == (c.building, c.floor))
    return out


def moat_pits(model) -> frozenset[int]:  # type: ignore[no-untyped-def]
    """The indices of the buildings of a model whose isolation system has a moat wall."""
    return frozenset(b for b, bld in enumerate(model.buildings) if bld.isolation is not None and bld.isolation.moat is not None)


def clear_distance(poly_a: np.ndarray, poly_b: np.ndarray) -> float:
    """The smallest distance in plan between two outlines at rest, m (0 where they touch)."""
    import shapely

    return float(shapely.Polygon(poly_a).distance(shapely.Polygon(poly_b)))


def neighbours(buildings: list[BuildingArrays], within: float = NEAR) -> list[tuple[int, int, float]]:
    """(i, j, d) for every two buildings i < j whose outlines at rest (any slab) come within
    `within` (m, default NEAR) of each other in plan, d their smallest distance, m; found with
    shapely's STRtree, so a city block is not compared building by building."""
    shapes = outlines(buildings)
    return [(i, j, float(shapes[i].distance(shapes[j]))) for i, j in sorted(near_pairs(shapes, within))]


def outlines(buildings: list) -> list:  # type: ignore[type-arg]
    """Each building's plan outline at rest: the union of its slabs (shapely)."""
    import shapely

    return [shapely.union_all([shapely.Polygon(p) for p in b.slabs]) for b in buildings]


def near_pairs(shapes: list, distance: float) -> set[tuple[int, int]]:  # type: ignore[type-arg]
    """(i, j), i < j, of the outlines within `distance` (m) of each other: shapely's STRtree,
    O(N log N) for a city rather than every two buildings."""
    import shapely

    if not math.isfinite(distance):
        n = len(shapes)
        return {(i, j) for i in range(n) for j in range(i + 1, n)}
    tree = shapely.STRtree(shapes)
    found = tree.query(shapes, predicate="dwithin", distance=distance)
    return {(int(min(i, j)), int(max(i, j))) for i, j in found.T if i != j}


def unmet_neighbours(buildings: list[BuildingArrays], pairs: list, crossings: list[StoreyCrossing],  # type: ignore[type-arg]
                     reach: float = math.inf) -> list[tuple[int, int, float]]:  # fmt: skip
    """The neighbours (i, j, d) of `neighbours` between which no contact can happen: no floors
    at one level (no slab–slab candidate among `pairs`, the contact arrays' PairInfo) and no
    slab of one inside a storey of the other. Such a pair is named in a plausibility warning
    (plausibility.unmet_neighbours): their floors all lie where nothing meets (one wholly above
    the other's roof, or at the other's ground). Neighbours beyond `reach` (m) have no
    candidates by design (city/reach.py) and are not named."""
    index = {b.name: k for k, b in enumerate(buildings)}
    met = {tuple(sorted((index[p.body_a], index[p.body_b]))) for p in pairs if p.floor_b}
    met |= {(min(c.building, c.struck), max(c.building, c.struck)) for c in crossings}
    return [(i, j, d) for i, j, d in neighbours(buildings, min(NEAR, reach)) if (i, j) not in met]


def scene_unmet_neighbours(scene) -> list[tuple[int, int, float]]:  # type: ignore[no-untyped-def]
    """unmet_neighbours of a prepared scene (none when contact is off)."""
    if not scene.loaded.model.contact.enabled:
        return []
    return unmet_neighbours(scene.system.buildings, scene.contact.pairs, scene.contact.crossings, scene.contact.reach)
