"""Plot: peak storey shear against storey, the force counterpart of profiles.py.

Three panels: peak |V_x|, |V_y| (kN) along the building's axes and the peak storey torque |T|
(kN·m) about the mass centre of the floor above, each against the storey (1 = ground storey,
whose shear is the base shear). One line per run and building; several runs on one figure
compare cases. Buildings of a file written before pound stored forces are left out.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

from .load import Run
from .profiles import MARKERS, storey_panels
from .style import colour, figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PANELS = (("V_x (kN)", 0), ("V_y (kN)", 1), ("T (kN·m)", 2))
"""(axis label, component of peak_storey_shear) of each panel."""


def shear_figure(runs: Sequence[Run]) -> Figure:
    """The three storey-shear profiles of every run in `runs` on one figure."""
    fig = figure(9.0, 4.2)
    axes = fig.subplots(1, 3, sharey=True)
    top, k = 1, 0
    for run in runs:
        for name, b in run.result.buildings.items():
            if b.forces is None:
                continue
            peaks = b.forces.peak_storey_shear / 1e3
            storeys = np.arange(1, peaks.shape[0] + 1)
            top = max(top, storeys[-1])
            label = f"{run.label}: {name}" if len(runs) > 1 else name
            for ax, (_, c) in zip(axes, PANELS):
                ax.plot(peaks[:, c], storeys, marker=MARKERS[k % len(MARKERS)], ms=4, lw=1.0, color=colour(k),
                        label=label)  # fmt: skip
            k += 1
    storey_panels(axes, [label for label, _ in PANELS], top)
    handles, labels = axes[0].get_legend_handles_labels()
    if labels:
        fig.legend(handles, labels, loc="outside lower center", ncols=min(3, len(labels)), fontsize="small")
    fig.suptitle("Peak storey shear per storey (storey 1: the base shear; building axes, torque about the floor "
                 "above's mass centre)", fontsize="medium")  # fmt: skip
    return fig
