"""Plot: peak interstorey deflection against storey, the paper's figures 6 and 7.

Three panels: peak |Δu_x| (mm), |Δu_y| (mm) along the building's axes and the storey twist
|Δθ| (mrad), each against the storey number (1 = ground storey). One line per run and
building: the chosen column's values, or without a column the largest over each storey's
columns. Several runs on one figure compare cases, as the paper does.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

from .document import check_column, columns_of
from .load import Run
from .style import COMPONENTS, colour, figure, grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MARKERS = "osD^v<>ph*"


def profile_series(run: Run, column: str | None = None) -> list[tuple[str, np.ndarray]]:
    """(label, (n_storeys, 3) peak deflections m, m, rad) per building of `run`: the column
    `column` ("C9" or "left:C9") where the building has it, or each storey's largest."""
    out = []
    for name, b in run.result.buildings.items():
        if column is None:
            isd = b.interstorey_deflection
            values = np.full(isd.shape[1:], np.nan)
            present = ~np.isnan(isd).all(axis=0)
            values[present] = np.nanmax(np.where(np.isnan(isd), -np.inf, isd), axis=0)[present]
            out.append((f"{name} (largest over the columns)", values))
            continue
        for i in columns_of(b, column):
            out.append((f"{name} {b.column_names[i]}", b.interstorey_deflection[i]))
    return out


def storey_panels(axes, labels: Sequence[str], top: int) -> None:  # type: ignore[no-untyped-def]
    """Panels of peaks against storey 1 … top: x labelled "peak <label>" from 0, storeys up the y axis."""
    from matplotlib.ticker import MaxNLocator

    for ax, label in zip(axes, labels):
        ax.set_xlabel(f"peak {label}")
        ax.set_xlim(left=0)
        ax.xaxis.set_major_locator(MaxNLocator(5))
    axes[0].set_ylabel("storey")
    axes[0].set_yticks(np.arange(1, top + 1))
    axes[0].set_ylim(0.5, top + 0.5)
    grid(axes)


def profile_figure(runs: Sequence[Run], column: str | None = None) -> Figure:
    """The three profiles of every run in `runs` on one figure; legend: run label and
    building (and column)."""
    for run in runs:
        check_column(run, column)
    fig = figure(9.0, 4.2)
    axes = fig.subplots(1, 3, sharey=True)
    top = 1
    k = 0
    for run in runs:
        for label, values in profile_series(run, column):
            storeys = np.arange(1, values.shape[0] + 1)
            top = max(top, storeys[-1])
            name = f"{run.label}: {label}" if len(runs) > 1 else label
            for c, (ax, (_, _, factor)) in enumerate(zip(axes, COMPONENTS)):
                ax.plot(factor * values[:, c], storeys, marker=MARKERS[k % len(MARKERS)], ms=4, lw=1.0,
                        color=colour(k), label=name)  # fmt: skip
            k += 1
    storey_panels(axes, [label for _, label, _ in COMPONENTS], top)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=min(3, max(1, len(labels))), fontsize="small")
    what = f"column {column}" if column else "largest over the columns"
    fig.suptitle(f"Peak interstorey deflection per storey ({what}; building axes)", fontsize="medium")
    return fig
