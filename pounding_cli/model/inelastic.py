"""Yielding members: hysteretic laws of inelastic columns, isolation bearings, the isolation
system of a base-isolated building and its moat wall.

A column's law is named in ``[hysteresis.<name>]`` and referred to by the column (its initial
stiffness comes from its section, 12EI/h³ per local axis). A bearing type is named in
``[bearings.<name>]`` with its own stiffness, as manufacturers give it; the isolators of a
building's ``isolation`` table refer to it. Both are bilinear: initial stiffness K1 up to the
yield force F_y, then K2 = α·K1 (docs/theory.md, "Yielding members").
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from .base import Name, Positive, Real, Strict
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


class Bearing(Strict):
    """An isolation bearing type (lead-rubber, friction pendulum, …) as a bilinear law, the
    same in every horizontal direction: K1 up to the yield displacement, then K2. A friction
    pendulum bearing of radius R carrying W with friction μ: K2 = W/R, Q = μ·W and a stiff K1."""

    initial_stiffness: Annotated[Real, Field(gt=0, le=1e12)]
    """Initial (elastic) stiffness K1, N/m."""

    post_yield_stiffness: Annotated[Real, Field(ge=0, le=1e12)]
    """Post-yield stiffness K2, N/m, below K1."""

    characteristic_strength: Force | None = None
    """Characteristic strength Q, the force at zero displacement on the post-yield branch, N;
    the yield force is Q·K1/(K1 − K2). Give one of this, yield_force or yield_displacement."""

    yield_force: Force | None = None
    """Yield force F_y, N."""

    yield_displacement: Deflection | None = None
    """Yield displacement d_y, m (the yield force is K1·d_y)."""

    interaction: Interaction = "elliptical"
    """"elliptical" (here a circle: a bearing yields at the same force in every direction) or
    "independent" (one bilinear spring along each of the building's axes)."""

    @model_validator(mode="after")
    def _consistent(self) -> "Bearing":
        given = [self.characteristic_strength, self.yield_force, self.yield_displacement]
        if sum(g is not None for g in given) != 1:
            raise ValueError(
                "give exactly one of 'characteristic_strength' (N), 'yield_force' (N) or 'yield_displacement' (m)"
            )
        if not self.post_yield_stiffness < self.initial_stiffness:
            raise ValueError(
                f"post_yield_stiffness ({self.post_yield_stiffness:g} N/m) must be below initial_stiffness "
                f"({self.initial_stiffness:g} N/m)"
            )
        return self

    def yield_strength(self) -> float:
        """Yield force F_y, N."""
        k1, k2 = self.initial_stiffness, self.post_yield_stiffness
        if self.yield_force is not None:
            return self.yield_force
        if self.yield_displacement is not None:
            return k1 * self.yield_displacement
        return self.characteristic_strength * k1 / (k1 - k2)


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


class Moat(Strict):
    """The moat (retaining) wall around the base slab: one rigid wall segment along each edge
    of the slab, at the slab's level, a clear gap away."""

    gap: Annotated[Real, Field(gt=0, le=100)]
    """Clear distance from each edge of the base slab at rest to the wall, m."""

    thickness: Annotated[Real, Field(gt=0, le=100)] = 1.0
    """Wall thickness in plan, m."""

    material: Name
    """Name of the wall's material in [materials] (for "auto" impact stiffness)."""

    k_normal: Annotated[Real, Field(gt=0, le=1e15)] | None = None
    """Normal impact stiffness against the wall per unit overlap area, N/m²; default: as
    [contact] gives it."""

    k_tangential: Annotated[Real, Field(gt=0, le=1e15)] | None = None
    """Tangential impact stiffness against the wall, N/m; default: as [contact] gives it."""

    friction_static: Annotated[Real, Field(ge=0, le=10)] | None = None
    """Static friction coefficient against the wall; default: [contact]'s."""

    friction_kinetic: Annotated[Real, Field(ge=0, le=10)] | None = None
    """Kinetic friction coefficient against the wall; default: [contact]'s."""


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

    isolators: list[Isolator] = []
    """Isolators given one by one."""

    isolator_grid: IsolatorGrid | None = None
    """Isolators generated on a grid (adds to `isolators`)."""

    moat: Moat | None = None
    """The moat wall around the base slab; none if absent."""

    @model_validator(mode="after")
    def _mass_and_isolators(self) -> "Isolation":
        if (self.mass is None) == (self.mass_per_area is None):
            raise ValueError("give exactly one of 'mass' (kg) or 'mass_per_area' (kg/m²)")
        names = [i.name for i in self.all_isolators()]
        if not names:
            raise ValueError("the base slab stands on no isolators: give 'isolators' or 'isolator_grid'")
        dup = sorted({n for n in names if names.count(n) > 1})
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
