"""Results: per-building histories and peaks, energy, and the HDF5 file."""

from .collect import collect
from .hdf5 import read_hdf5, write_hdf5
from .result import ENERGY_NAMES, BuildingResult, RunResult

__all__ = ["ENERGY_NAMES", "BuildingResult", "RunResult", "collect", "read_hdf5", "write_hdf5"]
