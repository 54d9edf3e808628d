"""Intensity measures of one ground-acceleration component.

pound applies the ground acceleration as **linear between samples** (docs/theory.md §5), so
the measures below integrate that piecewise-linear a(t) exactly, from rest (v = u = 0 at the
first sample), with no baseline correction beyond the record's own processing:

- velocity, trapezoidal rule (exact for linear a):  v_{i+1} = v_i + Δt (a_i + a_{i+1}) / 2;
- displacement, exact for linear a:  u_{i+1} = u_i + Δt v_i + Δt² (2 a_i + a_{i+1}) / 6;
- Arias intensity I_A = π / (2g) ∫ a² dt, m/s, with ∫ over a step of linear a
  = Δt (a_i² + a_i a_{i+1} + a_{i+1}²) / 3;
- 5-95 % significant duration D5-95 = t95 − t5, the times at which the running Arias
  intensity reaches 5 % and 95 % of its total (linear interpolation between samples).

PGA, PGV and PGD are the largest absolute values at the samples. An unprocessed record's
displacement drifts (a small offset in a integrates to a parabola): PGD is then meaningless,
and ``processing`` (demean, filter) is the cure.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

G = 9.80665
"""Standard gravity, m/s² per g."""


@dataclass(frozen=True)
class Metrics:
    """Intensity measures of one component (SI units; times in s from its first sample)."""

    dt: float  # s
    points: int
    duration: float  # s, first to last sample
    pga: float  # m/s²
    pga_time: float  # s
    pgv: float  # m/s
    pgv_time: float  # s
    pgd: float  # m
    pgd_time: float  # s
    arias_intensity: float  # m/s
    t5: float  # s
    t95: float  # s

    @property
    def pga_g(self) -> float:
        return self.pga / G

    @property
    def significant_duration(self) -> float:
        """D5-95, s."""
        return self.t95 - self.t5

    def as_dict(self) -> dict[str, float | int]:
        return asdict(self)


def integrate(acceleration: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Velocity (m/s) and displacement (m) of piecewise-linear `acceleration` (m/s²), from rest."""
    a = np.asarray(acceleration, dtype=np.float64)
    velocity = np.concatenate(([0.0], np.cumsum(0.5 * dt * (a[:-1] + a[1:]))))
    steps = dt * velocity[:-1] + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0
    return velocity, np.concatenate(([0.0], np.cumsum(steps)))


def arias_build_up(acceleration: np.ndarray, dt: float) -> np.ndarray:
    """Running Arias intensity π/(2g) ∫₀ᵗ a² dt at each sample, m/s (exact for linear a)."""
    a = np.asarray(acceleration, dtype=np.float64)
    steps = dt * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3.0
    return math.pi / (2.0 * G) * np.concatenate(([0.0], np.cumsum(steps)))


def crossing_time(build_up: np.ndarray, level: float, dt: float) -> float:
    """First time (s) at which the non-decreasing `build_up` reaches `level`, interpolated."""
    i = int(np.searchsorted(build_up, level, side="left"))
    if i == 0:
        return 0.0
    if i >= build_up.size:
        return (build_up.size - 1) * dt
    below, above = build_up[i - 1], build_up[i]
    fraction = (level - below) / (above - below) if above > below else 0.0
    return (i - 1 + fraction) * dt


def metrics(acceleration: np.ndarray, dt: float) -> Metrics:
    """The intensity measures of one component, `acceleration` in m/s² every `dt` s."""
    a = np.asarray(acceleration, dtype=np.float64)
    velocity, displacement = integrate(a, dt)
    build_up = arias_build_up(a, dt)
    total = float(build_up[-1])
    t5 = crossing_time(build_up, 0.05 * total, dt) if total > 0 else 0.0
    t95 = crossing_time(build_up, 0.95 * total, dt) if total > 0 else 0.0

    def peak(x: np.ndarray) -> tuple[float, float]:
        i = int(np.argmax(np.abs(x)))
        return float(abs(x[i])), i * dt

    (pga, t_a), (pgv, t_v), (pgd, t_d) = peak(a), peak(velocity), peak(displacement)
    return Metrics(dt, int(a.size), (a.size - 1) * dt, pga, t_a, pgv, t_v, pgd, t_d, total, t5, t95)
