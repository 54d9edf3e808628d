"""A suite sweep's statistics over its records: summary-stats.csv.

The cases of a sweep with a `suite` (sweep.suites) that differ only by their record form a
group (study, the case name without " @ record=…"). For every numeric result column of the
summary, over the group's complete cases, the lognormal fit of suites.fragility: the median
θ (geometric mean), the dispersion β (the standard deviation of the logarithms) and the 84th
percentile θ·e^β, in the column's unit, over its positive values (n_positive of n; zeros,
e.g. no impact, are left out of the fit and counted).

    summary-stats.csv   study, group, column, units, n, n_positive, median, beta, p84
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import write_text
from .suites import group_name

STATS_CSV = "summary-stats.csv"
HEADER = ["study", "group", "column", "units", "n", "n_positive", "median", "beta", "p84"]


def statistics_rows(columns: list[dict[str, Any]], rows: list[dict[str, Any]]) -> list[list[Any]]:
    """One row per group and numeric result column (HEADER's order)."""
    from ..suites.fragility import fit_lognormal

    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for row in rows:
        if row["status"] == "complete":
            groups.setdefault((row["study"], group_name(row["case"])), []).append(row)
    numeric = [c for c in columns if c["kind"] != "parameter" and c["dtype"] in ("float", "int")
               and c["name"] not in ("solver_time_s", "wall_time_s")]  # fmt: skip
    out = []
    for (study, group), members in groups.items():
        for c in numeric:
            values = np.array([np.nan if r[c["name"]] is None else float(r[c["name"]]) for r in members])
            fit = fit_lognormal(values)
            out.append([study, group, c["name"], c["units"], fit.n, fit.n_positive, fit.median, fit.beta, fit.p84])
    return out


def write_statistics(folder: Path, columns: list[dict[str, Any]], rows: list[dict[str, Any]]) -> Path:
    """Write summary-stats.csv atomically (numbers at full precision, empty where none)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(HEADER)
    for r in statistics_rows(columns, rows):
        writer.writerow(["" if isinstance(v, float) and not np.isfinite(v) else (repr(v) if isinstance(v, float) else v)
                         for v in r])  # fmt: skip
    return write_text(folder / STATS_CSV, buffer.getvalue())
