"""Yielding members: hysteretic laws of inelastic columns, isolation bearings, the isolation
system of a base-isolated building and its moat wall.

A column's law is named in ``[hysteresis.<name>]`` and referred to by the column (its initial
stiffness comes from its section, 12EI/h³ per local axis). A bearing type is named in
``[bearings.<name>]`` by any three constants that fix its bilinear law, as manufacturers
and engineers give them; the isolators of a building's ``isolation`` table refer to it. Both
are bilinear: initial stiffness K1 up to the yield force F_y, then K2 = α·K1 (docs/theory.md,
"Yielding members").
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass
from typing import Annotated, Callable, Literal

from pydantic import Field, model_validator

from ..limits import MAX_COLUMNS, check_columns
from .base import Name, Positive, Real, Strict
from .contact import ImpactOverrides
from .slab import SlabPolygon

Interaction = Literal["elliptical", "independent"]
Force = Annotated[Real, Field(gt=0, le=1e12)]
Deflection = Annotated[Real, Field(gt=0, le=10.0)]
Ratio = Annotated[Real, Field(ge=0, lt=1)]


class Hysteresis(Strict):
    """A bilinear hysteretic law for columns: elastic (the section's stiffness k) up to the
    yield force, then post_yield_ratio·k; unloading elastic (kinematic hardening)."""

    yield_force: tuple[Force, Force] | None = None
    """Yield shear [F_x, F_y] along the column's local x and y axes, N (each up to 1e12).
    Give this or yield_deflection."""

    yield_deflection: tuple[Deflection, Deflection] | None = None
    """Yield interstorey deflection [δ_x, δ_y] along the column's local axes, m (each up to
    10); the yield force is then k·δ_y. Give this or yield_force."""

    post_yield_ratio: Ratio
    """Post-yield stiffness as a fraction α of the initial stiffness, 0 ≤ α < 1 (0: elastic–
    perfectly plastic)."""

    interaction: Interaction = "elliptical"
    """How the two directions share the strength: "elliptical", a yield surface
    (f_x/F_x)² + (f_y/F_y)² = 1 (a column bent diagonally yields at its section's capacity);
    "independent", one bilinear spring per local axis (overstates diagonal strength by up to
    √2)."""

    @model_validator(mode="after")
    def _one_strength(self) -> "Hysteresis":
        if (self.yield_force is None) == (self.yield_deflection is None):
            raise ValueError("give exactly one of 'yield_force' (N) or 'yield_deflection' (m)")
        return self


@dataclass(frozen=True)
class BearingConstants:
    """The five constants of a bilinear bearing (SI units), related by F_y = K1·d_y and
    Q = F_y − K2·d_y = (K1 − K2)·d_y."""

    k1: float  # initial stiffness K1, N/m
    k2: float  # post-yield stiffness K2, N/m
    q: float  # characteristic strength Q, N
    fy: float  # yield force F_y, N
    dy: float  # yield displacement d_y, m


BEARING_FIELDS = {
    "initial_stiffness": "K1",
    "post_yield_stiffness": "K2",
    "characteristic_strength": "Q",
    "yield_force": "F_y",
    "yield_displacement": "d_y",
}
"""The fields of a bearing that fix its bilinear law, by symbol."""


def _ratio(a: float, b: float) -> float:
    return a / b if b != 0 else math.nan


# (K1, K2, d_y) from each set of three given constants that fixes the law
_SOLVE: dict[frozenset[str], Callable[[dict[str, float]], tuple[float, float, float]]] = {
    frozenset({"K1", "K2", "Q"}): lambda g: (g["K1"], g["K2"], _ratio(g["Q"], g["K1"] - g["K2"])),
    frozenset({"K1", "K2", "F_y"}): lambda g: (g["K1"], g["K2"], g["F_y"] / g["K1"]),
    frozenset({"K1", "K2", "d_y"}): lambda g: (g["K1"], g["K2"], g["d_y"]),
    frozenset({"K1", "Q", "F_y"}): lambda g: (g["K1"], g["K1"] * (1 - g["Q"] / g["F_y"]), g["F_y"] / g["K1"]),
    frozenset({"K1", "Q", "d_y"}): lambda g: (g["K1"], g["K1"] - g["Q"] / g["d_y"], g["d_y"]),
    frozenset({"K2", "Q", "F_y"}): lambda g: (g["K2"] + _ratio(g["Q"] * g["K2"], g["F_y"] - g["Q"]), g["K2"],
                                              _ratio(g["F_y"] - g["Q"], g["K2"])),
    frozenset({"K2", "Q", "d_y"}): lambda g: (g["K2"] + g["Q"] / g["d_y"], g["K2"], g["d_y"]),
    frozenset({"K2", "F_y", "d_y"}): lambda g: (g["F_y"] / g["d_y"], g["K2"], g["d_y"]),
    frozenset({"Q", "F_y", "d_y"}): lambda g: (g["F_y"] / g["d_y"], (g["F_y"] - g["Q"]) / g["d_y"], g["d_y"]),
}  # fmt: skip


def resolve_bearing(given: dict[str, float]) -> BearingConstants:
    """K1, K2, Q, F_y and d_y of a bilinear bearing from three of them (`given` by field
    name, BEARING_FIELDS). Raises ValueError naming the fields when they are more or fewer
    than three, when the three do not fix the law (K1, F_y and d_y: F_y = K1·d_y ties them
    and leaves K2 free; K2 = 0 with Q and F_y: F_y = Q then, and d_y is free), or when the
    law they fix is not bilinear hardening: K1 > K2 ≥ 0, d_y > 0 (so Q > 0, F_y > Q)."""
    named = {BEARING_FIELDS[k]: v for k, v in given.items()}
    fields = " and ".join(", ".join(given).rsplit(", ", 1)) if given else "none"
    if len(given) != 3:
        raise ValueError(
            f"give exactly three of initial_stiffness (K1), post_yield_stiffness (K2), characteristic_strength "
            f"(Q), yield_force (F_y) and yield_displacement (d_y), e.g. K1, K2 and Q, or Q, K2 and d_y; "
            f"given: {fields} ({'too many: they may contradict each other' if len(given) > 3 else 'too few'})"
        )
    solve = _SOLVE.get(frozenset(named))
    if solve is None:
        raise ValueError(
            f"{fields} do not fix the bearing: F_y = K1·d_y ties them, and the post-yield stiffness is left "
            "free; give post_yield_stiffness (K2) or characteristic_strength (Q) instead of one of them"
        )
    k1, k2, dy = solve(named)
    if not math.isfinite(dy) and "K2" in named and named["K2"] == 0:
        raise ValueError(f"{fields} do not fix the bearing: with K2 = 0, F_y = Q and the yield displacement "
                         "is left free; give initial_stiffness (K1) or yield_displacement (d_y) instead of one of them")  # fmt: skip
    c = BearingConstants(k1, k2, (k1 - k2) * dy, k1 * dy, dy)
    for symbol, value in named.items():  # the given values stay exactly as given
        c = dataclasses.replace(c, **{_ATTRIBUTE[symbol]: value})
    if not (all(math.isfinite(v) for v in dataclasses.astuple(c)) and c.k1 > c.k2 >= 0 and c.dy > 0):
        raise ValueError(
            f"{fields} are inconsistent: they give K1 = {k1:.6g} N/m, K2 = {k2:.6g} N/m and d_y = {dy:.6g} m, "
            "but a bilinear bearing needs K1 > K2 ≥ 0 and d_y > 0 (so that 0 < Q < F_y)"
        )
    return c


_ATTRIBUTE = {"K1": "k1", "K2": "k2", "Q": "q", "F_y": "fy", "d_y": "dy"}


class Bearing(Strict):
    """An isolation bearing type (lead-rubber, friction pendulum, …) as a bilinear law, the
    same in every horizontal direction: K1 up to the yield displacement d_y (force F_y), then
    K2, with F_y = K1·d_y and the characteristic strength Q = F_y − K2·d_y. Give three of K1,
    K2, Q, F_y and d_y that fix the law: K1 and K2 with one of Q, F_y or d_y; a lead-rubber
    datasheet's Q, K2 and d_y; … — not K1, F_y and d_y, which F_y = K1·d_y ties, leaving K2
    free. A friction pendulum bearing of radius R carrying W with friction μ: K2 = W/R,
    Q = μ·W and a small d_y."""

    initial_stiffness: Annotated[Real, Field(gt=0, le=1e12)] | None = None
    """Initial (elastic) stiffness K1, N/m, above K2."""

    post_yield_stiffness: Annotated[Real, Field(ge=0, le=1e12)] | None = None
    """Post-yield stiffness K2, N/m, below K1 (0: no hardening)."""

    characteristic_strength: Force | None = None
    """Characteristic strength Q, the force at zero displacement on the post-yield branch, N:
    Q = F_y − K2·d_y = (K1 − K2)·d_y."""

    yield_force: Force | None = None
    """Yield force F_y, N: F_y = K1·d_y."""

    yield_displacement: Deflection | None = None
    """Yield displacement d_y, m."""

    interaction: Interaction = "elliptical"
    """"elliptical" (here a circle: a bearing yields at the same force in every direction) or
    "independent" (one bilinear spring along each of the building's axes)."""

    @model_validator(mode="after")
    def _consistent(self) -> "Bearing":
        self.constants()
        return self

    def given(self) -> dict[str, float]:
        """The constants given in the file, by field name."""
        return {k: getattr(self, k) for k in BEARING_FIELDS if getattr(self, k) is not None}

    def constants(self) -> BearingConstants:
        """K1, K2, Q, F_y and d_y, resolved from the three given."""
        return resolve_bearing(self.given())


class Isolator(Strict):
    """One bearing under the base slab."""

    name: Name
    """Isolator name, unique within the building (e.g. "I1")."""

    x: Real
    """Plan x in building coordinates, m."""

    y: Real
    """Plan y in building coordinates, m."""

    bearing: Name
    """Name of the bearing type in [bearings]."""


class IsolatorGrid(Strict):
    """Isolators at every crossing of grid lines x × y, named I1, I2, … along y first, then
    along x (as columns on a grid)."""

    x: Annotated[list[Real], Field(min_length=1, max_length=1000)]
    """Plan x of the grid lines in building coordinates, m, strictly increasing."""

    y: Annotated[list[Real], Field(min_length=1, max_length=1000)]
    """Plan y of the grid lines in building coordinates, m, strictly increasing."""

    bearing: Name
    """Name of the bearing type of every generated isolator in [bearings]."""

    prefix: Name = "I"
    """Prefix of the generated names: prefix + running number."""

    def isolators(self) -> list[Isolator]:
        return [
            Isolator(name=f"{self.prefix}{i * len(self.y) + j + 1}", x=x, y=y, bearing=self.bearing)
            for i, x in enumerate(self.x)
            for j, y in enumerate(self.y)
        ]


class Moat(ImpactOverrides):
    """The moat (retaining) wall around the base slab: one rigid wall segment along each edge
    of the slab, at the slab's level, a clear gap away. Its impact parameters (stiffness,
    friction, dashpots), where given, replace [contact]'s for the base slab against it."""

    gap: Annotated[Real, Field(gt=0, le=100)]
    """Clear distance from each edge of the base slab at rest to the wall, m."""

    thickness: Annotated[Real, Field(gt=0, le=100)] = 1.0
    """Wall thickness in plan, m."""

    material: Name
    """Name of the wall's material in [materials] (for "auto" impact stiffness)."""


class Isolation(Strict):
    """A base-isolated building's isolation system: the base slab (a rigid diaphragm with its
    own mass, the building's lowest floor) on isolators standing on the ground."""

    height: Annotated[Real, Field(ge=0.01, le=100)]
    """Height of the isolation storey, m: the base slab's elevation above the ground, at which
    it meets its moat wall and any neighbour's floor."""

    slab: SlabPolygon
    """Base slab outline, a convex polygon [[x, y], ...] in building coordinates, m."""

    mass: Annotated[Positive, Field(ge=1.0, le=1e12)] | None = None
    """Base slab mass, kg. Give this or mass_per_area."""

    mass_per_area: Annotated[Positive, Field(ge=0.01, le=1e9)] | None = None
    """Base slab mass per area, kg/m². Give this or mass."""

    rotational_inertia: Annotated[Positive, Field(ge=1e-3, le=1e18)] | None = None
    """Mass moment of inertia of the base slab about its mass centre, kg·m²; default: a
    uniform slab's."""

    isolators: Annotated[list[Isolator], Field(max_length=MAX_COLUMNS)] = []
    """Isolators given one by one."""

    isolator_grid: IsolatorGrid | None = None
    """Isolators generated on a grid (adds to `isolators`)."""

    moat: Moat | None = None
    """The moat wall around the base slab; none if absent."""

    damping_ratio: Annotated[Real, Field(ge=0, lt=1)] = 0.0
    """Viscous damping of the isolation system as a fraction of critical at the isolated
    frequency ω_b = √(ΣK2/M) (M the building's mass, K2 the bearings' post-yield stiffness):
    dashpots in parallel with the isolators, c = 2·ζ_b·K2/ω_b each. Default 0: the bearings
    damp by their hysteresis only, and the isolated modes get no viscous damping (the
    building's Rayleigh damping acts on the superstructure's deformation only)."""

    @model_validator(mode="after")
    def _mass_and_isolators(self) -> "Isolation":
        if (self.mass is None) == (self.mass_per_area is None):
            raise ValueError("give exactly one of 'mass' (kg) or 'mass_per_area' (kg/m²)")
        grid = self.isolator_grid
        check_columns(len(self.isolators) + (len(grid.x) * len(grid.y) if grid is not None else 0),
                      "isolators under one base slab")  # before the grid's isolators are generated
        names = [i.name for i in self.all_isolators()]
        if not names:
            raise ValueError("the base slab stands on no isolators: give 'isolators' or 'isolator_grid'")
        dup = sorted(n for n, k in Counter(names).items() if k > 1)
        if dup:
            raise ValueError(f"isolator names repeat: {', '.join(dup)}")
        import shapely

        outline = shapely.Polygon(self.slab)
        for i in self.all_isolators():
            if outline.distance(shapely.Point(i.x, i.y)) > 1e-6 * max(1.0, outline.length):
                raise ValueError(f"isolator {i.name} at ({i.x:g}, {i.y:g}) m is outside the base slab")
        return self

    def all_isolators(self) -> list[Isolator]:
        grid = self.isolator_grid.isolators() if self.isolator_grid is not None else []
        return grid + list(self.isolators)


def moat_wall_polygons(slab_plan: list[tuple[float, float]], gap: float, thickness: float) -> list[list[tuple[float, float]]]:
    """The moat wall as one convex quadrilateral per edge of a convex, counter-clockwise slab
    outline in plan (m): the band between the edge's offsets by `gap` and `gap + thickness`,
    cut at the mitre lines through the vertices, so that neighbouring segments meet edge to
    edge and the wall is closed."""
    import math

    n = len(slab_plan)
    normals = []
    for i in range(n):
        (x0, y0), (x1, y1) = slab_plan[i], slab_plan[(i + 1) % n]
        length = math.hypot(x1 - x0, y1 - y0)
        normals.append(((y1 - y0) / length, -(x1 - x0) / length))  # outward for counter-clockwise

    def mitre(i: int, d: float) -> tuple[float, float]:
        (ax, ay), (bx, by) = normals[i - 1], normals[i]
        scale = d / (1.0 + ax * bx + ay * by)
        return slab_plan[i][0] + scale * (ax + bx), slab_plan[i][1] + scale * (ay + by)

    walls = []
    for i in range(n):
        j = (i + 1) % n
        walls.append([mitre(i, gap), mitre(j, gap), mitre(j, gap + thickness), mitre(i, gap + thickness)])
    return walls
