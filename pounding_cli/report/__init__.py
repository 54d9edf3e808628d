"""`pound report`: tables, plots and animations of a run or a sweep, for people and scripts.

The Python API (the CLI is a thin layer over it)::

    from pounding_cli import report
    doc = report.summary("out.h5")                  # the `pound report --json` document
    run = report.open_run("out.h5")                 # results, resolved model, label

Modules, one job each:

- :mod:`.load` reads result files; :mod:`.document` builds the JSON document and its schema;
  :mod:`.tables` turns it into tables (rich for the terminal).

Names are imported on first use.
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
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
