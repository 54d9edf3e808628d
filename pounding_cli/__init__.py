"""pound: 3D simulation of earthquake-induced pounding between adjacent buildings.

The Python API (the CLI is a thin layer over it)::

    import pounding_cli as pound
    model = pound.load_model("model.toml")      # validated; InputError on bad input
    info = pound.describe(model)                 # periods, damping, Δt, record
    result = pound.run_model(model, output="out.h5")
    again = pound.read_hdf5("out.h5")
    gaps = pound.required_gaps(model)           # the separation each contact candidate needs

Names are imported on first use, so `pound --version` and input errors answer without
loading numba, scipy and h5py. Importing pound first fixes the CPU its compiled code is
generated for (cpu_target), so that results are the same bits on every machine that runs it.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from . import cpu_target

__version__ = "0.1.0"

cpu_target.pin_portable_target()

_EXPORTS = {
    "describe": "api",
    "export_csv": "export",
    "prepare": "api",
    "run_model": "api",
    "required_gaps": "gap.required",
    "AnalysisFailed": "errors",
    "InputError": "errors",
    "PoundError": "errors",
    "RecordReadError": "errors",
    "LoadedModel": "model",
    "PoundModel": "model",
    "load_model": "model",
    "RunResult": "results",
    "read_hdf5": "results",
    "write_hdf5": "results",
    "run_sweep": "sweep",
}
_SUBMODULES = {"api", "assembly", "cli", "errors", "export", "gap", "model", "plausibility", "records", "results", "schema",
               "solver", "sweep"}

__all__ = ["__version__", *_EXPORTS]

if TYPE_CHECKING:
    from .api import describe, prepare, run_model
    from .errors import AnalysisFailed, InputError, PoundError, RecordReadError
    from .export import export_csv
    from .gap.required import required_gaps
    from .model import LoadedModel, PoundModel, load_model
    from .results import RunResult, read_hdf5, write_hdf5
    from .sweep import run_sweep


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS, *_SUBMODULES])
