"""`pound report`: tables, plots and animations of a run or a sweep, for people and scripts.

The Python API (the CLI is a thin layer over it)::

    from pounding_cli import report
    doc = report.summary("out.h5")                  # the `pound report --json` document
    run = report.open_run("out.h5")                 # results, resolved model, label
    fig = report.profile_figure([run], column="left:C9")   # a matplotlib Figure

Modules, one job each:

- :mod:`.load` reads result files; :mod:`.document` builds the JSON document and its schema;
  :mod:`.tables` turns it into tables (rich for the terminal, HTML for the report file);
- :mod:`.geometry` rebuilds the slab outlines from the model stored in the file;
- one module per plot, each returning a :class:`matplotlib.figure.Figure`: :mod:`.ground`,
  :mod:`.histories`, :mod:`.profiles`, :mod:`.impacts`, :mod:`.energy`, :mod:`.plan`,
  :mod:`.loops` (:mod:`.style` holds what they share); :mod:`.animate` writes the plan-view animation;
- :mod:`.plots` writes every plot into a folder, :mod:`.html` the self-contained HTML report.

Names are imported on first use: ``pound report --json`` never loads matplotlib.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "Run": "load",
    "open_run": "load",
    "open_runs": "load",
    "summary": "document",
    "summary_schema": "document",
    "run_tables": "tables",
    "plan_geometry": "geometry",
    "ground_figure": "ground",
    "displacement_figure": "histories",
    "profile_figure": "profiles",
    "impact_figure": "impacts",
    "energy_figure": "energy",
    "plan_figure": "plan",
    "loop_figure": "loops",
    "animate_plan": "animate",
    "write_plots": "plots",
    "write_html": "html",
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
