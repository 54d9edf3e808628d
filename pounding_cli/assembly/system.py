"""All buildings of a model as the plain arrays the solver works on.

Floors of all buildings are numbered one after another (building by building, bottom up);
floor f owns DOFs 3f, 3f+1, 3f+2 = (u_x, u_y, θ) at its mass centre, global axes.
Storeys are numbered the same way; storey s joins floor `storey_bottom[s]` (−1: the
ground) to floor `storey_top[s]`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import LoadedModel
from .building import BuildingArrays, assemble_building
from .levels import LEVEL_TOLERANCE, moat_pits, near_pairs, neighbours, outlines, storey_crossings



@dataclass(frozen=True)
class MemberArrays:
    """The yielding members of all buildings (inelastic columns, isolators), for the solver.
    Each is a bilinear law split into an elastic spring k (in the storey stiffness) and an
    elastic–perfectly-plastic correction of stiffness k_h = (1 − α)·k and strength
    f_h = (1 − α)·F_y carried by its plastic deflection (docs/theory.md)."""

    bottom: np.ndarray  # (n,) int64 global floor below, −1 = ground
    top: np.ndarray  # (n,) int64 global floor above
    arm_bottom: np.ndarray  # (n, 2) from the bottom floor's mass centre, m
    arm_top: np.ndarray  # (n, 2) from the top floor's mass centre, m
    axes: np.ndarray  # (n, 2) cos, sin of the local x axis from global X
    k0: np.ndarray  # (n, 2) initial stiffness along local x, y, N/m
    kh: np.ndarray  # (n, 2) (1 − α)·k, N/m
    fh: np.ndarray  # (n, 2) (1 − α)·F_y, N
    coupled: np.ndarray  # (n,) int64, 1: elliptical yield surface
    building: np.ndarray  # (n,) int64 building index

    @property
    def n(self) -> int:
        return self.top.size

    @property
    def yield_deflection(self) -> np.ndarray:
        """(n, 2) F_y/k, m."""
        return self.fh / self.kh


@dataclass(frozen=True)
class DampingLinkArrays:
    """The damping links of all buildings (assembly/damping.py): 6×6 blocks added to
    a0·M + a1·K on the DOFs of floors (bottom, top), global floor numbers, −1 the ground."""

    matrix: np.ndarray  # (n, 6, 6)
    bottom: np.ndarray  # (n,) int64
    top: np.ndarray  # (n,) int64


@dataclass(frozen=True)
class System:
    """The structural system as arrays (SI units)."""

    buildings: list[BuildingArrays]
    floor_start: np.ndarray  # (n_buildings + 1,) first global floor of each building
    mass: np.ndarray  # (n_dof,) diagonal of M
    dof_a0: np.ndarray  # (n_dof,) Rayleigh a0 of the DOF's building, 1/s
    dof_a1: np.ndarray  # (n_dof,) Rayleigh a1 of the DOF's building, s
    floor_centre: np.ndarray  # (n_floors, 2) global plan position of each mass centre, m
    storey_k: np.ndarray  # (n_storeys, 6, 6)
    storey_bottom: np.ndarray  # (n_storeys,) int64, −1 = ground
    storey_top: np.ndarray  # (n_storeys,) int64
    storey_axes: np.ndarray  # (n_storeys, 2) cos φ, sin φ of the storey's building rotation
    column_storey: np.ndarray  # (n_columns,) int64, global storey of each column instance
    column_plan: np.ndarray  # (n_columns, 2) global plan position, m
    members: MemberArrays  # yielding members (may be none)
    damping_links: DampingLinkArrays  # what C adds to a0·M + a1·K: an isolated building's, local modes' (may be none)
    influence: np.ndarray | None = None  # (n_dof,) ground influence ι: 1 on floors' u_x, u_y, Σw on a local mode's
    stiffness_links: DampingLinkArrays | None = None  # 6×6 stiffness blocks beyond the storeys (local modes' springs)
    local_modes: tuple = ()  # the struck columns' local modes (local_modes.LocalMode), one pseudo-floor each
    mode_floor: np.ndarray | None = None  # (n_modes,) the global pseudo-floor of each local mode

    def real_floors(self, b: int) -> slice:
        """Global floors of building b's own floors (its local modes' pseudo-floors follow them)."""
        f0 = int(self.floor_start[b])
        return slice(f0, f0 + self.buildings[b].n_floors)

    @property
    def n_dof(self) -> int:
        return self.mass.size

    @property
    def omega_max(self) -> float:
        """Highest natural circular frequency of any building, rad/s, the struck columns' local
        modes (on fixed floors) included: the central difference method's stability limit
        follows it (the hybrid's exact steps follow fastest_rate, the buildings' own)."""
        return max([float(b.modes.omega[-1]) for b in self.buildings] + [m.omega for m in self.local_modes])

    def fastest_rate(self) -> tuple[float, int, int, float]:
        """(ρ, building, mode, ζ): the largest |λ| of any building's damped modes, 1/s (≥ ω_max;
        BuildingArrays.fastest_rate), and where it is."""
        rates = [b.fastest_rate() for b in self.buildings]
        k = max(range(len(rates)), key=lambda i: rates[i][0] if rates[i][0] == rates[i][0] else np.inf)
        return rates[k][0], k, rates[k][1], rates[k][2]


def assemble(loaded: LoadedModel) -> System:
    """Assemble every building of a validated model."""
    model = loaded.model
    buildings = [
        assemble_building(b, model.materials, f"buildings[{i}]", str(loaded.source), model.hysteresis, model.bearings)
        for i, b in enumerate(model.buildings)
    ]
    check_no_overlap_at_rest(buildings, str(loaded.source), moat_pits(model))
    return combine(buildings)


def check_no_overlap_at_rest(buildings: list[BuildingArrays], source: str, pits: frozenset[int] = frozenset()) -> None:
    """Before the ground moves, no slab of one building may overlap another building: its
    slab at one level, or its storey's outline where the slab lies between its floors. And no
    building may stand wholly below the ground of a neighbour within NEAR of it: its roof
    would face the neighbour's foundation, which pound does not model."""
    import shapely

    def refuse(a: int, fa: int, b: int, fb: int, z: float, area: float, what: str) -> None:
        raise InputError(
            f"at rest, floor {fa + 1} of building {buildings[a].name!r} overlaps {what} {fb + 1} of building "
            f"{buildings[b].name!r} at elevation {z:g} m by {area:.4g} m²; move the building (origin, rotation) "
            "so that they are apart or touch",
            file=source,
            field=f"buildings[{max(a, b)}].origin",
        )

    def overlap(pa: np.ndarray, pb: np.ndarray) -> float:
        sa, sb = shapely.Polygon(pa), shapely.Polygon(pb)
        area = sa.intersection(sb).area
        return area if area > 1e-9 * min(sa.area, sb.area) else 0.0

    touching = near_pairs(outlines(buildings), 0.0)  # only outlines that meet can overlap
    for i, j in sorted(touching, key=lambda p: (p[1], p[0])):
        a, b = buildings[i], buildings[j]
        for fa, za in enumerate(a.elevation):
            for fb in np.flatnonzero(np.abs(b.elevation - za) < LEVEL_TOLERANCE):
                if area := overlap(a.slabs[fa], b.slabs[fb]):
                    refuse(j, int(fb), i, fa, za, area, "floor")
    for c in storey_crossings(buildings, pits, touching):
        struck = buildings[c.struck]
        if area := overlap(buildings[c.building].slabs[c.floor], struck.slabs[c.storey - 1]):
            refuse(c.building, c.floor, c.struck, c.storey - 1, c.elevation, area, "the storey beneath floor")
    for i, j, d in neighbours(buildings):
        for low, high in ((i, j), (j, i)):
            a, b = buildings[low], buildings[high]
            if a.elevation[-1] < b.base_elevation - LEVEL_TOLERANCE:
                raise InputError(
                    f"building {a.name!r} stands wholly below the ground of building {b.name!r} (its roof at "
                    f"{a.elevation[-1]:g} m, the other's ground at {b.base_elevation:g} m), {d:.3g} m from it in "
                    "plan: its floors would face the other's foundation, which pound does not model; check "
                    "the base_elevation of both",
                    file=source,
                    field=f"buildings[{max(i, j)}].base_elevation",
                )


def combine(buildings: list[BuildingArrays]) -> System:
    """Number the floors, storeys and columns of several buildings into global arrays."""
    counts = [b.n_floors for b in buildings]
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    bottom, top, axes, col_storey, col_plan = [], [], [], [], []
    for b, bld in enumerate(buildings):
        f0 = int(start[b])
        for s in range(bld.n_floors):
            bottom.append(f0 + s - 1 if s > 0 else -1)
            top.append(f0 + s)
            axes.append((np.cos(bld.rotation), np.sin(bld.rotation)))
        for c in bld.columns:
            col_storey.append(f0 + c.storey)
            col_plan.append(bld.mass_centre[c.storey] + c.arm_top)
    rows = []
    for b, bld in enumerate(buildings):
        f0 = int(start[b])
        for m in bld.members:
            k0 = np.array(m.stiffness)
            rows.append((f0 + m.storey - 1 if m.storey > 0 else -1, f0 + m.storey, m.arm_bottom, m.arm_top,
                         (np.cos(m.angle), np.sin(m.angle)), k0, (1 - np.array(m.post_yield_ratio)) * k0,
                         (1 - np.array(m.post_yield_ratio)) * np.array(m.yield_force), int(m.coupled), b))  # fmt: skip
    cols = list(zip(*rows)) if rows else [[] for _ in range(10)]
    ints = {0, 1, 8, 9}
    members = MemberArrays(*[
        np.asarray(c, dtype=np.int64) if i in ints else np.asarray(c, dtype=float).reshape(-1, 2)
        for i, c in enumerate(cols)
    ])  # fmt: skip
    per_dof = [np.full(3 * b.n_floors, 1.0) for b in buildings]
    links = [(int(start[b]) + k.bottom if k.bottom >= 0 else -1, int(start[b]) + k.top, k.matrix)
             for b, bld in enumerate(buildings) for k in bld.damping_links]  # fmt: skip
    damping_links = DampingLinkArrays(
        matrix=np.array([k[2] for k in links], dtype=float).reshape(-1, 6, 6),
        bottom=np.array([k[0] for k in links], dtype=np.int64),
        top=np.array([k[1] for k in links], dtype=np.int64),
    )
    return System(
        buildings=buildings,
        floor_start=start,
        mass=np.concatenate([b.mass for b in buildings]),
        dof_a0=np.concatenate([b.rayleigh[0] * w for b, w in zip(buildings, per_dof)]),
        dof_a1=np.concatenate([b.rayleigh[1] * w for b, w in zip(buildings, per_dof)]),
        floor_centre=np.concatenate([b.mass_centre for b in buildings]),
        storey_k=np.ascontiguousarray(np.concatenate([b.storey_k for b in buildings])),
        storey_bottom=np.asarray(bottom, dtype=np.int64),
        storey_top=np.asarray(top, dtype=np.int64),
        storey_axes=np.asarray(axes, dtype=float).reshape(-1, 2),
        column_storey=np.asarray(col_storey, dtype=np.int64),
        column_plan=np.asarray(col_plan, dtype=float).reshape(-1, 2),
        members=members,
        damping_links=damping_links,
        influence=np.tile([1.0, 1.0, 0.0], int(start[-1])),
    )
