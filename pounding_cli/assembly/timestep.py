"""The time grid of an analysis: step, output stride and number of steps.

The central difference method is stable for Δt < 2/ω_max. `dt = "auto"` takes
AUTO_DT_FRACTION of that limit (accuracy, not stability, sets the fraction: see
docs/theory.md), then shortens it so that a whole number of steps fills one output interval.
With contact candidates, ω_max is the larger of the structure's highest frequency and the
contact estimate of pounding_cli.assembly.contact.contact_omega.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from ..model import Analysis

AUTO_DT_FRACTION = 0.05
"""Δt_auto = AUTO_DT_FRACTION · 2/ω_max (before fitting it to the output interval)."""


@dataclass(frozen=True)
class TimeGrid:
    """Steps of the analysis: t_n = n·dt for n = 0 … n_steps; output every `stride` steps."""

    dt: float  # s
    stride: int  # steps per output sample
    n_steps: int  # a multiple of stride
    stability_limit: float  # 2/ω_max of the structure, s
    contact_limit: float = float("inf")  # 2/ω of the stiffest contact estimate, s

    @property
    def output_interval(self) -> float:
        return self.dt * self.stride

    @property
    def duration(self) -> float:
        return self.dt * self.n_steps

    @property
    def n_outputs(self) -> int:
        return self.n_steps // self.stride + 1


def stability_limit(omega_max: float) -> float:
    """Critical step of the central difference method, 2/ω_max, s."""
    return 2.0 / omega_max


def time_grid(
    analysis: Analysis, omega_max: float, record_duration: float, source: str = "", omega_contact: float = 0.0
) -> TimeGrid:
    """Choose Δt, the output stride and the step count for an analysis."""
    limit = stability_limit(omega_max)
    contact_limit = stability_limit(omega_contact) if omega_contact > 0 else float("inf")
    out = analysis.output_interval
    if analysis.dt == "auto":
        stride = max(1, math.ceil(out / (AUTO_DT_FRACTION * min(limit, contact_limit)) - 1e-9))
        dt = out / stride
    else:
        dt = float(analysis.dt)
        if dt >= limit:
            raise InputError(
                f"time step {dt:g} s is at or above the stability limit 2/ω_max = {limit:.4g} s "
                f"of the central difference method (ω_max = {omega_max:.4g} rad/s); use a "
                f'smaller step or "auto"',
                file=source or None,
                field="analysis.dt",
            )
        stride = max(1, round(out / dt))
    duration = analysis.duration if analysis.duration is not None else record_duration
    n_out = max(1, math.ceil(duration / (stride * dt) - 1e-9))
    return TimeGrid(dt=dt, stride=stride, n_steps=n_out * stride, stability_limit=limit, contact_limit=contact_limit)
