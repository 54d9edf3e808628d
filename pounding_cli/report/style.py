"""What every report figure shares: a bare Agg figure, colours, units, the impact marks.

Figures are :class:`matplotlib.figure.Figure` objects with no pyplot state (as in
:mod:`pounding_cli.records.plot`), saved by :func:`save_figure`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from ..records.plot import FORMATS, save_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["FORMATS", "COMPONENTS", "colour", "figure", "save_figure", "save_as"]

COMPONENTS = (
    ("x", "Δx (mm)", 1e3),
    ("y", "Δy (mm)", 1e3),
    ("θ", "Δθ (mrad)", 1e3),
)
"""(name, axis label, factor from SI) of the three interstorey deflection components."""

DISPLACEMENTS = (
    ("u_x (mm)", 1e3),
    ("u_y (mm)", 1e3),
    ("θ_z (mrad)", 1e3),
)
"""(axis label, factor from m, m, rad) of a floor's displacement components."""

IMPACT_COLOUR = "tab:red"


def figure(width: float, height: float) -> Figure:
    """An empty figure of `width` × `height` inches with constrained layout."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def colour(i: int) -> str:
    """The i-th colour of the tab10 cycle (buildings, runs)."""
    return f"C{i % 10}"


def grid(axes: Axes | Sequence[Axes]) -> None:
    """Light grid lines on every axes."""
    import numpy as np

    for ax in np.atleast_1d(axes).ravel():
        ax.grid(True, lw=0.3)


def mark_impacts(ax: Axes, times: Any, label: str | None = "impacts (log)") -> None:
    """Thin vertical lines at the impact peak times `times` (s), one legend entry."""
    for k, t in enumerate(times):
        ax.axvline(float(t), color=IMPACT_COLOUR, lw=0.6, alpha=0.5, label=label if k == 0 else None)


def save_as(fig: Figure, folder: Path, stem: str, fmt: str) -> Path:
    """Save `fig` as folder/stem.fmt and return the path."""
    path = Path(folder) / f"{stem}.{fmt}"
    save_figure(fig, path)
    return path
