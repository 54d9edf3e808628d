"""The plot of ``pound record --plot``: acceleration, velocity, displacement and the spectrum.

Four panels, one line per component: ground acceleration (g), velocity (m/s) and
displacement (m) against time (s), integrated as :mod:`.metrics` says, and the 5 %-damped
pseudo-spectral acceleration PSA (g) against period (s, logarithmic) from :mod:`.spectrum`.
The figure is a bare :class:`matplotlib.figure.Figure` drawn by the Agg canvas: no display,
no pyplot state.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pounding_cli.atomic import atomic_path
from pounding_cli.errors import InputError
from pounding_cli.records.inspect import RecordData
from pounding_cli.records.metrics import G, integrate
from pounding_cli.records.spectrum import DAMPING, DEFAULT_PERIODS, pseudo_acceleration

if TYPE_CHECKING:
    from matplotlib.figure import Figure

FORMATS = ("png", "pdf", "svg")
"""File types --plot writes, by the file's suffix."""

LABELS = {
    "acceleration": "acceleration (g)",
    "velocity": "velocity (m/s)",
    "displacement": "displacement (m)",
    "time": "time (s)",
    "period": "period (s)",
    "psa": f"PSA, {100 * DAMPING:g} % damping (g)",
}


def record_figure(data: RecordData, periods: np.ndarray = DEFAULT_PERIODS) -> Figure:
    """The four-panel figure of `data` (axes in the order acceleration, velocity,
    displacement, spectrum)."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(8.0, 10.0), layout="constrained")
    axes = figure.subplots(4, 1)
    for ax in axes[1:3]:  # the three time histories share the time axis
        ax.sharex(axes[0])
    for c in data.components:
        velocity, displacement = integrate(c.acceleration, c.dt)
        time = c.time
        axes[0].plot(time, c.acceleration / G, lw=0.7, label=c.name)
        axes[1].plot(time, velocity, lw=0.8, label=c.name)
        axes[2].plot(time, displacement, lw=0.8, label=c.name)
        axes[3].plot(periods, pseudo_acceleration(c.acceleration, c.dt, periods) / G, lw=1.0, label=c.name)
    for ax, quantity in zip(axes[:3], ("acceleration", "velocity", "displacement")):
        ax.set_xlabel(LABELS["time"])
        ax.set_ylabel(LABELS[quantity])
    axes[3].set_xscale("log")
    axes[3].set_xlabel(LABELS["period"])
    axes[3].set_ylabel(LABELS["psa"])
    for ax in axes:
        ax.grid(True, lw=0.3)
        ax.legend(loc="upper right", fontsize="small")
    figure.suptitle(data.metadata.get("name") or data.source.name)
    return figure


def save_figure(figure: Figure, path: str | Path) -> None:
    """Write `figure` to `path` (.png, .pdf or .svg), atomically; InputError naming the file
    otherwise."""
    path = Path(path)
    kind = path.suffix.lower().lstrip(".")
    if kind not in FORMATS:
        raise InputError(f"cannot write a {path.suffix or 'suffix-less'} plot; name a .png, .pdf or .svg file", file=path)
    if not path.parent.is_dir():
        raise InputError(f"the folder {str(path.parent)!r} does not exist; create it first", file=path)
    if path.is_dir():
        raise InputError("is a folder; give a file name for the plot, e.g. record.png", file=path)
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format=kind, dpi=120)
