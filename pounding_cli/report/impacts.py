"""Plot: impact force and overlap area against time, with the impact episodes marked.

Two sources, both shown: the contact histories (/impacts/normal_force, /impacts/area: one
line per contact pair, at the output interval, so an impact shorter than the interval may
fall between samples) and the impact log (/impacts/events: every episode's peak force and
peak area, found at every step, drawn as stems at its t_peak, its span shaded). Force in kN, area in cm².
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..results.sparse import held
from .load import Run
from .style import IMPACT_COLOUR, colour, figure, grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MARGIN_S = 1.0
"""Time shown before the first and after the last episode, s."""


def pair_label(pair: np.void) -> str:
    """"left 3 – right 3" (body and floor; an obstacle without floor; a storey struck between
    two floors as "right storey 2 at ξ 0.57")."""
    storey = int(pair["storey_b"])  # read_hdf5 gives 0 for files written before the column existed
    if storey:
        b = f"{pair['body_b']} storey {storey} at ξ {float(pair['xi']):.2f}"
    else:
        b = f"{pair['body_b']} {pair['floor_b']}" if pair["floor_b"] else str(pair["body_b"])
    return f"{pair['body_a']} {pair['floor_a']} – {b}"


def impact_figure(run: Run, whole_run: bool = False) -> Figure:
    """Normal force (kN, top) and overlap area (cm², bottom) of every pair that touched,
    against time (s): on the left zoomed to the episodes (± 1 s) unless `whole_run`, on the
    right around the largest episode; the log's episode peaks as stems."""
    r = run.result
    c = r.contact
    fig = figure(10.0, 5.5)
    axes = fig.subplots(2, 2, width_ratios=[2, 1])
    f_n = held(c.normal_force)
    touched = sorted({int(p) for p in c.events["pair"]} | set(f_n.columns[(f_n.values > 0).any(axis=0)].tolist()))
    for column in (0, 1):
        _draw(axes[:, column], run, touched)
    axes[0, 0].sharex(axes[1, 0])
    axes[0, 1].sharex(axes[1, 1])
    if c.events.size:
        if not whole_run:
            ends = np.where(np.isnan(c.events["t_end"]), r.time[-1], c.events["t_end"])
            axes[0, 0].set_xlim(max(r.time[0], c.events["t_start"].min() - MARGIN_S), min(r.time[-1], ends.max() + MARGIN_S))
        e = c.events[int(np.argmax(c.events["peak_normal_force"]))]
        end = e["t_end"] if np.isfinite(e["t_end"]) else r.time[-1]
        half = max(4 * _step(run), 2 * (end - e["t_start"]))
        axes[0, 1].set_xlim(e["t_start"] - half, end + half)
        axes[0, 1].set_title(f"the largest episode: {pair_label(c.pairs[int(e['pair'])])}", fontsize="small")
    else:
        for ax in axes[0]:
            ax.text(0.5, 0.5, "no impacts" if c.pairs.size else "no contact candidates", transform=ax.transAxes,
                    ha="center", va="center")  # fmt: skip
    axes[0, 0].set_ylabel("normal force F_N (kN)")
    axes[1, 0].set_ylabel("overlap area (cm²)")
    for ax in axes[1]:
        ax.set_xlabel("time (s)")
    for ax in axes.ravel():
        ax.set_ylim(bottom=0)
    handles = {label: h for h, label in zip(*axes[0, 0].get_legend_handles_labels())}
    if handles:
        fig.legend(handles.values(), handles.keys(), loc="outside lower center", ncols=min(3, len(handles)),
                   fontsize="small")  # fmt: skip
    grid(axes)
    fig.suptitle("Impacts: contact histories (lines, at the output interval) and the impact log (stems: each "
                 "episode's peak, found at every step)", fontsize="medium")  # fmt: skip
    return fig


def _draw(axes: np.ndarray, run: Run, touched: list[int]) -> None:
    """Histories of the touched pairs and the log's stems on a (force, area) pair of axes."""
    r, c = run.result, run.result.contact
    f_n, area = held(c.normal_force), held(c.area)
    for i, p in enumerate(touched):
        label = f"{pair_label(c.pairs[p])} (every {_step(run):.3g} s)"
        axes[0].plot(r.time, f_n.column(p) / 1e3, lw=0.8, marker=".", ms=2, color=colour(i), label=label)
        axes[1].plot(r.time, area.column(p) * 1e4, lw=0.8, marker=".", ms=2, color=colour(i), label=label)
    if c.events.size:
        ends = np.where(np.isnan(c.events["t_end"]), r.time[-1], c.events["t_end"])
        for ax, values in ((axes[0], c.events["peak_normal_force"] / 1e3), (axes[1], c.events["peak_area"] * 1e4)):
            for t0, t1 in zip(c.events["t_start"], ends):
                ax.axvspan(t0, t1, color=IMPACT_COLOUR, alpha=0.12, lw=0)
            ax.vlines(c.events["t_peak"], 0, values, color=IMPACT_COLOUR, lw=0.8)
            ax.plot(c.events["t_peak"], values, "v", color=IMPACT_COLOUR, ms=5, ls="none",
                    label=f"impact log: peak of each episode ({c.events.size})")  # fmt: skip


def _step(run: Run) -> float:
    """The output interval, s."""
    dt = run.result.diagnostics.get("output_interval")
    if dt is None and run.result.time.size > 1:
        dt = float(run.result.time[1] - run.result.time[0])
    return float(dt or 0.01)
