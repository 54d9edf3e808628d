"""Code-style estimates of the separation two adjacent structures need, from peak displacements.

With u_A and u_B the peak displacements of the two facing edges towards each other:

- ABS = u_A + u_B: the two peaks at the same instant, in opposite directions (an upper bound
  for motions along one line: the sum of the peaks can only exceed the peak of the sum);
- SRSS = √(u_A² + u_B²): the two responses statistically independent (EN 1998-1:2004
  §4.4.2.7(2), ASCE 7-16 §12.12.3 for adjacent structures on separate lots / building separation);
- DDC = √(u_A² + u_B² − 2ρ·u_A·u_B), the double difference combination: each response
  dominated by one mode, correlated by the CQC coefficient ρ of the two fundamental
  modes (Der Kiureghian 1981; Jeng, Kasai & Maison 1992; Penzien 1997). ρ → 1 for equal
  periods and damping (the buildings move in phase: DDC → |u_A − u_B|), ρ → 0 for well
  separated periods (DDC → SRSS).

ρ for modes of circular frequencies ω_i, ω_j and damping ratios ζ_i, ζ_j (r = ω_j/ω_i),
Der Kiureghian (1981):

    ρ = 8·√(ζ_i·ζ_j)·(ζ_i + r·ζ_j)·r^{3/2}
        / [(1 − r²)² + 4·ζ_i·ζ_j·r·(1 + r²) + 4·(ζ_i² + ζ_j²)·r²]
"""

from __future__ import annotations

import math

import numpy as np


def cqc_correlation(omega_i: float, zeta_i: float, omega_j: float, zeta_j: float) -> float:
    """ρ_ij of two modes (rad/s, fractions of critical); 1 for identical modes."""
    r = omega_j / omega_i
    top = 8.0 * math.sqrt(zeta_i * zeta_j) * (zeta_i + r * zeta_j) * r**1.5
    bottom = (1 - r * r) ** 2 + 4 * zeta_i * zeta_j * r * (1 + r * r) + 4 * (zeta_i**2 + zeta_j**2) * r * r
    return top / bottom if bottom > 0 else 1.0


def estimates(u_a: float, u_b: float, rho: float) -> dict[str, float]:
    """{"abs", "srss", "ddc"} in m from the facing edges' peak displacements (m) and ρ."""
    return {
        "abs": u_a + u_b,
        "srss": math.hypot(u_a, u_b),
        "ddc": math.sqrt(max(u_a * u_a + u_b * u_b - 2.0 * rho * u_a * u_b, 0.0)),
    }


def fundamental_mode(modes, mass: np.ndarray, damping: np.ndarray, n: np.ndarray) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """(ω, ζ) of a building's mode with the largest effective mass for ground motion along the
    unit direction n (global): Γ = φᵀ·M·r_n of mass-normalised φ, r_n = n_x on the u_x rows,
    n_y on the u_y rows; ζ = φᵀCφ/(2ω)."""
    from ..assembly.damping import modal_damping_ratios

    r = np.zeros(mass.size)
    r[0::3], r[1::3] = n[0], n[1]
    gamma = modes.shapes.T @ (mass * r)
    k = int(np.argmax(gamma * gamma))
    zeta = modal_damping_ratios(damping, modes.shapes[:, k : k + 1], modes.omega[k : k + 1])[0]
    return float(modes.omega[k]), float(zeta)
