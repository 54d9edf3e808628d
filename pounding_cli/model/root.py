"""The model file as a whole."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from .analysis import Analysis
from .base import Strict
from .building import Building, Name
from .excitation import Excitation
from .material import Material


class PoundModel(Strict):
    """A pound model: materials, buildings, excitation and analysis settings (SI units)."""

    title: str = ""
    """A one-line description of the model, shown in reports."""

    materials: Annotated[dict[Name, Material], Field(min_length=1)]
    """Materials by name, referred to by columns."""

    buildings: Annotated[list[Building], Field(min_length=1, max_length=1000)]
    """The buildings, each with its own floors, columns and damping."""

    excitation: Excitation
    """The ground motion."""

    analysis: Analysis = Analysis()
    """Duration, time step and output interval."""

    @model_validator(mode="after")
    def _names_resolve(self) -> "PoundModel":
        names = [b.name for b in self.buildings]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"building names repeat: {', '.join(dup)}")
        return self

    def unknown_materials(self) -> list[tuple[str, str]]:
        """(field path, material name) of every column whose material is not defined."""
        out = []
        for b, building in enumerate(self.buildings):
            for f, floor in enumerate(building.floors):
                path = f"buildings[{b}].floors[{f}]"
                if floor.column_grid and floor.column_grid.material not in self.materials:
                    out.append((f"{path}.column_grid.material", floor.column_grid.material))
                for c, col in enumerate(floor.columns):
                    if col.material not in self.materials:
                        out.append((f"{path}.columns[{c}].material", col.material))
        return out
