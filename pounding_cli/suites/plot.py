"""The pounding fragility plot (`pound gap --suite --plot`, `pound report gap-suite.h5`).

Per pair, the probability that a record of the suite makes it meet at a gap g (mm): the
empirical curve (a step down at each case's required separation) and the lognormal fit
(suites.fragility), with the gap as built marked. One colour per pair.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..report.style import colour, figure, grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def pair_name(row: Any) -> str:
    """'left floor 3 – right floor 3' from a pair row (dict or structured row)."""
    body_b = str(row["body_b"].decode() if isinstance(row["body_b"], bytes) else row["body_b"])
    body_a = str(row["body_a"].decode() if isinstance(row["body_a"], bytes) else row["body_a"])
    b = (f"{body_b} storey {int(row['storey_b'])}" if int(row["storey_b"])
         else f"{body_b} floor {int(row['floor_b'])}" if int(row["floor_b"]) else body_b)  # fmt: skip
    return f"{body_a} floor {int(row['floor_a'])} – {b}"


def fragility_figure(pairs: Any, gaps: np.ndarray, empirical: np.ndarray, fit: np.ndarray, title: str = "") -> "Figure":
    """The fragility curves of every pair (rows `pairs`, curves (ng, n_pairs))."""
    fig = figure(8.0, 4.6)
    ax = fig.subplots()
    for j, row in enumerate(pairs):
        c = colour(j)
        ax.step(1e3 * gaps, empirical[:, j], where="post", color=c, lw=1.0, alpha=0.8,
                label=f"{pair_name(row)}: records")  # fmt: skip
        ax.plot(1e3 * gaps, fit[:, j], color=c, lw=1.6, ls="--", label="lognormal fit")
        ax.axvline(1e3 * float(row["clear_distance"]), color=c, lw=0.8, ls=":")
    ax.set_xlabel("gap (mm)")
    ax.set_ylabel("probability of pounding")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(0, 1e3 * float(gaps[-1]))
    ax.set_title(title or "pounding fragility (dotted: the gap as built)", fontsize=10)
    ax.legend(loc="upper right", fontsize=7)
    grid(ax)
    return fig
