"""Plot: hysteresis loops of a building's yielding members, force against deflection.

One panel per member: every isolator (up to :data:`MAX_ISOLATORS`, those that moved most),
and the inelastic columns chosen — the `--column`'s member in every storey, or without one the
most ductile column of each storey (of the :data:`MAX_COLUMNS` storeys that yielded most).
In each panel the member's shear force f (kN) against its deflection δ (mm) along its local x
and y axes, from /buildings/<name>/yielding/force and /deflection (at the output interval, so
a loop's corners are as sharp as the output interval allows), with the yield forces ±F_y of
each axis as dashed lines of the same colour.
The enclosed area of a loop is the energy the member dissipated along that axis.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .document import check_column, members_of
from .load import Run
from .style import colour, figure, grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MAX_ISOLATORS = 9
"""Isolator panels per figure at most (the largest peak displacements)."""
MAX_COLUMNS = 6
"""Column panels per figure at most without --column (one per storey, the storeys of the
largest peak ductilities)."""
PANELS_PER_ROW = 3
AXES = (("local x", 0), ("local y", 1))
"""(label, index) of the two local axes of a member: one series each per panel."""


def loop_buildings(run: Run) -> list[str]:
    """Names of the buildings of `run` with yielding members, in the file's order."""
    return [name for name, b in run.result.buildings.items() if b.yielding is not None and b.yielding.members.size]


def loop_members(b: Any, column: str | None = None) -> list[int]:
    """Indices (rows of yielding/members) of the members building `b`'s loop figure draws:
    isolators first, then the inelastic columns (module docstring)."""
    y = b.yielding
    if y is None:
        return []
    isolators = members_of(b, column, "isolator")
    if len(isolators) > MAX_ISOLATORS:
        isolators = sorted(sorted(isolators, key=lambda i: -y.peak[i, 2])[:MAX_ISOLATORS])
    columns = members_of(b, column, "column")
    if column is None:
        worst: dict[int, int] = {}
        for i in columns:
            s = int(y.members["storey"][i])
            if s not in worst or y.ductility[i].max() > y.ductility[worst[s]].max():
                worst[s] = i
        top = sorted(worst.values(), key=lambda i: -float(y.ductility[i].max()))[:MAX_COLUMNS]
        columns = sorted(top, key=lambda i: int(y.members["storey"][i]))
    return isolators + columns


def loop_figure(run: Run, building: str, column: str | None = None) -> Figure:
    """The hysteresis loops of `building`'s members (:func:`loop_members`), one panel each,
    three panels a row; a legend for the local axes and the yield lines below."""
    check_column(run, column)
    b = run.result.buildings[building]
    chosen = loop_members(b, column)
    y = b.yielding
    n = max(1, len(chosen))
    cols = min(PANELS_PER_ROW, n)
    rows = math.ceil(n / cols)
    fig = figure(3.3 * cols + 0.6, 2.7 * rows + 0.9)
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax in axes[len(chosen):]:
        ax.set_visible(False)
    if not chosen:
        axes[0].set_visible(True)
        axes[0].text(0.5, 0.5, "no yielding members", ha="center", va="center", transform=axes[0].transAxes)
    for ax, i in zip(axes, chosen):
        m = y.members[i]
        for label, k in AXES:
            ax.plot(1e3 * y.deflection[:, i, k], y.force[:, i, k] / 1e3, lw=0.7, color=colour(k), label=label)
        for label, k in AXES:
            fy = float(m["yield_force"][k]) / 1e3
            for sign in (1, -1):  # x and y dashes interleaved: both show where F_y,x = F_y,y
                ax.axhline(sign * fy, color=colour(k), ls=(4 * k, (4, 4)), lw=0.9,
                           label=f"±F_y {label}" if sign == 1 else None)  # fmt: skip
        mu = y.ductility[i]
        where = "isolator" if m["kind"] == "isolator" else f"storey {int(m['storey'])}"
        ax.set_title(f"{m['name']}, {where}: μ {mu[0]:.3g} / {mu[1]:.3g}", fontsize="small")
        ax.set_xlabel("deflection δ (mm)")
        ax.set_ylabel("force f (kN)")
        ax.axhline(0, color="0.5", lw=0.4)
        ax.axvline(0, color="0.5", lw=0.4)
    grid([ax for ax in axes if ax.get_visible()])
    if chosen:
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", ncols=4, fontsize="small")
    kinds = {str(y.members["kind"][i]) for i in chosen} if chosen else set()
    what = " and ".join(k + "s" for k in ("isolator", "column") if k in kinds) or "members"
    picked = f"column {column}" if column else "the most ductile of each storey"
    fig.suptitle(f"Hysteresis loops: {building}, {what}{f' ({picked})' if picked and 'column' in kinds else ''}; "
                 "member local axes, dashed: yield force ±F_y", fontsize="medium")  # fmt: skip
    return fig
