"""The model file as a whole."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from .analysis import Analysis
from .base import Name, Strict, Text
from .building import Building
from .contact import Contact, Obstacle
from .excitation import Excitation
from .inelastic import Bearing, Hysteresis, moat_wall_polygons
from .material import Material
from .placement import placement_problems


class PoundModel(Strict):
    """A pound model: materials, buildings, excitation and analysis settings (SI units)."""

    title: Text = ""
    """A one-line description of the model, printed by validate and stored with the results."""

    materials: Annotated[dict[Name, Material], Field(min_length=1)]
    """Materials by name, referred to by columns."""

    hysteresis: dict[Name, Hysteresis] = {}
    """Hysteretic laws of inelastic columns by name, referred to by columns."""

    bearings: dict[Name, Bearing] = {}
    """Isolation bearing types by name, referred to by isolators."""

    buildings: Annotated[list[Building], Field(min_length=1, max_length=100_000)]
    """The buildings, each with its own floors, columns and damping (a district of thousands runs
    as its independent groups: `pound run --jobs` or `--scheduler`)."""

    excitation: Excitation
    """The ground motion."""

    analysis: Analysis = Analysis()
    """Duration, time step and output interval."""

    contact: Contact = Contact()
    """Pounding: impact stiffness, friction, dashpots."""

    obstacles: Annotated[list[Obstacle], Field(max_length=10_000)] = []
    """Fixed rigid bodies that floors can hit (walls, moat walls)."""

    def cross_reference_problems(self) -> list[tuple[str, str]]:
        """(field path, message) for names that repeat or refer to nothing."""
        out = []
        first: dict[str, str] = {}
        bodies = [(f"buildings[{b}]", x.name) for b, x in enumerate(self.buildings)]
        bodies += [(f"obstacles[{o}]", x.name) for o, x in enumerate(self.obstacles)]
        for path, name in bodies:
            if name in first:
                out.append((f"{path}.name", f"name {name!r} is already used by {first[name]}; "
                            "building and obstacle names must be unique"))  # fmt: skip
            first.setdefault(name, path)
        defined = ", ".join(self.materials)
        out += [(field, f"unknown material {name!r}; defined: {defined}")
                for field, name in self._column_references("material") if name not in self.materials]  # fmt: skip
        for b, building in enumerate(self.buildings):
            if building.slab_material is not None and building.slab_material not in self.materials:
                out.append((f"buildings[{b}].slab_material", f"unknown material {building.slab_material!r}; "
                            f"defined: {defined}"))  # fmt: skip
        for o, obstacle in enumerate(self.obstacles):
            if obstacle.material not in self.materials:
                out.append((f"obstacles[{o}].material", f"unknown material {obstacle.material!r}; defined: {defined}"))
        return out + placement_problems(self.buildings) + self._yielding_problems(first)

    def _column_references(self, key: str) -> list[tuple[str, str | None]]:
        """(field path, value) of `key` ("material" or "hysteresis") on every column grid and
        column, floor by floor."""
        used: list[tuple[str, str | None]] = []
        for b, building in enumerate(self.buildings):
            for f, floor in enumerate(building.floors):
                path = f"buildings[{b}].floors[{f}]"
                if floor.column_grid is not None:
                    used.append((f"{path}.column_grid.{key}", getattr(floor.column_grid, key)))
                used += [(f"{path}.columns[{c}].{key}", getattr(col, key)) for c, col in enumerate(floor.columns)]
        return used

    def _yielding_problems(self, bodies: dict[str, str]) -> list[tuple[str, str]]:
        """Unknown hysteretic laws, bearings and moat materials; moat names that clash."""
        out = []
        laws = ", ".join(self.hysteresis) or "none"
        bearings = ", ".join(self.bearings) or "none"
        out += [(field, f"unknown hysteretic law {name!r}; defined in [hysteresis]: {laws}")
                for field, name in self._column_references("hysteresis")
                if name is not None and name not in self.hysteresis]  # fmt: skip
        for b, building in enumerate(self.buildings):
            iso = building.isolation
            if iso is None:
                continue
            path = f"buildings[{b}].isolation"
            used = [(f"{path}.isolators[{i}].bearing", x.bearing) for i, x in enumerate(iso.isolators)]
            if iso.isolator_grid is not None:
                used.insert(0, (f"{path}.isolator_grid.bearing", iso.isolator_grid.bearing))
            out += [(field, f"unknown bearing {name!r}; defined in [bearings]: {bearings}")
                    for field, name in used if name not in self.bearings]  # fmt: skip
            if iso.moat is not None:
                if iso.moat.material not in self.materials:
                    out.append((f"{path}.moat.material", f"unknown material {iso.moat.material!r}; "
                                f"defined: {', '.join(self.materials)}"))  # fmt: skip
                for o in self._moat_walls(building):
                    if o.name in bodies:
                        out.append((f"{path}.moat", f"its wall segments are named {o.name!r}…, which "
                                    f"{bodies[o.name]} already uses"))  # fmt: skip
                        break
        return out

    def all_obstacles(self) -> list[Obstacle]:
        """The obstacles given, then the moat wall segments of isolated buildings."""
        return list(self.obstacles) + [o for b in self.buildings for o in self._moat_walls(b)]

    @staticmethod
    def _moat_walls(building: Building) -> list[Obstacle]:
        """Wall segments "<building>.moat<k>" around the base slab, at its elevation."""
        iso = building.isolation
        if iso is None or iso.moat is None:
            return []
        import math

        phi = math.radians(building.rotation)
        c, s = math.cos(phi), math.sin(phi)
        ox, oy = building.origin
        plan = [(ox + c * x - s * y, oy + s * x + c * y) for x, y in iso.slab]
        moat = iso.moat
        overrides = moat.overrides()
        return [
            Obstacle(name=f"{building.name}.moat{k + 1}", polygon=wall, elevation=iso.height, material=moat.material,
                     **overrides)  # fmt: skip
            for k, wall in enumerate(moat_wall_polygons(plan, moat.gap, moat.thickness))
        ]
