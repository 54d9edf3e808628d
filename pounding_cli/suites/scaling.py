"""Scale factors of a suite's records (docs/theory.md, "Record suites").

For record i with processed components a_L, a_T (m/s², after the record's own processing
and scale), the factor applied through the model's excitation scale is

    f_i = s_i · F · m_i,

s_i the record's `scale`, F the suite's `scaling.factor` and m_i the method's:

- "none": m = 1;
- "p695": m = the record's FEMA P695 normalisation factor (built-in sets);
- "pga":  m = PGA* / max(max|a_L|, max|a_T|), PGA* the target in g times g;
- "sa":   m = Sa* / √(Sa_L(T)·Sa_T(T)), Sa_c(T) = ω²·max|u_c| the 5 %-damped pseudo-spectral
  acceleration of component c at the period T (exact for the piecewise-linear ground motion:
  records.spectrum), T given in s or the fundamental period T1 of a named building.

Sa is computed at periods within SPECTRUM (s) and of at least MIN_SAMPLES_PER_PERIOD samples
of the record (below that the peak between samples is missed); elsewhere it is an InputError
naming the suite file and `scaling.period`.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

G = 9.80665
"""Standard gravity, m/s² (a target in g times G)."""

SPECTRUM = (0.01, 10.0)
"""Periods (s) at which pound computes a response spectrum (records.spectrum.DEFAULT_PERIODS)."""

MIN_SAMPLES_PER_PERIOD = 10
"""Samples per period below which Sa at the samples can miss the peak between them."""


def method_factor(method: str, acceleration: dict[str, np.ndarray], dt: float, *, target: float | None = None,
                  period: float | None = None, normalisation: float | None = None) -> float:  # fmt: skip
    """m of one record (module docstring) from its processed components (m/s²) at step dt (s)."""
    if method == "none":
        return 1.0
    if method == "p695":
        assert normalisation is not None
        return normalisation
    assert target is not None
    if method == "pga":
        return target * G / max(float(np.max(np.abs(a))) for a in acceleration.values())
    assert period is not None
    sa = [pseudo_acceleration_at(a, dt, period) for a in acceleration.values()]
    return target * G / math.exp(sum(math.log(s) for s in sa) / len(sa))  # the geometric mean


def check_period(period: float, dt: float, where: str, source: object) -> None:
    """InputError (naming `source` and `where`) unless Sa can be computed at `period` (s)."""
    low, high = SPECTRUM
    if not low <= period <= high:
        raise InputError(f"Sa is computed at periods from {low:g} s to {high:g} s, got T = {period:.6g} s", file=source,
                         field=where)  # fmt: skip
    if period < MIN_SAMPLES_PER_PERIOD * dt:
        raise InputError(f"T = {period:.6g} s is shorter than {MIN_SAMPLES_PER_PERIOD} samples of a record sampled "
                         f"every {dt:g} s: its Sa would miss the peaks between samples", file=source, field=where)  # fmt: skip


def pseudo_acceleration_at(acceleration: np.ndarray, dt: float, period: float, zeta: float = 0.05) -> float:
    """PSA(T) = ω²·max|u| (m/s²) of one oscillator of period T (s), damping ζ, under ground
    acceleration `acceleration` (m/s²) sampled every dt: records.spectrum's exact recurrence."""
    from ..records.spectrum import pseudo_acceleration

    return float(pseudo_acceleration(acceleration, dt, np.array([period]), zeta)[0])
