"""The time loop of records/spectrum.py's oscillators, compiled: one pass over the samples,
every oscillator at once (a Python loop over a long record cost ~10 µs a sample). Imported only
when a spectrum or a peak displacement is asked for, so that reading a record needs no numba."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def peak_displacements(p: np.ndarray, coef: np.ndarray, peak: np.ndarray) -> None:
    """peak[k] = max_i |u_k,i| (m) of oscillator k, from rest, under the load p = −a_g (m/s²):
    the exact piecewise-linear recurrence u⁺ = A·u + B·v + C·p_i + D·p_{i+1}, v⁺ = A'·u + B'·v +
    C'·p_i + D'·p_{i+1}, with coef (8, n) the rows A, B, C, D, A', B', C', D'
    (records.spectrum.coefficients)."""
    n = coef.shape[1]
    u = np.zeros(n)
    v = np.zeros(n)
    for i in range(p.size - 1):
        p0 = p[i]
        p1 = p[i + 1]
        for k in range(n):
            uk = coef[0, k] * u[k] + coef[1, k] * v[k] + coef[2, k] * p0 + coef[3, k] * p1
            v[k] = coef[4, k] * u[k] + coef[5, k] * v[k] + coef[6, k] * p0 + coef[7, k] * p1
            u[k] = uk
            if abs(uk) > peak[k]:
                peak[k] = abs(uk)
