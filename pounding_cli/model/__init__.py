"""Input models of pound files (pydantic v2). They validate and nothing else."""

from .analysis import Analysis
from .building import Building, Column, ColumnGrid, Floor, RayleighDamping
from .contact import Contact, Obstacle
from .excitation import Excitation, Record, RecordComponent
from .load import LoadedModel, load_model, read_document, validate_model
from .material import Material
from .root import PoundModel

__all__ = [
    "Analysis",
    "Building",
    "Column",
    "ColumnGrid",
    "Contact",
    "Excitation",
    "Floor",
    "LoadedModel",
    "Material",
    "Obstacle",
    "PoundModel",
    "RayleighDamping",
    "Record",
    "RecordComponent",
    "load_model",
    "read_document",
    "validate_model",
]
