"""Column and storey stiffness of shear-type storeys.

A column fixed at both ends with length h has lateral stiffness 12EI/h³ about each local
axis. For a section b_x × b_y (widths along the column's local x and y axes), a deflection
along local x bends it about local y: I = b_y·b_x³/12, so k_x = E·b_y·b_x³/h³ and
k_y = E·b_x·b_y³/h³. Column torsional stiffness (GJ/h) is neglected (shear-type model).

Small rotations: a point at plan offset r = (r_x, r_y) from a floor's mass centre moves by
u + θ·(−r_y, r_x); so a column's deflection (top minus bottom) is
δ = T(r_top)·q_top − T(r_bot)·q_bot with T(r) = [[1, 0, −r_y], [0, 1, r_x]] and q = (u_x, u_y, θ).
"""

from __future__ import annotations

import numpy as np


def column_local_stiffness(e: float, bx: float, by: float, h: float) -> tuple[float, float]:
    """Lateral stiffnesses (k_x, k_y) along the column's local axes, N/m."""
    return e * by * bx**3 / h**3, e * bx * by**3 / h**3


def column_plan_stiffness(kx: float, ky: float, angle: float) -> np.ndarray:
    """2×2 stiffness in global axes of a column whose local x is at `angle` rad from X, N/m."""
    c, s = np.cos(angle), np.sin(angle)
    e1, e2 = np.array([c, s]), np.array([-s, c])
    return kx * np.outer(e1, e1) + ky * np.outer(e2, e2)


def rigid_arm(r: np.ndarray) -> np.ndarray:
    """T(r): maps a floor's (u_x, u_y, θ) to the plan displacement of a point at offset r."""
    return np.array([[1.0, 0.0, -r[1]], [0.0, 1.0, r[0]]])


def storey_stiffness(
    plan_stiffness: list[np.ndarray], arm_bottom: list[np.ndarray], arm_top: list[np.ndarray]
) -> np.ndarray:
    """6×6 stiffness of a storey, DOFs (q_bottom, q_top), from its columns.

    Each column contributes Bᵀ·K_c·B with B = [−T(r_bot), T(r_top)].
    """
    k = np.zeros((6, 6))
    for kc, rb, rt in zip(plan_stiffness, arm_bottom, arm_top):
        b = np.hstack([-rigid_arm(rb), rigid_arm(rt)])
        k += b.T @ kc @ b
    return k
