"""Every plot of a report, drawn and written into a folder (``pound report --plots DIR``).

One run: ``ground``, ``displacement``, ``profiles``, ``storey_shear``, ``impacts``, ``energy``
and ``plan`` (.png, .svg or .pdf), and ``<building>-loops`` for each building with yielding
members (inelastic columns, isolators) to draw. Several runs: each run's plots prefixed with its
label (``<label>-ground.png``, ...) and one ``profiles`` and one ``storey_shear`` figure
comparing them all.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from ..errors import InputError
from .energy import energy_figure
from .ground import ground_figure
from .histories import Floor, displacement_figure
from .impacts import impact_figure
from .load import Run
from .loops import loop_buildings, loop_figure, loop_members
from .plan import plan_figure
from .profiles import profile_figure
from .shear_profiles import shear_figure
from .style import FORMATS, save_as

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def run_figures(
    run: Run, column: str | None = None, floors: Sequence[Floor] | None = None, magnify: float | None = None
) -> dict[str, Callable[[], Figure]]:
    """Name → a function drawing that figure, for one run (drawn one at a time, so that a
    long report does not hold every figure in memory)."""
    out: dict[str, Callable[[], Figure]] = {
        "ground": lambda: ground_figure(run),
        "displacement": lambda: displacement_figure(run, floors),
        "profiles": lambda: profile_figure([run], column),
        "storey_shear": lambda: shear_figure([run]),
        "impacts": lambda: impact_figure(run),
        "energy": lambda: energy_figure(run),
        "plan": lambda: plan_figure(run, magnify),
    }
    for name in loop_buildings(run):
        if loop_members(run.result.buildings[name], column):
            out[f"{name.replace('/', '-')}-loops"] = lambda name=name: loop_figure(run, name, column)
    return out


def all_figures(
    runs: Sequence[Run], column: str | None = None, floors: Sequence[Floor] | None = None, magnify: float | None = None
) -> dict[str, Callable[[], Figure]]:
    """File stem → figure function for a report on `runs` (see the module's docstring)."""
    if len(runs) == 1:
        return run_figures(runs[0], column, floors, magnify)
    out: dict[str, Callable[[], Figure]] = {"profiles": lambda: profile_figure(runs, column),
                                            "storey_shear": lambda: shear_figure(runs)}  # fmt: skip
    for run in runs:
        for name, draw in run_figures(run, column, floors, magnify).items():
            if name not in out:
                out[f"{run.label.replace('/', '-')}-{name}"] = draw
    return out


def write_plots(
    runs: Sequence[Run], folder: str | Path, fmt: str = "png", column: str | None = None,
    floors: Sequence[Floor] | None = None, magnify: float | None = None,
) -> list[Path]:  # fmt: skip
    """Draw every figure of the report and write it into `folder` (created if missing, its
    parent must exist) as `fmt` (png, svg or pdf); returns the files written."""
    folder = Path(folder)
    if fmt not in FORMATS:
        raise InputError(f"unknown plot format {fmt!r}; choose one of {', '.join(FORMATS)}", field="--format")
    if folder.exists() and not folder.is_dir():
        raise InputError("is a file; --plots names a folder to write the plots into", file=folder)
    if not folder.parent.is_dir():
        raise InputError(f"the folder {str(folder.parent)!r} does not exist; create it first", file=folder)
    folder.mkdir(exist_ok=True)
    return [save_as(draw(), folder, stem, fmt) for stem, draw in all_figures(runs, column, floors, magnify).items()]
