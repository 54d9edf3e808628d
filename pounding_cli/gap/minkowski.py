"""Convex outlines in plan: their Minkowski difference, and where a line leaves it.

Two convex outlines A and B + c (B translated by c) are apart by

    dist(A, B + c) = dist(c, A ⊖ B),   A ⊖ B = {a − b : a ∈ A, b ∈ B},

the Minkowski difference, itself a convex polygon whose edges are those of A and of −B,
merged by direction. So questions about sliding one building against another are questions
about one point and one polygon:

- where B must stand along a line c = p + t·d to be a gap g clear of A (relative placement):
  the largest t with dist(p + t·d, A ⊖ B) = g, where the line leaves A ⊖ B grown by g;
- how far B must be moved along d to clear A (the penetration depth along d, pound gap):
  the largest t with p + t·d in A ⊖ B (g = 0).

:func:`line_exit` answers both. Polygons are (n, 2) arrays of vertices, counter-clockwise,
m. Plain numpy: this is used before and after the time loop, never inside it.
"""

from __future__ import annotations

import math

import numpy as np


def minkowski_difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A ⊖ B = A ⊕ (−B) of two convex counter-clockwise polygons, counter-clockwise, m: the
    edges of both merged by their direction, from the sum of the two lowest vertices (O(n + m))."""
    return minkowski_sum(np.asarray(a, dtype=float), -np.asarray(b, dtype=float))


def _lowest_first(p: np.ndarray) -> np.ndarray:
    """The polygon's vertices from its lowest (smallest y, then smallest x), same order."""
    k = int(np.lexsort((p[:, 0], p[:, 1]))[0])
    return np.roll(p, -k, axis=0)


def minkowski_sum(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A ⊕ B of two convex counter-clockwise polygons, counter-clockwise; collinear vertices
    merged away."""
    a, b = _lowest_first(a), _lowest_first(b)
    na, nb = len(a), len(b)
    out = []
    i = j = 0
    while i < na or j < nb:
        out.append(a[i % na] + b[j % nb])
        ea = a[(i + 1) % na] - a[i % na]
        eb = b[(j + 1) % nb] - b[j % nb]
        cross = ea[0] * eb[1] - ea[1] * eb[0]
        if j >= nb or (i < na and cross > 0):
            i += 1
        elif i >= na or cross < 0:
            j += 1
        else:  # parallel edges: one edge of the sum
            i += 1
            j += 1
    return _without_collinear(np.array(out))


def _without_collinear(p: np.ndarray) -> np.ndarray:
    """Drop vertices that lie on the line of their neighbours (within rounding)."""
    n = len(p)
    scale = float(np.max(np.abs(p))) or 1.0
    keep = []
    for k in range(n):
        u, w = p[k] - p[k - 1], p[(k + 1) % n] - p[k]
        if abs(u[0] * w[1] - u[1] * w[0]) > 1e-14 * scale * scale or not np.any(u) or not np.any(w):
            if np.any(u):
                keep.append(k)
    return p[keep]


def line_exit(polygon: np.ndarray, p: np.ndarray, d: np.ndarray, grow: float = 0.0) -> float | None:
    """The largest t at which the point p + t·d (d a unit vector) is within `grow` (m, ≥ 0)
    of the convex counter-clockwise polygon: where the line leaves the polygon grown by
    `grow` (its edges moved out by `grow`, its corners rounded). None where the line passes
    farther than `grow` from it.

    Every candidate is a point of the grown polygon (on a moved edge, within its ends; or on
    a corner's circle), and the exit is one of them, so the largest is the exit."""
    best = -math.inf
    n = len(polygon)
    for k in range(n):
        v, w = polygon[k], polygon[(k + 1) % n] - polygon[k]
        length = math.hypot(w[0], w[1])
        normal = np.array([w[1], -w[0]]) / length  # outward: the polygon runs counter-clockwise
        along = float(normal @ d)
        if along != 0.0:
            t = float(normal @ (v - p) + grow) / along
            s = float(w @ (p + t * d - v)) / (length * length)
            if 0.0 <= s <= 1.0:
                best = max(best, t)
        if grow > 0.0:  # the corner at v: |p + t·d − v| = grow
            half_b = float(d @ (p - v))
            disc = half_b * half_b - (float((p - v) @ (p - v)) - grow * grow)
            if disc >= 0.0:
                best = max(best, -half_b + math.sqrt(disc))
    return best if best > -math.inf else None
