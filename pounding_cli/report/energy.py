"""Plot: the energy balance (/energy, relative-motion energies, kJ) against time (s).

Top: the energies the input went into, stacked (damping, hysteretic, contact, strain,
kinetic; a column that stays 0 is left out) under the input energy drawn as a line, so a
gap between the stack's top and the line is the balance error. Bottom: the balance error
input − (kinetic + strain + damping + hysteretic + contact) in % of the largest input.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .load import Run
from .style import colour, figure, grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure

STACKED = ("damping", "hysteretic", "contact", "strain", "kinetic")
"""Energy columns stacked, bottom up: the dissipated ones first, the oscillating ones on top."""


def energy_figure(run: Run) -> Figure:
    """Stack plot of the energies (kJ) under the input line, and the balance error (%)."""
    r = run.result
    fig = figure(8.0, 5.5)
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1])
    shown = [(name, r.energy_column(name) / 1e3) for name in STACKED if np.any(r.energy_column(name) != 0)]
    if shown:
        top.stackplot(r.time, *[v for _, v in shown], labels=[n for n, _ in shown],
                      colors=[colour(STACKED.index(n)) for n, _ in shown], alpha=0.8)  # fmt: skip
    top.plot(r.time, r.energy_column("input") / 1e3, color="k", lw=1.0, label="input")
    top.set_ylabel("energy (kJ)")
    top.legend(loc="upper left", fontsize="small")
    peak = np.abs(r.energy_column("input")).max(initial=0.0)
    error = 100 * r.energy_column("balance_error") / peak if peak > 0 else np.zeros_like(r.time)
    bottom.plot(r.time, error, color="k", lw=0.7, label="balance error")
    bottom.set_ylabel("error (% of max input)")
    bottom.set_xlabel("time (s)")
    grid([top, bottom])
    fig.suptitle(f"Energy balance: largest error {100 * r.balance_error_ratio:.3g} % of the largest input "
                 f"({peak / 1e3:.4g} kJ)", fontsize="medium")  # fmt: skip
    return fig
