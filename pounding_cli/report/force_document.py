"""The forces of a building in the report document (`pound report --json`): its peak storey
shears, base shear and column forces (results/forces.py: components, signs and axes)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .document_model import _Output


class StoreyShear(_Output):
    """Peak storey shears of one storey: each component's own peak over the run."""

    storey: int
    """Storey number, 1 = ground storey (an isolated building's isolation storey)."""
    x_N: float
    """Peak |V_x|, along the building's x axis, N."""
    y_N: float
    """Peak |V_y|, along the building's y axis, N."""
    torque_Nm: float
    """Peak |T| about the mass centre of the floor above (at rest), N·m."""
    X_N: float
    """Peak |V_X|, along global X, N."""
    Y_N: float
    """Peak |V_Y|, along global Y, N."""
    torque_origin_Nm: float
    """Peak |T_O| about the global origin, N·m."""
    column_shear_N: float | None
    """The largest peak column shear of the storey, either local axis, N; null without columns (an isolation storey)."""
    column: str | None
    """The column where column_shear_N occurs."""


class ColumnForces(_Output):
    """One column line's peak forces in every storey."""

    name: str
    """Column name."""
    shear_N: list[list[float | None]]
    """Per storey from the ground up: peak |V| along the column's local x, y, N; null where the column is absent."""
    moment_Nm: list[list[float | None]]
    """The same for the end moments |M| = |V|·h/2 (fixed at both ends), N·m: [x] from the shear along local x."""


class ForceReport(_Output):
    """A building's peak forces (/buildings/<name>/peaks: storey_shear, base_shear, column_shear, column_moment)."""

    base_shear: StoreyShear
    """The base shear: the shear of the storey on the ground (storey 1)."""
    storeys: list[StoreyShear]
    """Every storey, from the ground up."""
    max_column_shear_N: float | None
    """The largest peak column shear over all columns, storeys and local axes, N."""
    max_column: str | None
    """The column where max_column_shear_N occurs."""
    max_column_storey: int | None
    """The storey where max_column_shear_N occurs."""
    columns: list[ColumnForces]
    """Every column line, or only the one asked for with --column."""


def _nullable(values: np.ndarray) -> list[float | None]:
    return [None if not math.isfinite(v) else float(v) for v in np.asarray(values, dtype=float).ravel()]


def _storey(f: Any, names: list[str], s: int) -> StoreyShear:
    x, y, t, gx, gy, t0 = (float(v) for v in f.peak_storey_shear[s])
    shear = np.nanmax(np.where(np.isnan(f.peak_column_shear[:, s]), -np.inf, f.peak_column_shear[:, s]), axis=1) \
        if names else np.zeros(0)  # fmt: skip
    present = np.isfinite(shear)
    c = int(np.argmax(np.where(present, shear, -np.inf))) if present.any() else -1
    return StoreyShear(storey=s + 1, x_N=x, y_N=y, torque_Nm=t, X_N=gx, Y_N=gy, torque_origin_Nm=t0,
                       column_shear_N=float(shear[c]) if c >= 0 else None, column=names[c] if c >= 0 else None)  # fmt: skip


def force_report(b: Any, columns: list[int]) -> ForceReport | None:
    """Building `b`'s (a results BuildingResult) peak forces; `columns`: the column lines to list."""
    f = b.forces
    if f is None:
        return None
    storeys = [_storey(f, b.column_names, s) for s in range(f.peak_storey_shear.shape[0])]
    shear = f.peak_column_shear
    worst = None
    if shear.size and not np.isnan(shear).all():
        worst = np.unravel_index(np.nanargmax(shear), shear.shape)
    return ForceReport(
        base_shear=storeys[0],
        storeys=storeys,
        max_column_shear_N=float(shear[worst]) if worst else None,
        max_column=b.column_names[worst[0]] if worst else None,
        max_column_storey=int(worst[1]) + 1 if worst else None,
        columns=[ColumnForces(name=b.column_names[i], shear_N=[_nullable(v) for v in shear[i]],
                              moment_Nm=[_nullable(v) for v in f.peak_column_moment[i]]) for i in columns],  # fmt: skip
    )
