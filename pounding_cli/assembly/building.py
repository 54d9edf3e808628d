"""One building as arrays: floor masses at mass centres, storey stiffness matrices, its
global K, modes and damping (Rayleigh coefficients, and an isolated building's links).
Everything is in global plan coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model import Building, Material
from ..model.inelastic import Bearing, Hysteresis
from .columns import column_local_stiffness, column_plan_stiffness, storey_stiffness
from .damping import (
    DampingLink, damping_matrix, isolated_frequency, isolation_dashpots, isolation_links, modal_damping_ratios,
)  # fmt: skip
from .modal import Modes, modes, rayleigh_coefficients
from .polygon import polar_moment_about_centroid, polygon_area, polygon_centroid


@dataclass(frozen=True)
class ColumnLine:
    """A named column line of a building (the rows of the HDF5 `columns` table)."""

    name: str
    local: tuple[float, float]  # building coordinates, m
    plan: tuple[float, float]  # global coordinates, m
    section: tuple[float, float]  # [b_x, b_y] m, lowest storey where present
    angle: float  # degrees from the building's x axis


@dataclass(frozen=True)
class ColumnInstance:
    """A column in one storey, for interstorey deflections."""

    line: int  # index into the building's column lines
    storey: int  # 0 = ground storey
    arm_bottom: np.ndarray  # offset from the bottom floor's mass centre, m (global axes)
    arm_top: np.ndarray  # offset from the top floor's mass centre, m (global axes)
    stiffness: tuple[float, float] = (0.0, 0.0)  # 12EI/h³ along its local x, y, N/m (initial, if it yields)
    angle: float = 0.0  # rad, its local x axis from global X
    height: float = 0.0  # m, the storey's height (fixed-fixed end moments M = V·h/2)
    member: int = -1  # its index in the building's yielding members, −1 if it stays linear
    shear_capacity: tuple[float, float] | None = None  # N, along the column's local x and y (the model's)
    mass: float = 0.0  # ρ·A·h, kg (0: its material has no density; the floors' masses hold it)

    @property
    def plan_stiffness(self) -> np.ndarray:
        """(2, 2) lateral stiffness in global axes, N/m (fixed at both ends; initial, if it yields)."""
        return column_plan_stiffness(*self.stiffness, self.angle)


@dataclass(frozen=True)
class BuildingArrays:
    """A building turned into arrays (floors bottom up, DOFs u_x, u_y, θ per floor)."""

    name: str
    rotation: float  # rad, building x from global X
    mass: np.ndarray  # (3N,) diagonal of M: m, m, J per floor (kg, kg, kg·m²)
    mass_centre: np.ndarray  # (N, 2) global plan position, m
    elevation: np.ndarray  # (N,) floor level above the common ground datum, m (base_elevation + storey heights)
    slabs: list[np.ndarray]  # N counter-clockwise (n_v, 2) global outlines at rest, m
    storey_k: np.ndarray  # (N, 6, 6): storey s links floor s−1 (ground for s = 0) and s
    stiffness: np.ndarray  # (3N, 3N) global K of the building
    column_lines: list[ColumnLine]
    columns: list[ColumnInstance]
    modes: Modes
    rayleigh: tuple[float, float]  # (a0 1/s, a1 s)
    members: list["Member"]  # yielding members: inelastic columns, isolators
    isolated: bool = False  # floor 0 is a base slab on isolators
    damping_links: list[DampingLink] = field(default_factory=list)  # C − (a0·M + a1·K), damping.py
    rayleigh_modes: Modes | None = None  # the modes that fix (a0, a1): an isolated building's superstructure's on a fixed base
    base_elevation: float = 0.0  # m: the building's ground, the foot of its lowest storey

    @property
    def levels(self) -> np.ndarray:
        """(N + 1,) the building's ground and its floors, bottom up, m: storey j (1-based)
        spans levels[j − 1] to levels[j]."""
        return np.concatenate([[self.base_elevation], self.elevation])

    @property
    def height(self) -> float:
        """From the building's ground to its roof, m."""
        return float(self.elevation[-1] - self.base_elevation)

    @property
    def damping(self) -> np.ndarray:
        """Dense C (3N × 3N): Rayleigh, and for an isolated building its superstructure's on
        its deformation plus the isolation system's dashpots (damping.py)."""
        return damping_matrix(self.mass, self.stiffness, *self.rayleigh, self.damping_links)

    @property
    def n_floors(self) -> int:
        return self.elevation.size

    def fastest_rate(self) -> tuple[float, int, float]:
        """(ρ, mode, ζ): the largest |λ| of the building's modes under its damping, 1/s, and
        the mode (1-based) and damping ratio that give it. An underdamped mode's |λ| is ω; an
        overdamped one (ζ > 1) decays at up to ω·(ζ + √(ζ² − 1)) ≈ 2ζω, which exceeds ω_max
        where Rayleigh damping anchored at very slow modes overdamps the fast ones (ζ from the
        modal projection of C: exact for classical damping, an estimate with an isolated
        building's links)."""
        omega = self.modes.omega
        with np.errstate(all="ignore"):
            zeta = np.nan_to_num(modal_damping_ratios(self.damping, self.modes.shapes, omega), nan=0.0, posinf=np.inf)
            rate = np.where(zeta > 1.0, omega * (zeta + np.sqrt(np.maximum(zeta * zeta - 1.0, 0.0))), omega)
        k = int(np.argmax(np.where(np.isnan(rate), np.inf, rate)))
        return float(rate[k]), k + 1, float(zeta[k])


def _plan_transform(building: Building):
    phi = np.radians(building.rotation)
    rot = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    origin = np.asarray(building.origin, dtype=float)
    return phi, (lambda p: origin + rot @ np.asarray(p, dtype=float)), rot


@dataclass(frozen=True)
class Member:
    """A yielding member: an inelastic column in one storey, or an isolator. Its bilinear law
    acts along its local axes (angle from global X): initial stiffness k, yield force F_y,
    post-yield stiffness α·k per axis."""

    name: str  # column line or isolator name
    kind: str  # "column" or "isolator"
    storey: int  # building storey, 0 = lowest (the isolation storey of an isolated building)
    arm_bottom: np.ndarray  # offset from the bottom floor's mass centre, m (global; 0 on the ground)
    arm_top: np.ndarray  # offset from the top floor's mass centre, m (global)
    angle: float  # rad, local x axis from global X
    stiffness: tuple[float, float]  # initial k along local x, y, N/m
    yield_force: tuple[float, float]  # N
    post_yield_ratio: tuple[float, float]
    coupled: bool  # elliptical yield surface (else one spring per axis)


def assemble_building(
    building: Building,
    materials: dict[str, Material],
    field: str,
    source: str,
    laws: dict[str, Hysteresis] | None = None,
    bearings: dict[str, Bearing] | None = None,
) -> BuildingArrays:
    """Arrays of one building. `field` is its path in the model (for error messages)."""
    laws, bearings = laws or {}, bearings or {}
    phi, to_plan, rot = _plan_transform(building)
    storeys = building.storeys()
    iso = building.isolation
    # (height, slab, mass, J, eccentricity) bottom up; the base slab first when isolated
    levels = [(f.height, f.slab, f.mass, f.mass_per_area, f.rotational_inertia, f.eccentricity) for f in storeys]
    if iso is not None:
        levels.insert(0, (iso.height, iso.slab, iso.mass, iso.mass_per_area, iso.rotational_inertia, (0.0, 0.0)))
    base = 1 if iso is not None else 0
    n = len(levels)
    mass = np.empty(3 * n)
    centre = np.empty((n, 2))
    elevation = building.base_elevation + np.cumsum([lv[0] for lv in levels])
    slabs = []
    for i, (_, slab, m_given, m_area, j_given, ecc) in enumerate(levels):
        local = np.asarray(slab, dtype=float)
        area = polygon_area(local)
        m = m_given if m_given is not None else m_area * area
        j = j_given or m * polar_moment_about_centroid(local) / area
        mass[3 * i : 3 * i + 3] = m, m, j
        centre[i] = to_plan(polygon_centroid(local) + np.asarray(ecc))
        slabs.append(np.array([to_plan(p) for p in local]))

    lines: dict[str, int] = {}
    column_lines: list[ColumnLine] = []
    instances: list[ColumnInstance] = []
    members: list[Member] = []
    storey_k = np.empty((n, 6, 6))
    if iso is not None:
        plan_k, plan_k2, arms_b, arms_t = [], [], [], []
        for isolator in iso.all_isolators():
            bearing = bearings[isolator.bearing].constants()
            k1 = bearing.k1
            p = to_plan((isolator.x, isolator.y))
            plan_k.append(column_plan_stiffness(k1, k1, phi))
            plan_k2.append(column_plan_stiffness(bearing.k2, bearing.k2, phi))
            arms_b.append(np.zeros(2))
            arms_t.append(p - centre[0])
            fy = bearing.fy
            alpha = bearing.k2 / k1
            members.append(Member(isolator.name, "isolator", 0, np.zeros(2), arms_t[-1], phi, (k1, k1), (fy, fy),
                                  (alpha, alpha), bearings[isolator.bearing].interaction == "elliptical"))  # fmt: skip
        storey_k[0] = storey_stiffness(plan_k, arms_b, arms_t)
        storey_k2 = storey_stiffness(plan_k2, arms_b, arms_t)[3:, 3:]  # the bearings' K2 on the slab
        _check_storey(storey_k[0], 0, building, field, source)
    for s0, floor in enumerate(storeys):
        s = s0 + base
        plan_k, arms_b, arms_t = [], [], []
        for col in floor.all_columns():
            if col.name not in lines:
                lines[col.name] = len(column_lines)
                column_lines.append(
                    ColumnLine(col.name, (col.x, col.y), tuple(to_plan((col.x, col.y))), col.section, col.angle)
                )
            e = materials[col.material].elastic_modulus
            kx, ky = column_local_stiffness(e, *col.section, floor.height)
            angle = phi + np.radians(col.angle)
            plan_k.append(column_plan_stiffness(kx, ky, angle))
            p = to_plan((col.x, col.y))
            arm_b = p - centre[s - 1] if s > 0 else np.zeros(2)
            arms_b.append(arm_b)
            arms_t.append(p - centre[s])
            member = len(members) if col.hysteresis is not None else -1
            density = materials[col.material].density or 0.0
            instances.append(ColumnInstance(lines[col.name], s, arm_b, arms_t[-1], (kx, ky), angle, floor.height, member,
                                            col.shear_capacity, density * col.section[0] * col.section[1] * floor.height))  # fmt: skip
            if col.hysteresis is not None:
                law = laws[col.hysteresis]
                fy = law.yield_force or (kx * law.yield_deflection[0], ky * law.yield_deflection[1])
                a = law.post_yield_ratio
                members.append(Member(col.name, "column", s, arm_b, arms_t[-1], angle, (kx, ky), tuple(fy), (a, a),
                                      law.interaction == "elliptical"))  # fmt: skip
        storey_k[s] = storey_stiffness(plan_k, arms_b, arms_t)
        _check_storey(storey_k[s], s, building, field, source)

    stiffness = global_stiffness(storey_k)
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            building_modes = modes(stiffness, mass, phi)
    except np.linalg.LinAlgError:
        raise InputError(
            "its natural frequencies cannot be computed (stiffness and mass differ by too many orders "
            "of magnitude); check the units of column sections (m), heights (m), E (Pa) and masses (kg)",
            file=source,
            field=f"{field}.floors",
        ) from None
    # Rayleigh damping from two modes: the building's, or an isolated building's superstructure
    # on a fixed base (the base slab held: K and M without the slab's DOFs)
    anchor = building_modes
    whose = "the building has {n} modes (3 per floor)"
    if iso is not None:
        with np.errstate(over="ignore", invalid="ignore"):
            anchor = modes(stiffness[3:, 3:], mass[3:], phi)
        whose = "the superstructure (on a fixed base, which fixes its Rayleigh damping) has {n} modes (3 per floor)"
    (i, j), (zi, zj) = building.damping.modes, building.damping.ratios
    if max(i, j) > anchor.omega.size:
        raise InputError(
            f"mode {max(i, j)} asked for, but {whose.format(n=anchor.omega.size)}",
            file=source,
            field=f"{field}.damping.modes",
        )
    w = anchor.omega
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            rayleigh = rayleigh_coefficients(w[i - 1], w[j - 1], zi, zj)
    except ValueError as exc:
        raise InputError(
            f"modes {i} and {j}{' of the superstructure on a fixed base' if iso is not None else ''} have the "
            f"same frequency ({exc}), so Rayleigh damping cannot be fixed by them; choose two modes with "
            "different periods, e.g. [1, 3] for a symmetric building",
            file=source,
            field=f"{field}.damping.modes",
        ) from None
    links = []
    if iso is not None:
        total = float(mass[0::3].sum())
        if iso.damping_ratio > 0 and not isolated_frequency(storey_k2, total) > 0:
            raise InputError(
                "its bearings have no post-yield stiffness (K2 = 0), so the isolated frequency √(ΣK2/M) at "
                "which damping_ratio is a fraction of critical is zero; leave damping_ratio at 0 (the "
                "bearings' hysteresis damps the isolation system)",
                file=source,
                field=f"{field}.isolation.damping_ratio",
            )
        c_iso = isolation_dashpots(storey_k2, total, iso.damping_ratio)
        links = isolation_links(mass, centre, storey_k[0][3:, 3:], c_iso, *rayleigh)
    if not all(np.isfinite(rayleigh)) or not np.isfinite(w).all() or not np.isfinite(building_modes.omega).all():
        raise InputError(
            f"its natural frequencies ({w[-1]:.3g} rad/s at the highest) are beyond what can be "
            "computed; check the units of column sections (m), heights (m), E (Pa) and masses (kg)",
            file=source,
            field=f"{field}.floors",
        )
    return BuildingArrays(
        name=building.name,
        rotation=phi,
        mass=mass,
        mass_centre=centre,
        elevation=elevation,
        base_elevation=float(building.base_elevation),
        slabs=slabs,
        storey_k=storey_k,
        stiffness=stiffness,
        column_lines=column_lines,
        columns=instances,
        modes=building_modes,
        rayleigh=rayleigh,
        members=members,
        isolated=iso is not None,
        damping_links=links,
        rayleigh_modes=anchor,
    )


def global_stiffness(storey_k: np.ndarray) -> np.ndarray:
    """Dense 3N×3N K from storey matrices; storey 0's bottom is the fixed ground."""
    n = storey_k.shape[0]
    k = np.zeros((3 * n, 3 * n))
    for s in range(n):
        top = slice(3 * s, 3 * s + 3)
        k[top, top] += storey_k[s, 3:, 3:]
        if s > 0:
            bot = slice(3 * s - 3, 3 * s)
            k[bot, bot] += storey_k[s, :3, :3]
            k[bot, top] += storey_k[s, :3, 3:]
            k[top, bot] += storey_k[s, 3:, :3]
    return k


def _check_storey(k6: np.ndarray, s: int, building: Building, field: str, source: str) -> None:
    """A storey must resist x, y and torsion: its 3×3 stiffness against top-floor motion
    (bottom held) must be positive definite."""
    eig = np.linalg.eigvalsh(k6[3:, 3:])
    if eig[0] <= 1e-9 * eig[-1] and building.isolation is not None:
        if s == 0:
            raise InputError(
                "the base slab has no torsional stiffness (its isolators all stand at one plan point); "
                "add isolators elsewhere in plan", file=source, field=f"{field}.isolation",
            )  # fmt: skip
        s -= 1
    if eig[0] <= 1e-9 * eig[-1]:
        k = 0
        for idx, floor in enumerate(building.floors):
            if s < k + floor.repeat:
                break
            k += floor.repeat
        raise InputError(
            f"the storey below floor {s + 1} has no torsional stiffness (its columns all stand "
            "at one plan point); add columns elsewhere in plan",
            file=source,
            field=f"{field}.floors[{idx}]",
        )
