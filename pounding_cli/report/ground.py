"""Plot: the ground acceleration the run applied, along global X and Y (g) against time (s),
with the impact times of the log marked."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .document import G
from .load import Run
from .style import figure, grid, mark_impacts

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def ground_figure(run: Run) -> Figure:
    """Two panels sharing the time axis: a_X and a_Y (g) from /ground/acceleration (after θ
    and the scale), at the output instants."""
    r = run.result
    fig = figure(8.0, 4.5)
    axes = fig.subplots(2, 1, sharex=True)
    events = r.contact.events["t_peak"]
    for k, (ax, name) in enumerate(zip(axes, ("X", "Y"))):
        a = r.ground_acceleration[:, k] / G
        ax.plot(r.time, a, lw=0.7, color="k", label=f"a_{name}, PGA {np.abs(a).max(initial=0.0):.3f} g")
        ax.set_ylabel(f"a_{name} (g)")
        if events.size:
            mark_impacts(ax, events)
        ax.legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time (s)")
    grid(axes)
    e = run.model.get("excitation", {})
    rec = e.get("record", "")
    name = rec.get("name", "") if isinstance(rec, dict) else str(rec)
    fig.suptitle(f"Ground acceleration (global axes): {name or 'record'}, θ = {e.get('angle', 0):g}°", fontsize="medium")
    return fig
