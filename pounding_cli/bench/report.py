"""The benchmark's table, HDF5 file and work-precision plot."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..atomic import atomic_path, hdf5_writer
from .run import PERTURBATION, SceneReport, on_front


def table_rows(reports: list[SceneReport]) -> list[dict]:
    """One dict per (scene, setting), JSON-ready."""
    out = []
    for report in reports:
        front = on_front(report)
        for row in report.rows:
            e = row.errors
            out.append(
                {
                    "scene": row.scene,
                    "setting": row.setting.name,
                    "integrator": row.setting.integrator,
                    "default": row.setting.default,
                    "on_front": row.setting.name in front,
                    "steps": row.steps,
                    "contact_steps": row.contact_steps,
                    "wall_time_s": row.wall_time,
                    "peak_deflection_error": e.peak_deflection,
                    "peak_deflection_error_normwise": e.peak_deflection_norm,
                    "peak_force_error": e.peak_force,
                    "impact_count_difference": e.impact_count,
                    "energy_balance_error": e.energy_balance,
                    "yielding_members": e.members,
                    "member_deflection_error": e.member_deflection,
                    "ductility_error": e.ductility,
                    "reference_halving_change": report.convergence.peak_deflection,
                    "input_sensitivity": report.sensitivity.peak_deflection if report.sensitivity else None,
                    "error_floor": report.floor,
                }
            )
    return out


def markdown(reports: list[SceneReport]) -> str:
    """The table as Markdown, one section per scene, with the reference's convergence. Scenes
    with yielding members (inelastic columns, isolators) get two more columns: the errors of
    the members' peak deflections and peak ductilities."""
    lines = []
    for report in reports:
        c = report.convergence
        members = c.members > 0
        lines.append(
            f"**{report.scene}** — reference: {report.reference.name}, {report.reference_steps:,} steps; "
            f"halving its Δt changes peak deflections by {c.peak_deflection:.1e} (normwise "
            f"{c.peak_deflection_norm:.1e}) and the peak force by {c.peak_force:.1e} (impacts {c.impact_count:+d})"
            + (f"; the {c.members} yielding members' peak deflections by {c.member_deflection:.1e} and "
               f"peak ductilities by {c.ductility:.1e}" if members else "")
            + _sensitivity(report)
            + "\n"
        )  # fmt: skip
        extra = " member deflection error | ductility error |" if members else ""
        lines.append("| setting | steps | contact steps | solver (s) | peak deflection error | normwise "
                     f"| peak force error | impacts Δ | energy balance |{extra} front |")  # fmt: skip
        lines.append("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |" + " ---: | ---: |" * members
                     + " :---: |")  # fmt: skip
        front = on_front(report)
        for row in report.rows:
            e = row.errors
            name = f"**{row.setting.name}**" if row.setting.default else row.setting.name
            cells = f" {e.member_deflection:.1e} | {e.ductility:.1e} |" if members else ""
            lines.append(
                f"| {name} | {row.steps:,} | {row.contact_steps:,} | {row.wall_time:.3g} | "
                f"{e.peak_deflection:.1e} | {e.peak_deflection_norm:.1e} | {e.peak_force:.1e} | {e.impact_count:+d} | "
                f"{e.energy_balance:.1e} |{cells} "
                f"{'●' if row.setting.name in front else ''} |"
            )
        lines.append("")
    return "\n".join(lines)


def _sensitivity(report: SceneReport) -> str:
    """The scene's sensitivity to its input, in words (empty if not measured)."""
    e = report.sensitivity
    if e is None:
        return ""
    return (f". Scaling the record by 1 + {PERTURBATION:g} changes peak deflections by {e.peak_deflection:.1e} "
            f"(normwise {e.peak_deflection_norm:.1e}), the peak force by {e.peak_force:.1e} (impacts "
            f"{e.impact_count:+d}): errors below {report.floor:.1e} cannot be told apart")  # fmt: skip


def write_hdf5(reports: list[SceneReport], path: Path) -> None:
    """The table as a compound dataset /bench (written atomically)."""
    import h5py

    rows = table_rows(reports)
    dtype = np.dtype(
        [("scene", h5py.string_dtype()), ("setting", h5py.string_dtype()), ("integrator", h5py.string_dtype()),
         ("default", np.bool_), ("on_front", np.bool_), ("steps", np.int64), ("contact_steps", np.int64),
         ("wall_time_s", np.float64), ("peak_deflection_error", np.float64),
         ("peak_deflection_error_normwise", np.float64), ("peak_force_error", np.float64),
         ("impact_count_difference", np.int64), ("energy_balance_error", np.float64),
         ("yielding_members", np.int64), ("member_deflection_error", np.float64), ("ductility_error", np.float64)]
    )  # fmt: skip
    table = np.array([tuple(r[name] for name in dtype.names) for r in rows], dtype=dtype)
    from .. import __version__

    with atomic_path(path) as tmp, hdf5_writer(tmp) as f:
        ds = f.create_dataset("bench", data=table)
        ds.attrs["units"] = "-, -, -, -, -, -, -, s, -, -, -, -, -, -, -, -"
        ds.attrs["note"] = ("member_deflection_error and ductility_error: the yielding members' peaks "
                            "(0 where yielding_members is 0)")  # fmt: skip
        f.attrs["pound_version"] = __version__
        for report in reports:
            f.attrs[f"reference:{report.scene}"] = report.reference.name
            f.attrs[f"reference_halving_change:{report.scene}"] = report.convergence.peak_deflection
            if report.sensitivity is not None:
                f.attrs[f"input_sensitivity:{report.scene}"] = report.sensitivity.peak_deflection
            f.attrs[f"error_floor:{report.scene}"] = report.floor


def plot(reports: list[SceneReport], path: Path):
    """Work-precision plot: error against solver time, log-log, one panel per scene (with the
    yielding members' peak deflection error as open markers where the scene has members).
    Returns the matplotlib Figure (saved to `path`, written atomically)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(reports)
    cols = min(n, 3)
    fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(5 * cols, 4 * ((n + cols - 1) // cols)),
                             squeeze=False)  # fmt: skip
    for ax, report in zip(axes.flat, reports):
        for integrator, marker in (("hybrid", "o"), ("cdm", "s")):
            rows = [r for r in report.rows if r.setting.integrator == integrator]
            if not rows:
                continue
            ax.loglog([r.wall_time for r in rows], [max(r.errors.peak_deflection, 1e-9) for r in rows], marker,
                      label=f"{integrator}: peak deflection", linestyle="none")  # fmt: skip
            if report.convergence.members:
                ax.loglog([r.wall_time for r in rows], [max(r.errors.member_deflection, 1e-9) for r in rows], marker,
                          label=f"{integrator}: member peak |δ|", linestyle="none", markerfacecolor="none")  # fmt: skip
        default = next((r for r in report.rows if r.setting.default), None)
        if default is not None:
            ax.loglog([default.wall_time], [max(default.errors.peak_deflection, 1e-9)], "*", markersize=14,
                      color="k", label="default")  # fmt: skip
        ax.set_title(report.scene)
        ax.set_xlabel("solver time (s)")
        ax.set_ylabel("largest relative error of a peak deflection")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return fig
