"""What slab–storey impacts put into the struck columns, in the report document (`pound
report --json`) and its table: per struck column, the largest of its rows of
/impacts/column_demand (results/column_demand.py: shares, fixed-end forces, signs and axes),
with its demand/capacity ratio against `shear_capacity`, flagged at 1 or more."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .document_model import _Output
from .tables import TableSpec


class StruckColumn(_Output):
    """One column struck between its floors by a neighbour's slab, over the run."""

    building: str
    """The struck building."""
    column: str
    """The column's name."""
    storey: int
    """The storey struck (1-based)."""
    xi: float
    """Where along its height, (z − z_below)/h."""
    impacts: int
    """Impacts that struck it."""
    impact_shear_N: float
    """The largest |shear| an impact put into it on its own (either end, either local axis), N."""
    impact_moment_Nm: float
    """The largest end moment an impact put into it on its own, N·m."""
    shear_N: float
    """The largest |shear| at either end, the storey's drift included, either local axis, N."""
    capacity_N: list[float] | None
    """Its shear_capacity [V_x, V_y], N; null where the model gives none."""
    ratio: float | None
    """The largest demand/capacity (|shear| / capacity over both ends and local axes); null without a capacity."""
    exceeds: bool
    """ratio ≥ 1: the impact's shear reaches the column's capacity."""


def struck_columns(demand: np.ndarray) -> list[StruckColumn]:
    """StruckColumn of every (building, column, storey) in the rows of /impacts/column_demand."""
    out = []
    keys = sorted({(str(r["building"]), str(r["column"]), int(r["storey"])) for r in demand})
    for building, column, storey in keys:
        rows = demand[(demand["building"] == building) & (demand["column"] == column) & (demand["storey"] == storey)]
        impact = np.abs(np.stack([rows[f"impact_shear_{e}_{a}"] for e in ("bottom", "top") for a in "xy"]))
        whole = np.abs(np.stack([rows[f"shear_{e}_{a}"] for e in ("bottom", "top") for a in "xy"]))
        ratio = float(np.max(rows["ratio"])) if np.all(np.isfinite(rows["ratio"])) else None
        capacity = [float(rows["capacity_x"][0]), float(rows["capacity_y"][0])]
        out.append(StruckColumn(
            building=building, column=column, storey=storey, xi=float(rows["xi"][0]), impacts=int(rows.size),
            impact_shear_N=float(impact.max()), shear_N=float(whole.max()),
            impact_moment_Nm=float(max(rows["impact_moment_bottom"].max(), rows["impact_moment_top"].max())),
            capacity_N=capacity if all(math.isfinite(c) for c in capacity) else None, ratio=ratio,
            exceeds=ratio is not None and ratio >= 1.0,
        ))  # fmt: skip
    return out


def demand_table(doc: dict[str, Any]) -> list[TableSpec]:
    """The struck columns' table (none without slab–storey impacts)."""
    rows = []
    for c in doc["impacts"].get("struck_columns") or []:
        ratio = "-" if c["ratio"] is None else f"{c['ratio']:.3g}" + (" ≥ 1 !" if c["exceeds"] else "")
        capacity = "-" if c["capacity_N"] is None else " / ".join(f"{v / 1e3:.4g}" for v in c["capacity_N"])
        rows.append([c["building"], c["column"], str(c["storey"]), f"{c['xi']:.3f}", str(c["impacts"]),
                     f"{c['impact_shear_N'] / 1e3:.4g}", f"{c['impact_moment_Nm'] / 1e3:.4g}", f"{c['shear_N'] / 1e3:.4g}",
                     capacity, ratio])  # fmt: skip
    if not rows:
        return []
    return [TableSpec("Columns struck between floors (slab–storey impacts): the largest over the run; demand/capacity "
                      "against shear_capacity (x / y), flagged at 1 or more. The impact's part is its peak force's static share "
                      "by the fixed–fixed point-load formulas: where the columns vibrate with their own mass "
                      "(contact.column_modes) their inertia is not in it, and massless columns' peak shear can be up "
                      "to twice these (docs/validation.md)",
                      ["building", "column", "storey", "ξ", "impacts", "impact V (kN)", "impact M (kN·m)",
                       "whole V (kN)", "capacity (kN)", "demand/capacity"], rows, right={2, 3, 4, 5, 6, 7})]  # fmt: skip
