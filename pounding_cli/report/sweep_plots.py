"""Every plot of a sweep's report (``pound report DIR/ --plots PLOTS``).

- ``sweep-<x>``: deflections against the swept parameter x (the paper's figure 8);
- ``sweep-<x>-polar``: the same around a circle, when x is an angle;
- ``sweep-<x>-impacts``: impacts and peak impact force against x;
- ``sweep-<x>-columns``: the summary columns chosen with ``--y``, against x;
- ``sweep-cases`` (or ``sweep-cases-<study>`` per study): grouped bars of the cases chosen
  with ``--case``, or of every study of at most 12 cases (the paper's figures 6 and 7).

Without a numeric parameter that varies, only the bar charts.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from ..errors import InputError
from .style import FORMATS, save_as
from .sweep_bars import cases_figure, default_case_groups
from .sweep_data import Sweep, match_cases, match_columns, numeric_parameters
from .sweep_lines import default_x, is_angle, parameter_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def _stem(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "all"


def sweep_figures(
    sweep: Sweep, x: str | None = None, column: str | None = None, ys: Sequence[str] | None = None,
    cases: Sequence[str] | None = None,
) -> dict[str, Callable[[], Figure]]:  # fmt: skip
    """File stem → a function drawing that figure (see the module's docstring); `ys` and
    `cases` are shell-style patterns of summary columns and of cases."""
    out: dict[str, Callable[[], Figure]] = {}
    if x is not None or numeric_parameters(sweep):
        x = default_x(sweep, x)
        out[f"sweep-{_stem(x)}"] = lambda: parameter_figure(sweep, x, column)
        if is_angle(x):
            out[f"sweep-{_stem(x)}-polar"] = lambda: parameter_figure(sweep, x, column, polar=True)
        out[f"sweep-{_stem(x)}-impacts"] = lambda: parameter_figure(sweep, x, ys=["impacts", "peak_impact_force_N"])
        if ys:
            names = match_columns(sweep, ys)
            out[f"sweep-{_stem(x)}-columns"] = lambda: parameter_figure(sweep, x, ys=names)
    if cases:
        rows = match_cases(sweep, cases)
        out["sweep-cases"] = lambda: cases_figure(sweep, rows, column)
    else:
        groups = default_case_groups(sweep)
        for study, rows in groups:
            stem = "sweep-cases" if len(groups) == 1 else f"sweep-cases-{_stem(study)}"
            title = f"{sweep.title}, study {study}" if study else sweep.title
            out[stem] = lambda rows=rows, title=title: cases_figure(sweep, rows, column, title)
    return out


def write_sweep_plots(sweep: Sweep, folder: str | Path, fmt: str = "png", **options) -> list[Path]:
    """Draw every figure of a sweep's report into `folder` as `fmt`; returns the files."""
    folder = Path(folder)
    if fmt not in FORMATS:
        raise InputError(f"unknown plot format {fmt!r}; choose one of {', '.join(FORMATS)}", field="--format")
    if folder.exists() and not folder.is_dir():
        raise InputError("is a file; --plots names a folder to write the plots into", file=folder)
    if not folder.parent.is_dir():
        raise InputError(f"the folder {str(folder.parent)!r} does not exist; create it first", file=folder)
    figures = sweep_figures(sweep, **options)
    folder.mkdir(exist_ok=True)
    return [save_as(draw(), folder, stem, fmt) for stem, draw in figures.items()]
