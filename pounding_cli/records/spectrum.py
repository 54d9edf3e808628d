"""Elastic response spectrum: the exact response of damped oscillators to piecewise-linear input.

A single-degree-of-freedom oscillator of natural period T (ω = 2π/T) and damping ratio ζ on
the moving ground obeys

    ü + 2ζω u̇ + ω² u = −a_g(t)

(u relative to the ground). With a_g linear between samples, as pound applies it, the
solution over one step is known in closed form, so u and u̇ at the samples follow exactly
from a two-term recurrence (Nigam & Jennings 1969; Chopra, *Dynamics of Structures*, §5.2):

    u_{i+1} = A u_i + B u̇_i + C p_i + D p_{i+1}
    u̇_{i+1} = A' u_i + B' u̇_i + C' p_i + D' p_{i+1},      p = −a_g,

whose coefficients depend on ω, ζ and Δt only (:func:`coefficients`). The recurrence runs
once over time with every period at once (arrays over periods). The pseudo-spectral
acceleration is PSA(T) = ω² max_i |u_i|, the peak taken at the samples: at periods below
about ten samples the true peak between samples can be a little higher.
"""

from __future__ import annotations

import numpy as np

DEFAULT_PERIODS = np.geomspace(0.01, 10.0, 121)
"""Periods of the plotted spectrum, s: 40 per decade from 0.01 s to 10 s."""

DAMPING = 0.05
"""Damping ratio of the spectrum, the usual 5 %."""


def coefficients(omega: np.ndarray, zeta: float, dt: float) -> tuple[np.ndarray, ...]:
    """A, B, C, D, A', B', C', D' of the recurrence for circular frequencies `omega` (rad/s),
    damping ratio ``0 <= zeta < 1`` and step `dt` (s); the unit mass is implied (k = ω²)."""
    omega = np.asarray(omega, dtype=np.float64)
    root = np.sqrt(1.0 - zeta * zeta)
    omega_d = omega * root
    k = omega * omega
    e = np.exp(-zeta * omega * dt)
    s, c = np.sin(omega_d * dt), np.cos(omega_d * dt)
    z = zeta / root
    two_z = 2.0 * zeta / (omega * dt)
    a = e * (z * s + c)
    b = e * s / omega_d
    cc = (two_z + e * (((1.0 - 2.0 * zeta**2) / (omega_d * dt) - z) * s - (1.0 + two_z) * c)) / k
    d = (1.0 - two_z + e * ((2.0 * zeta**2 - 1.0) / (omega_d * dt) * s + two_z * c)) / k
    a1 = -e * omega / root * s
    b1 = e * (c - z * s)
    c1 = (-1.0 / dt + e * ((omega / root + zeta / (dt * root)) * s + c / dt)) / k
    d1 = (1.0 - e * (z * s + c)) / (k * dt)
    return a, b, cc, d, a1, b1, c1, d1


def oscillator_response(
    acceleration: np.ndarray, dt: float, periods: np.ndarray, zeta: float = DAMPING
) -> tuple[np.ndarray, np.ndarray]:
    """Relative displacement u (m) and velocity u̇ (m/s) of each oscillator at every sample,
    shape (samples, periods), from rest, under ground acceleration `acceleration` (m/s²)."""
    a, b, c, d, a1, b1, c1, d1 = coefficients(2.0 * np.pi / np.asarray(periods, dtype=np.float64), zeta, dt)
    p = -np.asarray(acceleration, dtype=np.float64)
    u = np.zeros((p.size, a.size))
    v = np.zeros((p.size, a.size))
    for i in range(p.size - 1):
        u[i + 1] = a * u[i] + b * v[i] + c * p[i] + d * p[i + 1]
        v[i + 1] = a1 * u[i] + b1 * v[i] + c1 * p[i] + d1 * p[i + 1]
    return u, v


def pseudo_acceleration(
    acceleration: np.ndarray, dt: float, periods: np.ndarray = DEFAULT_PERIODS, zeta: float = DAMPING
) -> np.ndarray:
    """PSA(T) = ω² max|u|, m/s², for each period T (s) of `periods`."""
    omega = 2.0 * np.pi / np.asarray(periods, dtype=np.float64)
    return omega * omega * peak_displacement(acceleration, dt, omega, zeta)


def peak_displacement(acceleration: np.ndarray, dt: float, omega: np.ndarray, zeta: float | np.ndarray = DAMPING) -> np.ndarray:
    """max|u| (m) of oscillators of circular frequencies `omega` (rad/s) and damping ratios
    `zeta` (one, or one each), from rest, under `acceleration` (m/s²)."""
    from .spectrum_kernel import peak_displacements

    omega = np.asarray(omega, dtype=np.float64)
    coef = np.array(np.broadcast_arrays(*coefficients(omega, zeta, dt)), dtype=np.float64)  # type: ignore[arg-type]
    peak = np.zeros(omega.size)
    peak_displacements(-np.ascontiguousarray(acceleration, dtype=np.float64), coef.reshape(8, -1), peak)
    return peak.reshape(omega.shape)
