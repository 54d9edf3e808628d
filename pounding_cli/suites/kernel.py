"""The one compiled loop of the suites: an oscillator's peak displacement (scaling.py)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def peak_displacement(acc: np.ndarray, coef: np.ndarray) -> float:
    """max_i |u_i| (m) of the oscillator whose exact piecewise-linear recurrence has the
    coefficients `coef` = (A, B, C, D, A', B', C', D') (records.spectrum.coefficients), from
    rest, under ground acceleration `acc` (m/s²)."""
    a, b, c, d, a1, b1, c1, d1 = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5], coef[6], coef[7]
    u = 0.0
    v = 0.0
    best = 0.0
    for i in range(acc.size - 1):
        p0 = -acc[i]
        p1 = -acc[i + 1]
        u, v = a * u + b * v + c * p0 + d * p1, a1 * u + b1 * v + c1 * p0 + d1 * p1
        best = max(best, abs(u))
    return best
