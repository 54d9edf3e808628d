"""Exact discrete-time propagation of linear buildings (state-transition matrices).

Between contacts each building is linear: M·ü + C·u̇ + K·u = −M·ι·a_g(t), i.e. ẋ = A·x + B·a_g
with x = (u, v), A = [[0, I], [−M⁻¹K, −M⁻¹C]], B = [[0], [−ι]]. Over a step h in which a_g is
linear in time (h divides the record's sample interval), the solution is exact:

    x(t + h) = Φ·x(t) + Γ₀·a_g(t) + Γ₁·(a_g(t + h) − a_g(t))

with Φ, Γ₀, Γ₁ blocks of the matrix exponential of [[A·h, B·h, 0], [0, 0, I], [0, 0, 0]]
(first-order hold). They are computed once per building here and applied by the compiled
loop in hybrid.py.
"""

from __future__ import annotations

import numpy as np
from .expm import expm


def building_propagators(
    stiffness_blocks: list[np.ndarray], damping_blocks: list[np.ndarray], mass: np.ndarray, starts, counts, h: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Φ, Γ₀, Γ₁) of every building over a step h, padded to (n_b, 2·n_max, ·).

    stiffness_blocks[b] and damping_blocks[b] are building b's dense K and C; mass the
    diagonal of M; starts, counts the buildings' DOF ranges. Rows/columns 0…n−1 of Φ are u,
    n…2n−1 v.
    """
    n_max = int(max(counts))
    phi = np.zeros((len(counts), 2 * n_max, 2 * n_max))
    g0 = np.zeros((len(counts), 2 * n_max, 2))
    g1 = np.zeros((len(counts), 2 * n_max, 2))
    for b, (d0, n) in enumerate(zip(starts, counts)):
        m = mass[d0 : d0 + n]
        k = stiffness_blocks[b]
        c = damping_blocks[b]
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -k / m[:, None]
        a[n:, n:] = -c / m[:, None]
        bmat = np.zeros((2 * n, 2))
        bmat[n::3, 0] = -1.0  # the v_x rows feel −a_X
        bmat[n + 1 :: 3, 1] = -1.0  # the v_y rows feel −a_Y
        aug = np.zeros((2 * n + 4, 2 * n + 4))
        aug[: 2 * n, : 2 * n] = a * h
        aug[: 2 * n, 2 * n : 2 * n + 2] = bmat * h
        aug[2 * n : 2 * n + 2, 2 * n + 2 :] = np.eye(2)
        e = expm(aug)
        phi[b, : 2 * n, : 2 * n] = e[: 2 * n, : 2 * n]
        g0[b, : 2 * n] = e[: 2 * n, 2 * n : 2 * n + 2]
        g1[b, : 2 * n] = e[: 2 * n, 2 * n + 2 :]
    return phi, g0, g1
