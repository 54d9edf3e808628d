"""Exact discrete-time propagation of linear buildings (state-transition matrices), and the
exact work of the ground and of the damping over each propagated step.

Between contacts each building is linear: M·ü + C·u̇ + K·u = −M·ι·a_g(t), i.e. ẋ = A·x + B·a_g
with x = (u, v), A = [[0, I], [−M⁻¹K, −M⁻¹C]], B = [[0], [−ι]]. Over a step h in which a_g is
linear in time (h divides the record's sample interval), a_g(t + σh) = a₀ + σ·Δa, the
augmented state z = (x, a₀, Δa) obeys dz/dσ = Â·z with Â = [[A·h, B·h, 0], [0, 0, I], [0, 0, 0]]
(first-order hold), so z(σ) = e^{Âσ}·z₀ exactly and

    x(t + h) = Φ·x(t) + Γ₀·a₀ + Γ₁·Δa,  [Φ Γ₀ Γ₁] the top rows of e^{Â}.

The work over the step is exact too, from the same z₀:
- input, W_in = ∫ −a_gᵀ·ιᵀM·v dt = −Σ_axes [a₀·(S₁ − S₀) + Δa·(S₁ − S̄)], S = ι_axisᵀ·M·u the
  mass-weighted floor translation along the axis (kg·m) and S̄ = ∫₀¹ S dσ its mean over the
  step: S̄ = r_axis·z₀, r_axis the ι_axisᵀM-weighted u rows of Ψ = ∫₀¹ e^{Âσ} dσ (the top
  right block of exp([[Â, I], [0, 0]]));
- damping, W_d = ∫ vᵀ·C·v dt = z₀ᵀ·G·z₀ with G = h·∫₀¹ e^{Âᵀσ}·Q·e^{Âσ} dσ, Q = C in the v
  block: Van Loan's formula, G = F₂₂ᵀ·F₁₂ from exp([[−Âᵀ, h·Q], [0, Â]]) = [[·, F₁₂], [0, F₂₂]]
  (Van Loan 1978, "Computing integrals involving the matrix exponential").
They are computed once per building here and applied by the compiled loop in hybrid.py.
"""

from __future__ import annotations

import numpy as np
from .expm import expm


def building_propagators(
    stiffness_blocks: list[np.ndarray], damping_blocks: list[np.ndarray], mass: np.ndarray, starts, counts, h: float,
    doublings: int = 0, influence: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(Φ, Γ₀, Γ₁, mean rows r, damping form G) of every building over steps of h, 2h, 4h, …
    2^doublings·h, each stacked on a first axis of doublings + 1 and padded to n_b buildings
    of n_max DOFs: Φ (·, n_b, 2n_max, 2n_max), Γ₀ and Γ₁ (·, n_b, 2n_max, 2), r
    (·, n_b, 2, 2n_max + 4) kg·m per unit of z₀, G (·, n_b, 2n_max + 4, 2n_max + 4) J per unit
    of z₀².

    stiffness_blocks[b] and damping_blocks[b] are building b's dense K and C; mass the
    diagonal of M; influence ι, how far a unit ground displacement moves each DOF (1 on the
    floors' u_x, u_y; default); starts, counts the buildings' DOF ranges. Rows/columns 0…n−1 of Φ are u,
    n…2n−1 v; z₀ = (u, v, a₀X, a₀Y, ΔaX, ΔaY), of 2n + 4 entries (a building with n < n_max
    leaves the rest of its rows and columns zero, so its ground entries sit at 2n … 2n + 3).
    The matrix exponentials are taken over h only; each longer step follows from the one
    half its length (_doubled), exactly but for rounding.
    """
    n_max, n_b, levels = int(max(counts)), len(counts), doublings + 1
    phi = np.zeros((levels, n_b, 2 * n_max, 2 * n_max))
    g0 = np.zeros((levels, n_b, 2 * n_max, 2))
    g1 = np.zeros((levels, n_b, 2 * n_max, 2))
    mean_rows = np.zeros((levels, n_b, 2, 2 * n_max + 4))
    damping_form = np.zeros((levels, n_b, 2 * n_max + 4, 2 * n_max + 4))
    iota = np.tile([1.0, 1.0, 0.0], mass.size // 3) if influence is None else influence
    for b, (d0, n) in enumerate(zip(starts, counts)):
        m = mass[d0 : d0 + n]
        c = damping_blocks[b]
        size = 2 * n + 4
        aug = _augmented(stiffness_blocks[b], c, m, n, h, iota[d0 : d0 + n])
        e, rows, form = expm(aug), _mean_rows(aug, m * iota[d0 : d0 + n], n), _damping_form(aug, c, n, h)
        for level in range(levels):
            if level:
                e, rows, form = _doubled(e, rows, form, n)
            phi[level, b, : 2 * n, : 2 * n] = e[: 2 * n, : 2 * n]
            g0[level, b, : 2 * n] = e[: 2 * n, 2 * n : 2 * n + 2]
            g1[level, b, : 2 * n] = e[: 2 * n, 2 * n + 2 :]
            mean_rows[level, b, :, :size] = rows
            damping_form[level, b, :size, :size] = form
    return phi, g0, g1, mean_rows, damping_form


def state_matrix(k: np.ndarray, c: np.ndarray, m: np.ndarray) -> np.ndarray:
    """A = [[0, I], [−M⁻¹K, −M⁻¹C]] (2n)², 1/s, of a building with dense K, C and the diagonal
    m of M: ẋ = A·x for x = (u, v) in free vibration."""
    n = m.size
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -k / m[:, None]
    a[n:, n:] = -c / m[:, None]
    return a


def _augmented(k: np.ndarray, c: np.ndarray, m: np.ndarray, n: int, h: float, iota: np.ndarray) -> np.ndarray:
    """Â (2n + 4)² of a step h: dz/dσ = Â·z for z = (u, v, a₀, Δa), σ = t/h (iota: ι, (n,))."""
    a = state_matrix(k, c, m)
    bmat = np.zeros((2 * n, 2))
    bmat[n::3, 0] = -iota[0::3]  # the v_x rows feel −ι·a_X
    bmat[n + 1 :: 3, 1] = -iota[1::3]  # the v_y rows feel −ι·a_Y
    aug = np.zeros((2 * n + 4, 2 * n + 4))
    aug[: 2 * n, : 2 * n] = a * h
    aug[: 2 * n, 2 * n : 2 * n + 2] = bmat * h
    aug[2 * n : 2 * n + 2, 2 * n + 2 :] = np.eye(2)
    return aug


def _doubled(e: np.ndarray, rows: np.ndarray, form: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e^Â, r, G) of a step 2τ from those of τ. With S = diag(1, …, 1, ½, ½) halving the
    ground's rise Δa, a step of 2τ from z₀ is the step of τ from S·z₀ and then from
    z_mid = e^Â·S·z₀ (the augmented state carries a₀ + Δa/2 and Δa/2 to the second half):
    e^Â₂ = S⁻¹·(e^Â)²·S, r₂ = ½·r·(I + e^Â)·S (the mean over both halves), G₂ = Sᵀ·(G +
    e^Âᵀ·G·e^Â)·S."""
    scale = np.ones(2 * n + 4)
    scale[2 * n + 2 :] = 0.5
    e2 = (e @ e) * scale[None, :]
    e2[2 * n + 2 :] /= 0.5
    rows2 = 0.5 * (rows + rows @ e) * scale[None, :]
    form2 = (form + e.T @ form @ e) * np.outer(scale, scale)
    return e2, rows2, 0.5 * (form2 + form2.T)


def _mean_rows(aug: np.ndarray, m: np.ndarray, n: int) -> np.ndarray:
    """(2, 2n + 4): S̄_axis = row·z₀, the step's mean of ι_axisᵀ·M·u (X, Y), kg·m (m: M·ι)."""
    size = aug.shape[0]
    block = np.zeros((2 * size, 2 * size))
    block[:size, :size] = aug
    block[:size, size:] = np.eye(size)
    psi = expm(block)[:size, size:]  # ∫₀¹ e^{Âσ} dσ
    return np.vstack([m[axis::3] @ psi[axis:n:3] for axis in range(2)])


def _damping_form(aug: np.ndarray, c: np.ndarray, n: int, h: float) -> np.ndarray:
    """G (2n + 4)²: the damping's work z₀ᵀ·G·z₀ over the step, J (symmetric)."""
    size = aug.shape[0]
    scale = max(float(np.abs(c).max()) * h, 1e-300)  # Q's block made O(1) for expm's scaling
    block = np.zeros((2 * size, 2 * size))
    block[:size, :size] = -aug.T
    block[:size, size:][n : 2 * n, n : 2 * n] = c * h / scale
    block[size:, size:] = aug
    f = expm(block)
    form = f[size:, size:].T @ f[:size, size:] * scale
    return 0.5 * (form + form.T)
