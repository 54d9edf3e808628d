"""Eigen-analysis of a building and Rayleigh damping from two of its modes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Modes:
    """Undamped modes of K·φ = ω²·M·φ, longest period first.

    `participation` holds the effective modal mass ratios (n_modes, 3) for unit rigid motion
    along the building's x and y axes and a unit rotation θ of every floor about its own mass
    centre; each column sums to 1 over all modes.
    """

    omega: np.ndarray  # (n,) rad/s
    shapes: np.ndarray  # (3N, n), mass-normalised: φᵀMφ = I
    participation: np.ndarray  # (n, 3)

    @property
    def periods(self) -> np.ndarray:
        """Periods 2π/ω, s."""
        return 2 * np.pi / self.omega


def modes(stiffness: np.ndarray, mass: np.ndarray, rotation: float) -> Modes:
    """Modes of a building with dense K (3N×3N, N/m, N, N·m) and diagonal mass `mass` (3N,).

    `rotation` (rad) is the building's x axis from global X, used for the participation axes.
    """
    # M is diagonal: K·φ = ω²·M·φ is the symmetric problem M^-½·K·M^-½·ψ = ω²·ψ, φ = M^-½·ψ
    scale = 1.0 / np.sqrt(mass)
    lam, psi = np.linalg.eigh(scale[:, None] * stiffness * scale[None, :])
    phi = scale[:, None] * psi
    lam = np.clip(lam, 0.0, None)
    c, s = np.cos(rotation), np.sin(rotation)
    influence = np.zeros((mass.size, 3))
    influence[0::3, 0], influence[1::3, 0] = c, s  # building x
    influence[0::3, 1], influence[1::3, 1] = -s, c  # building y
    influence[2::3, 2] = 1.0  # rotation
    gamma = phi.T @ (mass[:, None] * influence)  # φ is M-normalised
    total = (mass[:, None] * influence**2).sum(axis=0)
    return Modes(omega=np.sqrt(lam), shapes=phi, participation=gamma**2 / total)


def rayleigh_coefficients(
    omega_i: float, omega_j: float, zeta_i: float, zeta_j: float
) -> tuple[float, float]:
    """(a0 [1/s], a1 [s]) such that ζ(ω) = a0/(2ω) + a1·ω/2 passes through both points.

    Raises ValueError when the two frequencies coincide (the fit is then singular).
    """
    if abs(omega_j - omega_i) <= 1e-6 * max(omega_i, omega_j):
        raise ValueError(f"both modes have ω = {omega_i:.6g} rad/s")
    d = omega_j**2 - omega_i**2
    a0 = 2 * omega_i * omega_j * (zeta_i * omega_j - zeta_j * omega_i) / d
    a1 = 2 * (zeta_j * omega_j - zeta_i * omega_i) / d
    return a0, a1
