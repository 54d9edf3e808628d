"""The time loop: compiled kernels on plain arrays (no pydantic, h5py or obspy here)."""

from .kernel_cache import drop_stale_kernels

drop_stale_kernels()  # before any kernel module is imported

from .cdm import ENERGY_NAMES  # noqa: E402
from .integrate import Response, simulate, step_matrices  # noqa: E402

__all__ = ["ENERGY_NAMES", "Response", "simulate", "step_matrices"]
