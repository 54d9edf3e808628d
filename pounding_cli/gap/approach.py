"""How far one moving convex outline must be pushed along a direction to clear another.

Outline B translated by σ·n touches or overlaps outline A exactly when σ·n lies in the
Minkowski difference D = A ⊖ B (gap.minkowski). D is the intersection of the half-planes
m·x ≤ h_A(m) + h_B(−m) over the outward edge normals m of A and of −B (h the support
function, h_P(m) = max over P's vertices of m·p). On the line x = σ·n, each half-plane bounds σ:

    from above where m·n > 0:  σ ≤ (h_A(m) + h_B(−m)) / (m·n)
    from below where m·n < 0:  σ ≥ (h_A(m) + h_B(−m)) / (m·n)
    not at all where m·n = 0, except that the line misses D where h_A(m) + h_B(−m) < 0.

So the largest σ at which B + σ·n still meets A is the smallest upper bound, provided it is
not below the largest lower bound (else the line misses D: no push along n makes them meet,
−∞). This is the ray cast on the Minkowski difference, exact (no iteration), and vectorised
over time: `push_out` takes outlines at nt instants. tests/test_gap.py checks it against
minkowski.line_exit and shapely.
"""

from __future__ import annotations

import numpy as np


def outward_normals(poly: np.ndarray) -> np.ndarray:
    """(..., n, 2) unit outward normals of the edges k → k + 1 of counter-clockwise
    outlines (..., n, 2)."""
    edge = np.roll(poly, -1, axis=-2) - poly
    normal = np.stack([edge[..., 1], -edge[..., 0]], axis=-1)
    return normal / np.linalg.norm(normal, axis=-1, keepdims=True)


def support(poly: np.ndarray, m: np.ndarray) -> np.ndarray:
    """h_P(m) = max_k m·p_k of outlines (..., n, 2) in directions (..., q, 2): (..., q).

    Over many instants, a running maximum over the few vertices k (each m·p_k the same two
    products and one sum as einsum's: bit for bit its result) is an order of magnitude faster
    than einsum's (..., q, k) product (it is what `pound gap --suite` spends most on); einsum
    is faster for one instant (the refinement between samples)."""
    if m.shape[-2] * np.prod(np.broadcast_shapes(poly.shape[:-2], m.shape[:-2])) < 256:
        return np.max(np.einsum("...qd,...kd->...qk", m, poly), axis=-1)
    best = m[..., 0] * poly[..., None, 0, 0] + m[..., 1] * poly[..., None, 0, 1]
    for k in range(1, poly.shape[-2]):
        np.maximum(best, m[..., 0] * poly[..., None, k, 0] + m[..., 1] * poly[..., None, k, 1], out=best)
    return best


def push_out(a: np.ndarray, b: np.ndarray, n: np.ndarray) -> np.ndarray:
    """(nt,) the largest σ (m) at which B + σ·n meets A, for outlines a (nt, na, 2) and b
    (nt, nb, 2), counter-clockwise, and a unit direction n (2,); −inf where no σ makes them
    meet. Outlines apart at σ = 0 give σ < 0: −σ is then how far B could move against n
    before touching."""
    m = np.concatenate([outward_normals(a), -outward_normals(b)], axis=1)  # D's edge normals
    h = support(a, m) + support(b, -m)  # (nt, q): D = {x : m·x ≤ h}
    along = m @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = h / along
    upper = np.min(np.where(along > 0, bound, np.inf), axis=1)
    lower = np.max(np.where(along < 0, bound, -np.inf), axis=1)
    missed = (lower > upper) | np.any((along == 0) & (h < 0), axis=1)
    return np.where(missed, -np.inf, upper)


def advance(poly: np.ndarray, rest: np.ndarray, n: np.ndarray) -> np.ndarray:
    """(nt,) how far outlines (nt, k, 2) have advanced along n from `rest` (k, 2), m: the
    change of their support in n, the motion of their edge that faces along n (torsion
    included)."""
    return support(poly, n[None, None, :])[:, 0] - support(rest[None], n[None, None, :])[0, 0]
