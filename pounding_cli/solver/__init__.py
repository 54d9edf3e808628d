"""The time loop: compiled kernels on plain arrays (no pydantic, h5py or obspy here).

Importing the package loads no kernel and not numba: `simulate`, `Response` and
`step_matrices` load the integrator on first use, so that commands which never integrate
(`pound validate`, `report`, `export`, `schema`) start without numba's 0.8 s."""

from .kernel_cache import drop_stale_kernels

drop_stale_kernels()  # before any kernel module is imported

from .layout import ENERGY_NAMES  # noqa: E402

_INTEGRATOR_NAMES = ("Response", "simulate", "step_matrices")


def __getattr__(name: str):
    if name in _INTEGRATOR_NAMES:
        from . import integrate

        return getattr(integrate, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["ENERGY_NAMES", "Response", "simulate", "step_matrices"]
