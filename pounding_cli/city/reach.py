"""Which buildings can meet: the reach within which two buildings get contact candidates.

Two buildings whose outlines at rest lie d apart in plan can touch only if their floors'
excursions add up to d. For a linear building with classical (Rayleigh) damping on the
moving ground, the displacement of DOF k is Σ_n φ_kn·(Γ_nX·D_nX(t) + Γ_nY·D_nY(t)), D_nX the
response of an oscillator of mode n's ω_n and ζ_n to the X component; so

    |u_k| ≤ Σ_n |φ_kn|·(|Γ_nX|·S_d,X(ω_n, ζ_n) + |Γ_nY|·S_d,Y(ω_n, ζ_n))      (absolute sum)

with S_d the record's spectral displacement (exact at the samples: records/spectrum.py). A
point of a slab at distance r from its mass centre moves at most e_f = √(b_x² + b_y²) + b_θ·r.
Impacts push a building beyond its free response, and yielding members and isolators lengthen
its periods, so the default reach is REACH_FACTOR × (e_i + e_j) for the two largest building
excursions, and never less than NEAR (1 m: neighbours that close keep their candidates, as
`pound validate` lists them, whatever the record); buildings with yielding members or
isolators give no bound (no pruning unless `contact.reach` is given). Every run then checks what the bound assumed (check_pruned): no
pruned pair came within its measured excursions of touching (docs/theory.md, "Which
buildings can meet").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..assembly.levels import NEAR, near_pairs, outlines
from ..records.spectrum import peak_displacement

REACH_FACTOR = 2.0
"""The default reach over the two largest free-response excursion bounds: room for impacts
to push a building past its free response (1.2–1.6 times in the pounding literature)."""


@dataclass(frozen=True)
class Reach:
    """The reach of a scene and where it comes from."""

    distance: float  # m; inf: nothing pruned
    source: str  # "contact.reach", "bound" or why there is none


def excursion_bounds(buildings: list, acceleration: np.ndarray, dt: float) -> np.ndarray:  # type: ignore[type-arg]
    """Per building, the bound of how far any point of any of its slabs moves in plan, m
    (module docstring); inf for a building with yielding members or isolators."""
    omegas, zetas, owners = [], [], []
    for k, bld in enumerate(buildings):
        a0, a1 = bld.rayleigh
        omega = bld.modes.omega
        omegas.append(omega)
        zetas.append(a0 / (2 * np.maximum(omega, 1e-12)) + a1 * omega / 2)
        owners.append(np.full(omega.size, k))
    omega = np.maximum(np.concatenate(omegas), 1e-6)
    zeta = np.clip(np.concatenate(zetas), 0.0, 0.99)
    sd = [peak_displacement(acceleration[:, c], dt, omega, zeta) for c in (0, 1)]
    out = np.empty(len(buildings))
    start = 0
    for k, bld in enumerate(buildings):
        n = bld.modes.omega.size
        out[k] = _building_excursion(bld, sd[0][start:start + n], sd[1][start:start + n])
        start += n
    return out


def _building_excursion(bld, sd_x: np.ndarray, sd_y: np.ndarray) -> float:  # type: ignore[no-untyped-def]
    if bld.members or bld.isolated:
        return math.inf
    phi = bld.modes.shapes  # (3N, n), M-normalised
    gamma_x = phi[0::3].T @ bld.mass[0::3]
    gamma_y = phi[1::3].T @ bld.mass[1::3]
    modal = np.abs(gamma_x) * sd_x + np.abs(gamma_y) * sd_y  # (n,)
    bound = np.abs(phi) @ modal  # (3N,)
    radius = np.array([np.max(np.hypot(*(s - c).T)) for s, c in zip(bld.slabs, bld.mass_centre)])
    return float(np.max(np.hypot(bound[0::3], bound[1::3]) + bound[2::3] * radius))


def default_reach(excursions: np.ndarray) -> float:
    """REACH_FACTOR × the sum of the two largest excursion bounds, m (inf if one is)."""
    if excursions.size < 2:
        return math.inf
    top = np.sort(excursions)[-2:]
    return float(REACH_FACTOR * top.sum())


def measured_excursions(result, buildings: list) -> np.ndarray:  # type: ignore[no-untyped-def, type-arg]
    """Per building, how far a point of its slabs moved in plan during a run, at most, m:
    √(peak|u_x|² + peak|u_y|²) + peak|θ|·r per floor (peaks over every step)."""
    out = np.zeros(len(buildings))
    for k, bld in enumerate(buildings):
        peak = result.buildings[bld.name].peak_displacement
        radius = np.array([np.max(np.hypot(*(s - c).T)) for s, c in zip(bld.slabs, bld.mass_centre)])
        out[k] = float(np.max(np.hypot(peak[:, 0], peak[:, 1]) + peak[:, 2] * radius, initial=0.0))
    return out


def check_pruned(shapes: list, kept: set[tuple[int, int]], moved: np.ndarray,  # type: ignore[type-arg]
                 reach: float) -> list[tuple[int, int, float]]:  # fmt: skip
    """The pruned building pairs (i, j, d) whose clear distance at rest d (m) the two
    buildings' measured excursions `moved` (m) could have closed: they might have touched.
    Nothing to search when the two largest excursions together stay within `reach`."""
    if not math.isfinite(reach) or moved.size < 2 or np.sort(moved)[-2:].sum() < reach:
        return []
    import shapely

    tree = shapely.STRtree(shapes)
    widest = float(moved.max())
    out = []
    for i, shape in enumerate(shapes):
        for j in tree.query(shape, predicate="dwithin", distance=float(moved[i]) + widest):
            j = int(j)
            if j <= i or (i, j) in kept:
                continue
            d = float(shape.distance(shapes[j]))
            if d <= moved[i] + moved[j]:
                out.append((i, j, d))
    return out


def scene_reach(model, buildings: list, acceleration: np.ndarray, dt: float) -> tuple[Reach, frozenset | None]:  # type: ignore[no-untyped-def, type-arg]
    """The reach of a model (contact.reach, or the default bound) and the building pairs
    within it; None for the pairs when nothing is pruned (every two buildings are within
    reach, or there is no bound): then the candidates are those of every pair, as always."""
    contact = model.contact
    if not contact.enabled or len(buildings) < 2:
        return Reach(math.inf, "no pairs of buildings"), None
    n = len(buildings)
    shapes = outlines(buildings)
    if contact.reach is not None:
        reach = Reach(float(contact.reach), "contact.reach")
    elif len(near_pairs(shapes, NEAR)) == n * (n - 1) // 2:  # the reach is at least NEAR: nothing to prune
        return Reach(math.inf, "every two buildings within 1 m"), None
    else:
        bound = max(default_reach(excursion_bounds(buildings, acceleration, dt)), NEAR)
        reach = Reach(bound, "bound" if math.isfinite(bound) else "no bound: yielding members or isolators")
    if not math.isfinite(reach.distance):
        return reach, None
    near = near_pairs(shapes, reach.distance)
    return reach, (None if len(near) == n * (n - 1) // 2 else frozenset(near))
