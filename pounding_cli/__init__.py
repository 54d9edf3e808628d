"""pound: 3D simulation of earthquake-induced pounding between adjacent buildings.

The Python API (the CLI is a thin layer over it)::

    import pounding_cli as pound
    model = pound.load_model("model.toml")      # validated; InputError on bad input
    info = pound.describe(model)                 # periods, damping, Δt, record
    result = pound.run_model(model, output="out.h5")
    again = pound.read_hdf5("out.h5")
"""

__version__ = "0.1.0"

from .api import describe, prepare, run_model  # noqa: E402
from .errors import AnalysisFailed, InputError, PoundError, RecordReadError  # noqa: E402
from .model import LoadedModel, PoundModel, load_model  # noqa: E402
from .results import RunResult, read_hdf5, write_hdf5  # noqa: E402

__all__ = [
    "AnalysisFailed",
    "InputError",
    "LoadedModel",
    "PoundError",
    "PoundModel",
    "RecordReadError",
    "RunResult",
    "__version__",
    "describe",
    "load_model",
    "prepare",
    "read_hdf5",
    "run_model",
    "write_hdf5",
]
