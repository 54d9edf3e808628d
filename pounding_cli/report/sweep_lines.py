"""Plot: summary columns of a sweep against a swept parameter, the paper's figure 8 (peak
interstorey deflections of column C9 against the angle of incidence), also as a polar plot.

The x axis is a numeric swept parameter; only the studies in which it varies are drawn.
Cases that differ in the other parameters that vary make separate lines (labelled with
their values), so a sweep of angle × gap gives one line per gap. Panels by quantity:
x, y and θ deflections (mm, mrad) — of one column's every storey, or of each building's
largest — or the chosen columns grouped by unit. N are drawn in kN.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..errors import InputError
from .style import colour, figure, grid
from .sweep_data import Sweep, column_names, numeric_parameters, short_value

if TYPE_CHECKING:
    from matplotlib.figure import Figure

UNITS = {"m": ("mm", 1e3), "rad": ("mrad", 1e3), "N": ("kN", 1e-3)}
"""SI unit → (unit drawn, factor)."""
COMPONENT_LABELS = ("peak Δx", "peak Δy", "peak Δθ")
LINESTYLES = ("-", "--", ":", "-.")
POLAR_TITLE_PAD = 28.0
"""Points between a polar panel's circle and its title: room for the 90° label."""


def default_x(sweep: Sweep, x: str | None) -> str:
    """The parameter on the x axis: `x`, checked, or the first numeric one that varies."""
    numeric = numeric_parameters(sweep)
    if x is None:
        if not numeric:
            raise InputError("the sweep has no numeric parameter that varies to plot against; its named cases are "
                             "compared by the bar chart", file=sweep.folder, field="--x")  # fmt: skip
        return numeric[0]
    if x not in numeric:
        raise InputError(f"{x!r} is not a numeric swept parameter that varies; choose one of "
                         f"{', '.join(numeric) or '(none)'}", file=sweep.folder, field="--x")  # fmt: skip
    return x


def is_angle(x: str) -> bool:
    """Whether the parameter is an angle in degrees (drawn also as a polar plot)."""
    return x.rsplit(".", 1)[-1].endswith("angle")


def groups(sweep: Sweep, x: str) -> list[tuple[str, list[dict[str, Any]]]]:
    """(label, rows sorted by x) per line: rows of the studies where `x` varies, split by
    study and by the values of the other parameters that vary."""
    by_study: dict[str, list[dict[str, Any]]] = {}
    for r in sweep.rows:
        by_study.setdefault(r["study"], []).append(r)
    out: dict[str, list[dict[str, Any]]] = {}
    for study, rows in by_study.items():
        if len({r[x] for r in rows}) < 2:
            continue
        others = [p for p in sweep.names("parameter")
                  if p != x and len({json.dumps(r[p], sort_keys=True) for r in rows}) > 1]  # fmt: skip
        for r in rows:
            key = ", ".join(f"{p}={_legend_value(r[p])}" for p in others)
            label = f"{study}: {key}" if study and key else study or key
            out.setdefault(label, []).append(r)
    return [(label, sorted(rows, key=lambda r: r[x])) for label, rows in out.items()]


def _legend_value(value: Any) -> str:
    """A parameter value in a legend: numbers and strings as JSON, lists and tables shortened."""
    return short_value(value) if isinstance(value, (list, dict)) else json.dumps(value, ensure_ascii=False)


PRETTY = {"impacts": "impacts", "peak_impact_force_N": "peak impact force", "energy_balance_error": "energy balance error",
          "solver_time_s": "solver time", "wall_time_s": "analysis time"}  # fmt: skip
"""Axis labels of the summary's scalar result columns."""


def axis_label(sweep: Sweep, name: str) -> str:
    """"peak impact force (kN)": a column's name for an axis, in the unit drawn."""
    unit = sweep.column(name)["units"]
    shown, _ = UNITS.get(unit, (unit if unit not in ("", "-") else "", 1.0))
    return f"{PRETTY.get(name, name)} ({shown})" if shown else PRETTY.get(name, name)


def _series(sweep: Sweep, column: str | None, ys: Sequence[str] | None) -> list[tuple[str, list[tuple[str, str]]]]:
    """Panels: (y label, [(series label, summary column)])."""
    if ys:
        panels: dict[str, list[tuple[str, str]]] = {}
        for name in ys:
            unit = sweep.column(name)["units"]
            panels.setdefault(UNITS.get(unit, (unit, 1.0))[0], []).append((name, name))
        return [(axis_label(sweep, cols[0][1]) if len(cols) == 1 else f"({unit})" if unit not in ("", "-") else "value",
                 cols) for unit, cols in panels.items()]  # fmt: skip
    if column:
        per_building = column_names(sweep, column)
        col = column.rpartition(":")[2]
        return [
            (f"{COMPONENT_LABELS[k]} ({'mrad' if k == 2 else 'mm'})",
             [(f"{b} {col} storey {s + 1}" if len(per_building) > 1 else f"storey {s + 1}", storeys[s][k])
              for b, storeys in per_building.items() for s in range(len(storeys))])
            for k in range(3)
        ]  # fmt: skip
    buildings = [n[len("peak_isd_x_m["):-1] for n in sweep.names("result") if n.startswith("peak_isd_x_m[") and "/" not in n]
    return [
        (f"{COMPONENT_LABELS[k]} ({'mrad' if k == 2 else 'mm'})",
         [(f"{b} (largest)", f"peak_isd_{suffix}[{b}]") for b in buildings])
        for k, suffix in enumerate(("x_m", "y_m", "theta_rad"))
    ]  # fmt: skip


def _legend(fig: Figure, panels: list, lines: list) -> None:
    """Colours name the series (when a panel has several), line styles the groups."""
    from matplotlib.lines import Line2D

    handles = []
    if any(len(series) > 1 for _, series in panels):
        names = list(dict.fromkeys(label for _, series in panels for label, _ in series))
        handles += [Line2D([], [], color=colour(i), marker="o", ms=3, label=name) for i, name in enumerate(names)]
    if len(lines) > 1:
        handles += [Line2D([], [], color="0.3", ls=LINESTYLES[j % len(LINESTYLES)], label=label or "(base)")
                    for j, (label, _) in enumerate(lines)]  # fmt: skip
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncols=min(4, len(handles)), fontsize="small")


def _polar_layout(ax: Any, title: str) -> None:
    """Title and radial ticks of a polar panel that clear each other and the angle labels:
    the title at a fixed height above the 90° label (left to matplotlib, it moves up after the
    layout is made and runs into the figure's title), at most four small radial labels along
    the 22.5° ray, on a white ground over the lines."""
    from matplotlib.ticker import MaxNLocator

    ax.set_rlim(bottom=0)
    ax.set_title(title, fontsize="small", y=1.0, pad=POLAR_TITLE_PAD)
    ax.yaxis.set_major_locator(MaxNLocator(nbins=4, min_n_ticks=2))
    ax.set_rlabel_position(22.5)
    ax.tick_params(axis="y", labelsize="x-small")
    for label in ax.get_yticklabels():
        label.set_bbox(dict(boxstyle="round,pad=0.1", facecolor="white", edgecolor="none", alpha=0.8))


def parameter_figure(
    sweep: Sweep, x: str | None = None, column: str | None = None, ys: Sequence[str] | None = None,
    polar: bool = False,
) -> Figure:  # fmt: skip
    """Summary columns against the swept parameter `x` (default: the first numeric one):
    the deflections of `column`'s storeys ("left:C9"), or the columns `ys`, or each
    building's largest deflections; `polar` draws the angle around a circle (degrees,
    counter-clockwise from global X, as the excitation angle)."""
    x = default_x(sweep, x)
    lines = groups(sweep, x)
    panels = _series(sweep, column, ys)
    n = len(panels)
    if polar:
        fig = figure(4.2 * n, 5.2)
        axes = [fig.add_subplot(1, n, i + 1, projection="polar") for i in range(n)]
    else:
        fig = figure(8.0, 2.6 * n + 0.8)
        axes = list(np.atleast_1d(fig.subplots(n, 1, sharex=True)))
    for ax, (ylabel, series) in zip(axes, panels):
        for j, (_, rows) in enumerate(lines):
            xs = np.array([r[x] for r in rows], dtype=float)
            for i, (slabel, name) in enumerate(series):
                _, factor = UNITS.get(sweep.column(name)["units"], ("", 1.0))
                values = np.array([np.nan if r[name] is None else r[name] for r in rows], dtype=float) * factor
                ax.plot(np.radians(xs) if polar else xs, values, marker="o", ms=3, lw=1.0, color=colour(i),
                        ls=LINESTYLES[j % len(LINESTYLES)], label=f"{slabel} | {lines[j][0]}")  # fmt: skip
        if polar:
            _polar_layout(ax, ylabel)
        else:
            ax.set_ylabel(ylabel)
    if not polar:
        axes[-1].set_xlabel(f"{x} (°)" if is_angle(x) else x)
        grid(axes)
    _legend(fig, panels, lines)
    what = f"column {column}" if column else ", ".join(PRETTY.get(y, y) for y in ys) if ys else "largest per building"
    fig.suptitle(f"{sweep.title}\n{what} against {x}" + (" (polar: angle counter-clockwise from X)" if polar else ""),
                 fontsize="medium")  # fmt: skip
    return fig
