"""Relative placement: a building stands a clear gap beside a neighbour instead of at an origin.

``place = { beside = "left", side = "+x", gap = 0.05 }`` puts the building 5 cm clear of the
building named "left", on that neighbour's +x side. Sides are the neighbour's own axes (its
rotation applied), so a row of buildings along a skewed street is placed as along a straight
one. The model validates the fields and their references here; pounding_cli.gap.placement
solves for the origin and rotation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field

from .base import Name, Real, Strict

if TYPE_CHECKING:
    from .building import Building

Side = Literal["+x", "-x", "+y", "-y"]


class Placement(Strict):
    """Where a building stands, given beside a neighbour: slid in along one of the
    neighbour's axes until its outlines at rest are `gap` clear of the neighbour's."""

    beside: Name
    """Name of the neighbouring building this one is placed beside (itself placed by origin,
    or beside another building: chains resolve in order)."""

    side: Side
    """Side of the neighbour on which this building stands, along the neighbour's own axes
    (its rotation applied): "+x" is beyond the neighbour's largest local x, "-y" beyond its
    smallest local y."""

    gap: Annotated[Real, Field(ge=0.0, le=1e4)]
    """Clear distance at rest, m, 0 to 1e4: the smallest plan distance between any outline of
    this building (every slab, the base slab of an isolated building) and any outline of the
    neighbour, whatever their levels."""

    align: Literal["min", "centre", "max"] = "min"
    """How the two line up along the neighbour's other axis (its y for sides ±x, its x for
    ±y), by the extents of their outlines at rest: "min" their smallest coordinates
    coincide, "centre" their middles, "max" their largest."""

    offset: Annotated[Real, Field(ge=-1e6, le=1e6)] = 0.0
    """Shift after aligning, m, along the neighbour's other axis (positive towards its +y
    for sides ±x, its +x for sides ±y)."""

    rotation: Annotated[Real, Field(ge=-360.0, le=360.0)] = 0.0
    """Rotation of this building's x axis from the neighbour's x axis, degrees,
    counter-clockwise (0: the two stand parallel)."""


def placement_problems(buildings: list["Building"]) -> list[tuple[str, str]]:
    """(field path, message) for placements that cannot be resolved: `origin` or `rotation`
    given beside `place`, a neighbour that does not exist or is the building itself, and
    cycles of `place` references (each cycle named once, at its first building)."""
    names = {b.name: k for k, b in enumerate(buildings)}
    out = []
    for k, b in enumerate(buildings):
        if b.place is None:
            continue
        both = [f for f in ("origin", "rotation") if f in b.model_fields_set]
        if both:
            out.append((f"buildings[{k}].{both[0]}", f"give either '{both[0]}' or 'place', not both: 'place' fixes "
                        "the building's origin and rotation from its neighbour's"))  # fmt: skip
        if b.place.beside == b.name:
            out.append((f"buildings[{k}].place.beside", f"building {b.name!r} cannot be placed beside itself; "
                        "name another building"))  # fmt: skip
        elif b.place.beside not in names:
            out.append((f"buildings[{k}].place.beside", f"unknown building {b.place.beside!r}; buildings: "
                        f"{', '.join(names)}"))  # fmt: skip
    return out + _cycles(buildings, names)


def _cycles(buildings: list["Building"], names: dict[str, int]) -> list[tuple[str, str]]:
    """Each cycle of `place` references (a beside b beside … beside a), named once at the
    building of smallest index in it."""
    out, seen = [], set()
    for start in range(len(buildings)):
        path: list[int] = []
        k: int | None = start
        while k is not None and k not in path and k not in seen:
            path.append(k)
            place = buildings[k].place
            k = names.get(place.beside) if place is not None and place.beside != buildings[k].name else None
        seen.update(path)
        if k is not None and k in path:
            cycle = path[path.index(k) :]
            first = min(cycle)
            at = cycle.index(first)
            ring = cycle[at:] + cycle[:at] + [first]
            out.append((f"buildings[{first}].place.beside", "a cycle of place references: "
                        + " → ".join(buildings[i].name for i in ring)
                        + "; place one building of it by origin"))  # fmt: skip
    return out


def stored_json(model) -> str:  # type: ignore[no-untyped-def]
    """The model as the result files keep it (JSON): a placed building keeps its `place`, and
    its origin and rotation, which the placement fixes, are left out, so that the stored model
    validates again (to the same placement) wherever a result is read."""
    import json

    text = model.model_dump_json()
    if all(b.place is None for b in model.buildings):
        return text
    data = json.loads(text)
    for building, stored in zip(model.buildings, data["buildings"]):
        if building.place is not None:
            stored.pop("origin", None)
            stored.pop("rotation", None)
    return json.dumps(data, separators=(",", ":"), ensure_ascii=False)
