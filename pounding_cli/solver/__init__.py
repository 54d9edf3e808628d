"""The time loop: compiled kernels on plain arrays (no pydantic, h5py or obspy here)."""

from .cdm import ENERGY_NAMES
from .integrate import Response, simulate, step_matrices

__all__ = ["ENERGY_NAMES", "Response", "simulate", "step_matrices"]
