"""Plot: displacement time histories of chosen floors (u_x, u_y in mm, θ_z in mrad; global
axes, relative to the ground, at each floor's mass centre), impact times marked."""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from ..errors import InputError
from .load import Run
from .style import DISPLACEMENTS, colour, figure, grid, mark_impacts

if TYPE_CHECKING:
    from matplotlib.figure import Figure

Floor = tuple[str, int]
"""(building name, floor number 1-based from the bottom)."""


def parse_floor(text: str) -> Floor:
    """"left:4" → ("left", 4); "left" → ("left", 0), where 0 stands for the roof."""
    name, _, level = text.rpartition(":")
    if not name:
        return text, 0
    try:
        return name, int(level)
    except ValueError:
        raise InputError(f"expected building:floor such as left:4, got {text!r}", field="--floor") from None


def resolve_floors(run: Run, floors: Sequence[Floor] | None) -> list[Floor]:
    """The floors to plot: as given (0 = roof), or the roof of every building."""
    buildings = run.result.buildings
    if not floors:
        return [(name, b.elevation.size) for name, b in buildings.items()]
    out = []
    for name, level in floors:
        if name not in buildings:
            raise InputError(f"no building {name!r}; buildings: {', '.join(buildings)}", file=run.path, field="--floor")
        n = buildings[name].elevation.size
        level = level or n
        if not 1 <= level <= n:
            raise InputError(f"building {name!r} has floors 1 to {n}, not {level}", file=run.path, field="--floor")
        out.append((name, level))
    return out


def displacement_figure(run: Run, floors: Sequence[Floor] | None = None) -> Figure:
    """Three panels sharing the time axis (u_x, u_y, θ_z), one line per floor; `floors` as
    (building, floor) pairs, default the roof of each building."""
    r = run.result
    chosen = resolve_floors(run, floors)
    fig = figure(8.0, 6.5)
    axes = fig.subplots(3, 1, sharex=True)
    for i, (name, level) in enumerate(chosen):
        u = r.buildings[name].displacement[:, level - 1, :]
        for k, (ax, (_, factor)) in enumerate(zip(axes, DISPLACEMENTS)):
            ax.plot(r.time, factor * u[:, k], lw=0.7, color=colour(i), label=f"{name} floor {level}")
    for ax, (label, _) in zip(axes, DISPLACEMENTS):
        ax.set_ylabel(label)
        if r.contact.events.size:
            mark_impacts(ax, r.contact.events["t_peak"])
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time (s)")
    grid(axes)
    fig.suptitle("Floor displacements at the mass centre (global axes, relative to the ground)", fontsize="medium")
    return fig
