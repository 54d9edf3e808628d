"""Input models of pound files (pydantic v2). They validate and nothing else."""

from .analysis import Analysis
from .building import Building, Column, ColumnGrid, Floor, RayleighDamping
from .contact import Contact, Obstacle
from .excitation import Excitation, Record, RecordComponent
from .load import LoadedModel, load_model, read_document, validate_model
from .material import Material
from .root import PoundModel

_SWEEP_NAMES = ("LoadedSweep", "load_sweep", "validate_sweep")


def __getattr__(name: str):
    """The sweep file's models load on first use: `pound run` does not need them (30 ms)."""
    if name in _SWEEP_NAMES:
        from . import sweep

        return getattr(sweep, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = [
    "Analysis",
    "Building",
    "Column",
    "ColumnGrid",
    "Contact",
    "Excitation",
    "Floor",
    "LoadedModel",
    "LoadedSweep",
    "Material",
    "Obstacle",
    "PoundModel",
    "RayleighDamping",
    "Record",
    "RecordComponent",
    "load_model",
    "load_sweep",
    "read_document",
    "validate_model",
    "validate_sweep",
]
