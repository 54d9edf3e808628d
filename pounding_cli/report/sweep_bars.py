"""Plot: grouped bars comparing named cases of a sweep, the paper's figures 6 and 7 as bars.

Three panels, peak |Δu_x| and |Δu_y| (mm, building axes) and |Δθ| (mrad); along the x axis
the storeys of one column ("left:C9", from the summary's per-storey columns), or without a
column the buildings (each one's largest); one bar per case in each group.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from .style import colour, figure, grid
from .sweep_data import Sweep, column_names

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MAX_CASES = 12
"""Most cases a bar chart compares by default (one per study at most this size)."""
SUFFIXES = ("x_m", "y_m", "theta_rad")
LABELS = ("peak Δx (mm)", "peak Δy (mm)", "peak Δθ (mrad)")


def default_case_groups(sweep: Sweep) -> list[tuple[str, list[dict[str, Any]]]]:
    """(study, rows) of every study with at most :data:`MAX_CASES` cases."""
    studies: dict[str, list[dict[str, Any]]] = {}
    for r in sweep.rows:
        studies.setdefault(r["study"], []).append(r)
    return [(s, rows) for s, rows in studies.items() if len(rows) <= MAX_CASES]


def cases_figure(sweep: Sweep, rows: Sequence[dict[str, Any]], column: str | None = None, title: str = "") -> Figure:
    """Bars of `rows` (summary rows) side by side: per storey of `column`, or per building."""
    if column:
        per_building = column_names(sweep, column)
        groups = [(f"{b} storey {s + 1}" if len(per_building) > 1 else f"storey {s + 1}", names)
                  for b, storeys in per_building.items() for s, names in enumerate(storeys)]  # fmt: skip
    else:
        buildings = [n[len("peak_isd_x_m["):-1] for n in sweep.names("result")
                     if n.startswith("peak_isd_x_m[") and "/" not in n]  # fmt: skip
        groups = [(b, [f"peak_isd_{s}[{b}]" for s in SUFFIXES]) for b in buildings]
    fig = figure(min(12.0, max(8.0, 0.3 * len(groups) * max(1, len(rows)) + 2.0)), 8.0)
    axes = fig.subplots(3, 1, sharex=True)
    width = 0.8 / max(1, len(rows))
    where = np.arange(len(groups))
    for i, row in enumerate(rows):
        for k, ax in enumerate(axes):
            values = [np.nan if row[names[k]] is None else 1e3 * row[names[k]] for _, names in groups]
            ax.bar(where - 0.4 + (i + 0.5) * width, values, width, color=colour(i), label=sweep.label(row))
    for ax, label in zip(axes, LABELS):
        ax.set_ylabel(label)
    axes[-1].set_xticks(where, [g for g, _ in groups])
    grid(axes)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=min(2, max(1, len(labels))), fontsize="small")
    what = f"column {column}, per storey" if column else "largest per building"
    fig.suptitle(f"{title or sweep.title}\npeak interstorey deflection ({what}; building axes)", fontsize="medium")
    return fig
