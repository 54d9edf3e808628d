"""The storey a slab strikes between a neighbour's floors: how its outline moves, which columns
it strikes, and how flexible they are where they are struck (docs/theory.md, "Floors at
different heights").

Kinematics. A shear-type storey between rigid floors (below: q₀, above: q₁, each (u_x, u_y, θ)
at its own mass centre) has columns clamped at both ends; under end displacements alone they
bend into the cubic s(ξ) = 3ξ² − 2ξ³, so the storey's outline at height ξ·h moves as the
rigid body

    q(ξ) = (1 − s)·T·q₀ + s·q₁,    T·q₀ = (u₀x − θ₀·d_y, u₀y + θ₀·d_x, θ₀),

referred to the upper floor's mass centre (d = G₁ − G₀ at rest, T moves floor 0's motion
there). The contact kernel treats it as a floor of its own (a virtual floor, solver/storey_bodies.py):
it reads q(ξ) and hands its generalized force Q back as Q₁ = s·Q and Q₀ = (1 − s)·Tᵀ·Q,
the transpose of the same map, so the contact's virtual work on the floors is its work on the
outline and the energy balance stays closed. The outline is the slab of the floor above (the
façade follows the columns, which stand under it).

Local flexibility. A point load P at a = ξ·h above the foot of a column clamped at both ends
(b = h − a) deflects it there by P·a³b³/(3EIh³) (Roark, fixed–fixed beam, point load), the
column's own lateral stiffness 12EI/h³ divided by 4ξ³(1 − ξ)³ (point_load_factor): at
mid-height 16× softer than the storey's chord spring would suggest, and nothing at the
floors. The slab presses the façade along its contact line; the columns standing on that line
(struck_columns) deflect together under it, so their point-load stiffnesses add, and the
result acts in series with the overlap law. For the face-to-face contact of a slab edge along
a façade, whose overlap area is A = L·δ for a contact line of length L, the series pair is
again an overlap-area law, with

    k_N,eff = (1/k_N + C_n·L)⁻¹,   C_n = 1 / Σ_i n·K_i·n / point_load_factor(ξ),

exactly (n: the façade's normal, K_i: column i's 2 × 2 lateral stiffness); and friction's
spring likewise, k_T,eff = (1/k_T + C_t)⁻¹ with the columns' stiffness along the façade. The
finite-element frame of tests/fe_frame.py shows that, for massless columns, this reduced model
is the frame to rounding; without it the peak force came out 5–8× too high (the study of
issue 23, tests/fe_study.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .building import BuildingArrays
from .levels import StoreyCrossing

ROW_TOLERANCE = 0.5
"""Columns whose plan position lies within this (m) of the façade row nearest the struck
face stand on that face: a façade's columns are rarely on one exact line."""


def storey_shape(xi: float) -> float:
    """s(ξ) = 3ξ² − 2ξ³: the deflected shape of a column clamped at both ends under a sway of
    its upper end, 0 at the floor below and 1 at the floor above."""
    return 3.0 * xi * xi - 2.0 * xi**3


def point_load_factor(xi: float) -> float:
    """12EI/h³ over the point-load stiffness 3EIh³/(a³b³) at a = ξh, b = (1 − ξ)h: 4ξ³(1 − ξ)³
    (1/16 at mid-height, 0 at the floors)."""
    return 4.0 * xi**3 * (1.0 - xi) ** 3


@dataclass(frozen=True)
class StoreyBody:
    """The outline a slab strikes inside a neighbour's storey, and the columns that take it."""

    crossing: StoreyCrossing
    below: int  # 0-based floor of the struck building below the storey, −1 for its ground
    above: int  # 0-based floor above it (whose slab is the outline)
    shape: float  # s(ξ)
    arm: np.ndarray  # (2,) G_above − G_below at rest, m (zero over the ground)
    normal: np.ndarray  # (2,) unit outward normal of the struck façade, at rest
    line: float  # the contact line along the façade at rest, m
    columns: tuple[int, ...]  # indices into the struck building's `columns` that take the blow
    compliance_normal: float  # C_n, m/N, along the normal (0: no column found)
    compliance_tangential: float  # C_t, m/N, along the façade
    modes: int = 0  # local modes of the struck columns (local_modes.py); their flexibility leaves C_n, C_t
    bundle_mass: float = 0.0  # the struck columns' mass Σρ_iA_ih, kg (0: massless, no modes)


def facing_edge(slab: np.ndarray, outline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(start, end) of the edge of the (counter-clockwise) outline nearest the slab at rest: the
    façade it strikes; of edges at one distance, the one the slab spans farthest."""
    import shapely

    target = shapely.Polygon(slab)
    best, best_key = 0, (np.inf, 0.0)
    n = len(outline)
    for k in range(n):
        p, q = outline[k], outline[(k + 1) % n]
        length = float(np.hypot(*(q - p)))
        if length == 0.0:
            continue
        d = float(shapely.LineString([p, q]).distance(target))
        key = (round(d, 9), -_span(slab, p, q)[1])
        if key < best_key:
            best, best_key = k, key
    return outline[best], outline[(best + 1) % n]


def _span(slab: np.ndarray, p: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """(start, length) along edge p→q of the part of it the slab's projection covers, m."""
    e = (q - p) / np.hypot(*(q - p))
    along = (slab - p) @ e
    lo, hi = max(0.0, float(along.min())), min(float(np.hypot(*(q - p))), float(along.max()))
    return lo, max(0.0, hi - lo)


def struck_columns(struck: BuildingArrays, storey: int, p: np.ndarray, q: np.ndarray, start: float,
                   length: float) -> tuple[int, ...]:  # fmt: skip
    """The columns of `storey` (1-based) of the struck building that take a blow along the
    façade p→q over [start, start + length] (m along it): those of the row nearest the façade
    (within ROW_TOLERANCE of it) that stand within the span; where none does (the slab strikes
    between two), the nearest one on each side of it, which the façade between them loads."""
    e = (q - p) / np.hypot(*(q - p))
    outward = np.array([e[1], -e[0]])
    above = storey - 1
    found = []
    for i, col in enumerate(struck.columns):
        if col.storey != storey - 1:
            continue
        where = struck.mass_centre[above] + col.arm_top - p
        found.append((i, float(where @ e), float(-(where @ outward))))  # along, inward depth
    if not found:
        return ()
    front = min(depth for _, _, depth in found)
    row = [(i, t) for i, t, depth in found if depth <= front + ROW_TOLERANCE]
    within = tuple(i for i, t in row if start - 1e-9 <= t <= start + length + 1e-9)
    if within:
        return within
    left = [(start - t, i) for i, t in row if t < start]
    right = [(t - start - length, i) for i, t in row if t > start + length]
    return tuple(sorted(min(side)[1] for side in (left, right) if side))


def facade_stiffness(struck: BuildingArrays, columns: tuple[int, ...], direction: np.ndarray) -> float:
    """The columns' summed storey stiffness 12EI/h³ along a unit plan direction, N/m."""
    return sum(float(direction @ struck.columns[i].plan_stiffness @ direction) for i in columns)


def storey_body(buildings: list[BuildingArrays], crossing: StoreyCrossing, column_modes: int | str = 0,
                k_normal: float = 0.0) -> StoreyBody:  # fmt: skip
    """The storey body of a slab–storey crossing: its kinematic weights, the struck façade and
    columns, and their point-load compliances at ξ; where the columns have mass and
    column_modes > 0 (or "auto": local_modes.auto_modes for the face stiffness k_normal·L, k_normal
    in N/m²), their first local modes move the outline (local_modes.py) and only the flexibility
    those leave out stays in the compliances."""
    from .local_modes import auto_modes, residual_fraction

    slab = buildings[crossing.building].slabs[crossing.floor]
    struck = buildings[crossing.struck]
    above = crossing.storey - 1
    below = crossing.storey - 2
    outline = struck.slabs[above]
    p, q = facing_edge(slab, outline)
    start, line = _span(slab, p, q)
    e = (q - p) / np.hypot(*(q - p))
    normal = np.array([e[1], -e[0]])
    columns = struck_columns(struck, crossing.storey, p, q, start, line)
    factor = point_load_factor(crossing.xi)
    k_n = facade_stiffness(struck, columns, normal) / factor
    k_t = facade_stiffness(struck, columns, e) / factor
    arm = struck.mass_centre[above] - struck.mass_centre[below] if below >= 0 else np.zeros(2)
    mass = float(sum(struck.columns[i].mass for i in columns))
    if column_modes == "auto":
        column_modes = auto_modes(k_normal * line, k_n * factor) if mass > 0 and k_n > 0 else 0
    modes = int(column_modes) if mass > 0 else 0
    kept = residual_fraction(crossing.xi, modes)
    return StoreyBody(crossing, below, above, storey_shape(crossing.xi), arm, normal, line, columns,
                      kept / k_n if k_n > 0 else 0.0, kept / k_t if k_t > 0 else 0.0, modes, mass)  # fmt: skip


def series_stiffness(k_normal: float, k_tangential: float, body: StoreyBody) -> tuple[float, float]:
    """(k_N,eff N/m², k_T,eff N/m): the overlap law in series with the struck columns' local
    flexibility (module docstring)."""
    return (1.0 / (1.0 / k_normal + body.compliance_normal * body.line),
            1.0 / (1.0 / k_tangential + body.compliance_tangential))  # fmt: skip
