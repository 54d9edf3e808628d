"""Parametric sweeps: many analyses of one base model, in parallel, resumable.

    from pounding_cli.sweep import run_sweep
    outcome = run_sweep("inputs/pounding_angle_gap.sweep.toml", "out/", jobs=2)
    outcome.rows[0]["peak_impact_force_N"]

Modules, one job each: :mod:`.expand` (a sweep file → its cases), :mod:`.paths` (dotted
paths into a model document), :mod:`.document` (each case's model document, and messages
naming the case), :mod:`.plan` (checking every case before anything runs), :mod:`.tasks`
(what a worker does for one case), :mod:`.pool` (local worker processes), :mod:`.cluster`
(Dask), :mod:`.store` (the output folder), :mod:`.columns` and :mod:`.summary` (the summary
table), :mod:`.run` (all of it together). The file format and the summary's columns are
documented in docs/sweep.md.

Names are imported on first use: worker processes import this package before their thread
settings may take effect, so it must not load numpy or numba itself.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_EXPORTS = {
    "run_sweep": "run",
    "SweepOutcome": "run",
    "plan_sweep": "plan",
    "Plan": "plan",
    "rebuild_summary": "summary",
    "read_summary": "summary",
}

__all__ = list(_EXPORTS)

if TYPE_CHECKING:
    from .plan import Plan, plan_sweep
    from .run import SweepOutcome, run_sweep
    from .summary import read_summary, rebuild_summary


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
