"""Buildings: floors (rigid convex diaphragms), the columns of the storey below each floor,
and Rayleigh damping. Coordinates in a building are local: metres from the building's own
origin, along its own x and y axes (see :attr:`Building.origin` and :attr:`Building.rotation`).
"""

from __future__ import annotations

from collections import Counter
from typing import Annotated

from pydantic import Field, ValidationInfo, field_validator, model_validator

from ..limits import MAX_COLUMNS, MAX_REPEAT, check_columns, check_repeat, max_storeys
from .base import Count, Name, Positive, Real, Strict
from .inelastic import Isolation
from .placement import Placement
from .slab import SlabPolygon

Width = Annotated[Real, Field(ge=0.001, le=50.0)]
Section = tuple[Width, Width]
ShearCapacity = tuple[Annotated[Positive, Field(le=1e12)], Annotated[Positive, Field(le=1e12)]]


class Column(Strict):
    """One vertical column, fixed at both ends (lateral stiffness 12EI/h³ per local axis)."""

    name: Name
    """Column name, unique within its storey (e.g. "C9"); a name used in several storeys
    denotes one column line and must keep its plan position."""

    x: Real
    """Plan x of the column axis in building coordinates, m."""

    y: Real
    """Plan y of the column axis in building coordinates, m."""

    section: Section
    """Rectangular section [b_x, b_y], m (each 0.001 to 50): widths along the column's
    local x and y axes."""

    angle: Real = 0.0
    """Rotation of the column's local x axis from the building's x axis, degrees,
    counter-clockwise."""

    material: Name
    """Name of the column's material in [materials]."""

    hysteresis: Name | None = None
    """Name of the column's hysteretic law in [hysteresis]; absent: linear elastic."""

    shear_capacity: ShearCapacity | None = None
    """Shear strength [V_x, V_y] of the column along its local x and y axes, N (each > 0):
    where a neighbour's slab strikes the column between its floors, pound reports the shear
    demand against it (demand/capacity, `pound report`); absent: no ratio."""


class ColumnGrid(Strict):
    """Columns at every crossing of grid lines x × y, named C1, C2, … along y first, then
    along x, from the corner at the smallest x and y (the paper's numbering: on a 3×3 grid
    C9 is the corner at the largest x and y)."""

    x: Annotated[list[Real], Field(min_length=1, max_length=1000)]
    """Plan x of the grid lines in building coordinates, m, strictly increasing."""

    y: Annotated[list[Real], Field(min_length=1, max_length=1000)]
    """Plan y of the grid lines in building coordinates, m, strictly increasing."""

    section: Section
    """Rectangular section [b_x, b_y] of every generated column, m (each 0.001 to 50)."""

    angle: Real = 0.0
    """Rotation of every generated column's local x axis from the building's x axis,
    degrees, counter-clockwise."""

    material: Name
    """Name of the material of the generated columns in [materials]."""

    hysteresis: Name | None = None
    """Name of the generated columns' hysteretic law in [hysteresis]; absent: linear elastic."""

    shear_capacity: ShearCapacity | None = None
    """Shear strength [V_x, V_y] of every generated column along its local x and y axes, N
    (each > 0), against which the shear a neighbour's slab puts into it is reported; absent:
    no ratio."""

    prefix: Name = "C"
    """Prefix of the generated names: prefix + running number."""

    sections: dict[Name, Section] = {}
    """Sections [b_x, b_y] in m (each 0.001 to 50) that replace `section` for the named
    generated columns, e.g. {C1 = [1.0, 0.3]}."""

    omit: list[Name] = []
    """Generated columns to leave out (by name), for grids with gaps."""

    @field_validator("x", "y")
    @classmethod
    def _increasing(cls, lines: list[float]) -> list[float]:
        for a, b in zip(lines, lines[1:]):
            if not b > a:
                raise ValueError(f"grid lines must increase strictly, got {a:g} then {b:g} m")
        return lines

    def generated_names(self) -> list[str]:
        """Names of all crossings in the paper's order (y first, then x), before `omit`."""
        return [f"{self.prefix}{i + 1}" for i in range(len(self.x) * len(self.y))]

    def count(self) -> int:
        """How many columns the grid generates (its crossings less the omitted)."""
        return len(self.x) * len(self.y) - len(set(self.omit))

    @model_validator(mode="after")
    def _known_names(self) -> "ColumnGrid":
        check_columns(len(self.x) * len(self.y), "columns on one grid")  # before any name is generated
        names = set(self.generated_names())
        for field, given in (("sections", self.sections), ("omit", self.omit)):
            unknown = [n for n in given if n not in names]
            if unknown:
                raise ValueError(
                    f"{field} names {', '.join(unknown)}, which the grid does not generate "
                    f"(it makes {self.prefix}1 … {self.prefix}{len(names)})"
                )
        return self

    def columns(self) -> list[Column]:
        """The generated columns, in the paper's numbering."""
        out = []
        omit = set(self.omit)
        for i, x in enumerate(self.x):
            for j, y in enumerate(self.y):
                name = f"{self.prefix}{i * len(self.y) + j + 1}"
                if name in omit:
                    continue
                out.append(
                    Column(
                        name=name,
                        x=x,
                        y=y,
                        section=self.sections.get(name, self.section),
                        angle=self.angle,
                        material=self.material,
                        hysteresis=self.hysteresis,
                        shear_capacity=self.shear_capacity,
                    )
                )
        return out


class Floor(Strict):
    """A floor: its rigid slab (diaphragm) and the storey of columns beneath it."""

    height: Annotated[Real, Field(ge=0.1, le=1000.0)]
    """Height of the storey below this floor (column length), m, 0.1 to 1000."""

    repeat: Annotated[Count, Field(ge=1, le=MAX_REPEAT)] = 1
    """Number of identical storeys this entry stands for, stacked upwards."""

    slab: SlabPolygon
    """Slab outline: a convex polygon [[x, y], ...] in building coordinates, m, either
    orientation."""

    mass: Annotated[Positive, Field(ge=1.0, le=1e12)] | None = None
    """Lumped floor mass, kg, 1 to 1e12. Give this or mass_per_area."""

    mass_per_area: Annotated[Positive, Field(ge=0.01, le=1e9)] | None = None
    """Floor mass per slab area, kg/m², 0.01 to 1e9 (the paper uses 1000). Give this or mass."""

    eccentricity: tuple[Real, Real] = (0.0, 0.0)
    """Offset [e_x, e_y] of the mass centre from the slab centroid, m, building axes. The
    mass centre must lie on the slab (the floor's mass does)."""

    rotational_inertia: Annotated[Positive, Field(ge=1e-3, le=1e18)] | None = None
    """Mass moment of inertia J about the vertical axis through the mass centre, kg·m².
    Default: that of a uniform slab of the floor's mass, m·(I_x + I_y)/A about the slab
    centroid, whatever the eccentricity (the accidental-eccentricity convention)."""

    columns: Annotated[list[Column], Field(max_length=MAX_COLUMNS)] = []
    """Columns of the storey below this floor, given one by one."""

    column_grid: ColumnGrid | None = None
    """Columns of the storey below this floor, generated on a grid (adds to `columns`)."""

    @field_validator("repeat", mode="before")
    @classmethod
    def _repeat_within_limit(cls, value: object) -> object:
        if isinstance(value, int) and not isinstance(value, bool):
            check_repeat(value)  # before pydantic's bound, to say why there is one
        return value

    @field_validator("eccentricity")
    @classmethod
    def _mass_centre_on_slab(cls, ecc: tuple[float, float], info: ValidationInfo) -> tuple[float, float]:
        """The mass of a floor lies on its slab, a convex polygon, so its centre does too."""
        import shapely

        slab = info.data.get("slab")
        if slab is None:  # the slab itself was refused
            return ecc
        outline = shapely.Polygon(slab)
        centre = shapely.Point(outline.centroid.x + ecc[0], outline.centroid.y + ecc[1])
        outside = outline.distance(centre)
        if outside > 1e-6 * max(1.0, outline.length):  # as for columns under the slab
            raise ValueError(
                f"the mass centre, at ({centre.x:.6g}, {centre.y:.6g}) m, is {outside:.3g} m outside the slab: "
                "a floor's mass lies on its slab, so its centre must lie within the slab outline; "
                f"got [{ecc[0]:g}, {ecc[1]:g}] m from the slab centroid"
            )
        return ecc

    @model_validator(mode="after")
    def _mass_and_columns(self) -> "Floor":
        if (self.mass is None) == (self.mass_per_area is None):
            raise ValueError("give exactly one of 'mass' (kg) or 'mass_per_area' (kg/m²)")
        if not self.columns and self.column_grid is None:
            raise ValueError(
                "the storey below this floor has no columns: give 'columns' or 'column_grid'"
            )
        check_columns(self.column_count())  # before the grid's columns are generated
        names = [c.name for c in self.all_columns()]
        dup = sorted(n for n, k in Counter(names).items() if k > 1)
        if dup:
            raise ValueError(f"column names repeat within the storey: {', '.join(dup)}")
        self._columns_under_slab()
        return self

    def _columns_under_slab(self) -> None:
        import shapely

        outline = shapely.Polygon(self.slab)
        tolerance = 1e-6 * max(1.0, outline.length)
        for c in self.all_columns():
            if outline.distance(shapely.Point(c.x, c.y)) > tolerance:
                raise ValueError(
                    f"column {c.name} at ({c.x:g}, {c.y:g}) m is outside the slab it carries"
                )

    def column_count(self) -> int:
        """Columns of the storey, counted without generating the grid's."""
        return len(self.columns) + (self.column_grid.count() if self.column_grid is not None else 0)

    def all_columns(self) -> list[Column]:
        """Grid-generated columns followed by the ones given one by one."""
        grid = self.column_grid.columns() if self.column_grid is not None else []
        return grid + list(self.columns)


class RayleighDamping(Strict):
    """Rayleigh damping C = a0·M + a1·K fixed by two damping ratios at two modes. Of a
    base-isolated building: the superstructure's, from its modes on a fixed base and acting
    on its deformation only (docs/theory.md §12)."""

    ratios: tuple[Annotated[Real, Field(ge=0, lt=1)], Annotated[Real, Field(ge=0, lt=1)]] = (
        0.05,
        0.05,
    )
    """Damping ratios [ζ_i, ζ_j], fraction of critical (0.05 = 5 %)."""

    modes: tuple[Annotated[Count, Field(ge=1)], Annotated[Count, Field(ge=1)]] = (1, 3)
    """Mode numbers [i, j] (1 = longest period) where the ratios hold; of a base-isolated
    building, modes of its superstructure on a fixed base. Default [1, 3]: a symmetric
    building's modes 1 and 2 share one frequency and cannot anchor the fit."""

    @field_validator("modes")
    @classmethod
    def _distinct(cls, modes: tuple[int, int]) -> tuple[int, int]:
        if modes[0] == modes[1]:
            raise ValueError(f"the two modes must differ, got [{modes[0]}, {modes[1]}]")
        return modes


class Building(Strict):
    """A shear-type building: floors listed from the bottom up, columns fixed at the ground
    (or on the base slab of an isolation system)."""

    name: Name
    """Building name, unique in the model; used as the HDF5 group name."""

    origin: tuple[Real, Real] = (0.0, 0.0)
    """Global plan position [X, Y] of the building's local origin, m."""

    rotation: Real = 0.0
    """Rotation of the building's local x axis from the global X axis, degrees,
    counter-clockwise."""

    place: Placement | None = None
    """Place the building beside a neighbour instead of at `origin`: a gap (m) clear of it on
    one of its sides, aligned as stated (give `place` or `origin`/`rotation`, not both)."""

    base_elevation: Annotated[Real, Field(ge=-1e4, le=1e4)] = 0.0
    """Elevation of the building's ground, m (positive up): the foot of its lowest storey
    (of its isolation storey, when isolated). It shifts all its levels, for sites on a slope
    or a building on a podium; the ground motion is the same for every building."""

    floors: Annotated[list[Floor], Field(min_length=1)]
    """Floors from the lowest up; each carries the storey of columns beneath it."""

    @field_validator("floors", mode="before")
    @classmethod
    def _entries_within_limit(cls, value: object) -> object:
        """More floor entries than the storey limit are refused before each is checked (each
        takes about a millisecond: a 50 MB file of them would take minutes)."""
        if isinstance(value, list) and len(value) > max_storeys():
            raise ValueError(f"{len(value)} floor entries: more than the limit of {max_storeys():.0f} storeys "
                             "(POUND_MAX_STOREYS)")  # fmt: skip
        return value

    damping: RayleighDamping = RayleighDamping()
    """Rayleigh damping of this building (of a base-isolated building: of its superstructure,
    see `isolation.damping_ratio` for the isolation system)."""

    isolation: Isolation | None = None
    """The isolation system of a base-isolated building (base slab on isolators, optional moat
    wall): the base slab becomes the building's lowest floor and the isolation storey its
    lowest storey; `floors` stand on the base slab. Absent: columns fixed at the ground."""

    slab_material: Name | None = None
    """Material of the floor slabs in [materials], for "auto" impact stiffness. Default:
    the columns' material when they all share one."""

    @model_validator(mode="after")
    def _column_lines_keep_position(self) -> "Building":
        seen: dict[str, tuple[float, float, int]] = {}
        for k, floor in enumerate(self.floors):
            for c in floor.all_columns():
                if c.name in seen:
                    x, y, k0 = seen[c.name]
                    if abs(x - c.x) > 1e-9 or abs(y - c.y) > 1e-9:
                        raise ValueError(
                            f"column {c.name} is at ({c.x:g}, {c.y:g}) m below floors[{k}] but "
                            f"at ({x:g}, {y:g}) m below floors[{k0}]; a column name denotes "
                            "one column line: give the moved column another name"
                        )
                else:
                    seen[c.name] = (c.x, c.y, k)
        return self

    def slab_material_name(self) -> str | None:
        """The slab material: given, or the one material all columns share (else None)."""
        if self.slab_material is not None:
            return self.slab_material
        used = {c.material for floor in self.floors for c in floor.all_columns()}
        return used.pop() if len(used) == 1 else None

    def storeys(self) -> list[Floor]:
        """The floors with `repeat` expanded: one entry per storey, bottom up."""
        return [floor for floor in self.floors for _ in range(floor.repeat)]
