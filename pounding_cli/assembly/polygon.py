"""Closed-form properties of a simple polygon (shoelace formulas), for slab mass and inertia.

Vertices are (n, 2) arrays in m, counter-clockwise; all results are exact for straight edges.
"""

from __future__ import annotations

import numpy as np


def _cross_terms(vertices: np.ndarray) -> tuple[np.ndarray, ...]:
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    return x, y, xn, yn, x * yn - xn * y


def polygon_area(vertices: np.ndarray) -> float:
    """Signed area, m² (positive counter-clockwise)."""
    *_, c = _cross_terms(vertices)
    return float(c.sum() / 2)


def polygon_centroid(vertices: np.ndarray) -> np.ndarray:
    """Area centroid [x, y], m."""
    x, y, xn, yn, c = _cross_terms(vertices)
    a = c.sum() / 2
    return np.array([((x + xn) * c).sum(), ((y + yn) * c).sum()]) / (6 * a)


def polar_moment_about_centroid(vertices: np.ndarray) -> float:
    """Polar second moment of area I_x + I_y about the centroid, m⁴."""
    x, y, xn, yn, c = _cross_terms(vertices)
    ixx_origin = ((y * y + y * yn + yn * yn) * c).sum() / 12  # ∫ y² dA
    iyy_origin = ((x * x + x * xn + xn * xn) * c).sum() / 12  # ∫ x² dA
    a = c.sum() / 2
    cx, cy = polygon_centroid(vertices)
    return float(ixx_origin + iyy_origin - a * (cx * cx + cy * cy))
