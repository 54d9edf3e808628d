"""`pound gap --plot FILE`: the approach history of the governing pair.

The gap the pair needs at each sample of the contact-free run (clear distance at rest +
σ*(t), gap.required) against time, with the clear distance at rest (the gap as built), the
required separation at the time of closest approach, and the code-style estimates ABS, SRSS
and DDC as levels beside it. Where the curve rises above the gap as built, the pair meets.
Lengths in mm, time in s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..report.style import colour, figure, grid
from .required import GapResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

ESTIMATES = (("abs", "ABS", ":"), ("srss", "SRSS", "--"), ("ddc", "DDC", "-."))


def pair_label(p) -> str:  # type: ignore[no-untyped-def]
    """'left floor 3 – right floor 3' (or '… right storey 2, ξ = 0.57')."""
    b = f"{p.body_b} storey {p.storey_b}, ξ = {p.xi:.2f}" if p.storey_b else (f"{p.body_b} floor {p.floor_b}" if p.floor_b else p.body_b)
    return f"{p.body_a} floor {p.floor_a} – {b}"


def approach_figure(result: GapResult, pair: int | None = None) -> "Figure":
    """The approach history of `pair` (default: the governing one)."""
    k = result.governing if pair is None else pair
    fig = figure(9.0, 4.2)
    ax = fig.subplots()
    if k is None:
        ax.text(0.5, 0.5, "no contact candidates", ha="center", va="center", transform=ax.transAxes)
        return fig
    p = result.pairs[k]
    ax.plot(result.time, 1e3 * result.approach[:, k], color=colour(0), lw=0.8, label="gap needed at t (contact off)")
    ax.axhline(1e3 * p.clear_distance, color="k", lw=1.0, label=f"gap at rest {1e3 * p.clear_distance:.4g} mm")
    for key, name, style in ESTIMATES:
        ax.axhline(1e3 * getattr(p, key), color="0.35", lw=0.8, ls=style, label=f"{name} {1e3 * getattr(p, key):.4g} mm")
    ax.plot([p.time], [1e3 * p.required], "o", color="tab:red",
            label=f"required {1e3 * p.required:.4g} mm at t = {p.time:.4f} s")  # fmt: skip
    ax.set_xlabel("time (s)")
    ax.set_ylabel("separation needed (mm)")
    ax.set_title(f"approach of {pair_label(p)} (along {p.direction[0]:+.3f}, {p.direction[1]:+.3f})", fontsize=10)
    ax.legend(loc="lower left", fontsize=8)
    grid(ax)
    return fig
