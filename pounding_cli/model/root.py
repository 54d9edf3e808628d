"""The model file as a whole."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from .analysis import Analysis
from .base import Strict
from .base import Name
from .building import Building
from .contact import Contact, Obstacle
from .excitation import Excitation
from .material import Material


class PoundModel(Strict):
    """A pound model: materials, buildings, excitation and analysis settings (SI units)."""

    title: str = ""
    """A one-line description of the model, printed by validate and stored with the results."""

    materials: Annotated[dict[Name, Material], Field(min_length=1)]
    """Materials by name, referred to by columns."""

    buildings: Annotated[list[Building], Field(min_length=1, max_length=1000)]
    """The buildings, each with its own floors, columns and damping."""

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
        for b, building in enumerate(self.buildings):
            for f, floor in enumerate(building.floors):
                path = f"buildings[{b}].floors[{f}]"
                used = [(f"{path}.columns[{c}].material", col.material) for c, col in enumerate(floor.columns)]
                if floor.column_grid is not None:
                    used.insert(0, (f"{path}.column_grid.material", floor.column_grid.material))
                out += [(field, f"unknown material {name!r}; defined: {defined}")
                        for field, name in used if name not in self.materials]  # fmt: skip
            if building.slab_material is not None and building.slab_material not in self.materials:
                out.append((f"buildings[{b}].slab_material", f"unknown material {building.slab_material!r}; "
                            f"defined: {defined}"))  # fmt: skip
        for o, obstacle in enumerate(self.obstacles):
            if obstacle.material not in self.materials:
                out.append((f"obstacles[{o}].material", f"unknown material {obstacle.material!r}; defined: {defined}"))
        return out
