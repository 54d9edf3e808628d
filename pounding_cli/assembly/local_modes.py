"""The struck columns' own mass: their local bending modes as degrees of freedom (docs/theory.md,
"The struck columns' own mass").

A column clamped at both ends in a shear-type storey (height h, between floors 0 and 1) deflects
as w(ξ) = Σ_b ψ_b(ξ)·u_b + Σ_k φ_k(ξ)·q_k: the storey shapes ψ₀ = 1 − s(ξ), ψ₁ = s(ξ) (the
massless column's deflection under its ends' sway) plus the clamped–clamped modes φ_k
(cos βξ·cosh βξ = 1, β_k = 4.730, 7.853, 10.996, …; ∫₀¹ φ_k² dξ = 1), which vanish with their
slopes at both floors (Craig–Bampton). The modes are orthogonal to the storey shapes in
stiffness, so the column's strain energy is that of the storey plus ½·Σ k_k·q_k², k_k =
EI·β_k⁴/h³ = (12EI/h³)·β_k⁴/12; its kinetic energy couples them through the mass: with the
column's mass m = ρAh,

    T = ½·u̇ᵀM_bb·u̇ + Σ_k m·q̇_k·(w_k·u̇) + ½·Σ_k m·q̇_k²,   w_k = (∫ψ₀φ_k dξ, ∫ψ₁φ_k dξ).

In the coordinates y_k = q_k + w_k·u (the mode's mass's own displacement: "sprung mass") the
mass decouples: T = ½·u̇ᵀ(M_bb − Σ_k m·w_k·w_kᵀ)·u̇ + ½·Σ_k m·ẏ_k², and the strain energy
½·k_k·(y_k − w_k·u)² couples the mode's mass to the two floors through a spring. pound keeps a
diagonal mass matrix: the floors' block is lumped by rows (the user's floor masses hold the
columns' mass, half to each end floor, which is M_bb lumped by rows), so each floor gives up
m·w_b·Σw of its mass to each mode (tests/fe_study.py T6: the lumping moves durations by ≤ 0.2 %
and drifts by ≤ 0.034 % against the Craig–Bampton form). A rigid translation of the storey
moves the mode's mass by Σw (its ground influence; zero for the antisymmetric modes), so the
rigid-body mass is unchanged.

The columns a slab strikes (storey_contact.struck_columns) bend together: their bundle has one
set of modes, each a pseudo-floor of the struck building with mass Σρ_iA_ih along both plan axes
and the plan stiffness (β_k⁴/12)·ΣK_i (exact where the columns share ρA/EI, i.e. one section;
otherwise the bundle's, as their massless flexibilities are added). The bundle moves with the
floors at its own plan point (the columns' stiffness-weighted centre): floor b's (u_x, u_y, θ)
moves it by T_b·u_b = (u_x − θ·r_y, u_y + θ·r_x), r the point from floor b's mass centre. A
pseudo-floor's third DOF is inert (a rotation no force reaches, at the mode's frequency, with
Rayleigh's damping: it never moves).

The modes are damped at the building's first damping ratio (a dashpot 2ζ·ω_k·m on y_k − w_k·u,
in place of what Rayleigh's a1·K would give them, ζ = a1·ω_k/2: overdamped for ω_k of
thousands of rad/s).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .storey_contact import storey_shape

AUTO_RATIO = 8.0
"""column_modes = "auto": the highest mode's frequency on fixed floors over the contact's own
against the columns' mass, √(k_N·L/m). The FE comparison of tests/test_local_modes_fe.py (a
1 m contact line): the first impact's peak force is 7.6 % off at 3.9× (8 modes), 0.34 % at 8.4×
(12) and 0.18 % at 14.7× (16)."""

MAX_MODES = 16

INERT_RADIUS = 1.0
"""m: the radius of gyration that gives a pseudo-floor's inert rotation its inertia m·r²."""


@lru_cache(maxsize=None)
def clamped_beta(k: int) -> float:
    """β_k of the k-th (1-based) mode of a clamped–clamped beam of unit length: the k-th positive
    root of cos β·cosh β = 1 (4.730041, 7.853205, 10.995608, 14.137165, …)."""
    from scipy.optimize import brentq

    x0 = (k + 0.5) * np.pi
    return float(brentq(lambda x: np.cos(x) - 1.0 / np.cosh(x), x0 - 0.5, x0 + 0.5, xtol=1e-15, rtol=1e-15))


def clamped_mode(k: int, xi: np.ndarray | float) -> np.ndarray:
    """φ_k(ξ) = cosh βξ − cos βξ − σ(sinh βξ − sin βξ), σ = (cosh β − cos β)/(sinh β − sin β),
    normalised so that ∫₀¹ φ_k² dξ = 1 (the classical form has this property); evaluated as
    ½(1 − σ)e^{βξ} + ½(1 + σ)e^{−βξ} − cos βξ + σ sin βξ, with 1 − σ computed without
    cancellation."""
    b = clamped_beta(k)
    x = b * np.asarray(xi, dtype=float)
    den = np.sinh(b) - np.sin(b)
    sigma = (np.cosh(b) - np.cos(b)) / den
    one_minus = (np.cos(b) - np.sin(b) - np.exp(-b)) / den
    return 0.5 * one_minus * np.exp(x) + 0.5 * (1.0 + sigma) * np.exp(-x) - np.cos(x) + sigma * np.sin(x)


@lru_cache(maxsize=None)
def storey_weights(k: int) -> tuple[float, float]:
    """w_k = (∫₀¹(1 − s)φ_k dξ, ∫₀¹ s·φ_k dξ): mode k's mass coupling to the floor below and
    above, per unit of the column's mass (Gauss–Legendre, exact to rounding for k ≤ 40)."""
    x, wq = np.polynomial.legendre.leggauss(200)
    xi, wq = 0.5 * (x + 1.0), 0.5 * wq
    phi = clamped_mode(k, xi)
    s = storey_shape(xi)
    return float(wq @ ((1.0 - s) * phi)), float(wq @ (s * phi))


@lru_cache(maxsize=None)
def rotation_weights(k: int) -> tuple[float, float]:
    """(∫₀¹ ξ(1 − ξ)²φ_k dξ, ∫₀¹ ξ²(ξ − 1)φ_k dξ): mode k's couplings to the end rotations (the
    Hermite rotation shapes over h), which give the end moments its load puts into a clamped
    column (Betti: the end moment of a load q(ξ) is h·∫ shape·q)."""
    x, wq = np.polynomial.legendre.leggauss(200)
    xi, wq = 0.5 * (x + 1.0), 0.5 * wq
    phi = clamped_mode(k, xi)
    return float(wq @ (xi * (1.0 - xi) ** 2 * phi)), float(wq @ (xi**2 * (xi - 1.0) * phi))


@dataclass(frozen=True)
class LocalMode:
    """One local mode of a struck bundle of columns: a pseudo-floor of the struck building."""

    building: int  # the struck building
    storey: int  # 1-based storey of the bundle
    below: int  # the building's floor below the storey (−1: its ground)
    above: int  # the floor above
    number: int  # k, 1-based
    columns: tuple[int, ...]  # the bundle: indices into the building's `columns`
    mass: float  # Σρ_iA_ih, kg
    stiffness: np.ndarray  # (2, 2) (β_k⁴/12)·ΣK_i in global plan axes, N/m
    weights: tuple[float, float]  # w_k (below, above)
    arm_below: np.ndarray  # (2,) the bundle's point from the mass centre below, m (0 over the ground)
    arm_above: np.ndarray  # (2,) from the mass centre above, m
    damping_ratio: float  # ζ of the mode

    @property
    def omega(self) -> float:
        """The mode's largest circular frequency on fixed floors, rad/s."""
        return float(np.sqrt(np.linalg.eigvalsh(self.stiffness)[-1] / self.mass))

    def coupling(self) -> np.ndarray:
        """(2, 9) E: the mode's coordinate q = y − w₀·T₀·u₀ − w₁·T₁·u₁ = E·(u_below, u_above,
        pseudo-floor), T_b·u = (u_x − θ·r_y, u_y + θ·r_x) at the bundle's point (nothing from
        the ground below a first storey; the pseudo-floor's inert rotation not in it)."""
        e = np.zeros((2, 9))
        if self.below >= 0:
            e[:, :3] = -self.weights[0] * np.array([[1.0, 0.0, -self.arm_below[1]], [0.0, 1.0, self.arm_below[0]]])
        e[:, 3:6] = -self.weights[1] * np.array([[1.0, 0.0, -self.arm_above[1]], [0.0, 1.0, self.arm_above[0]]])
        e[:, 6:8] = np.eye(2)
        return e

    def spring(self) -> np.ndarray:
        """(9, 9) stiffness of the mode on (u_below, u_above, pseudo-floor): ½·qᵀK_k·q = ½·xᵀEᵀK_kE·x."""
        e = self.coupling()
        return e.T @ self.stiffness @ e


def bundle_modes(struck, building: int, storey: int, columns: tuple[int, ...], n_modes: int,
                 damping_ratio: float) -> list[LocalMode]:  # fmt: skip
    """The first n_modes local modes of a bundle of columns of `storey` (1-based) of the struck
    building (BuildingArrays); none where the columns have no mass (no density)."""
    cols = [struck.columns[i] for i in columns]
    mass = sum(c.mass for c in cols)
    if not mass > 0 or n_modes <= 0:
        return []
    k_plan = sum(c.plan_stiffness for c in cols)
    diag = np.array([np.trace(c.plan_stiffness) for c in cols])
    point_above = sum(d * c.arm_top for d, c in zip(diag, cols)) / diag.sum()
    above = storey - 1
    below = storey - 2
    arm_below = (point_above + struck.mass_centre[above] - struck.mass_centre[below]) if below >= 0 else np.zeros(2)
    return [LocalMode(building, storey, below, above, k, tuple(columns), float(mass),
                      clamped_beta(k) ** 4 / 12.0 * k_plan, storey_weights(k), arm_below, point_above, damping_ratio)
            for k in range(1, n_modes + 1)]  # fmt: skip


def highest_mode_ratio(n_modes: int, face_stiffness: float, column_stiffness: float) -> float:
    """How many times the contact's own frequency √(k_c/m) the highest of n_modes local modes
    reaches on fixed floors, √((β_n⁴/12)·K/m) over it (the columns' mass m cancels):
    face_stiffness k_c = k_N·L (N/m), column_stiffness K the struck columns' summed 12EI/h³
    along the façade's normal (N/m)."""
    return float(np.sqrt(clamped_beta(n_modes) ** 4 / 12.0 * column_stiffness / face_stiffness))


def auto_modes(face_stiffness: float, column_stiffness: float) -> int:
    """The fewest local modes (1 … MAX_MODES) whose highest reaches AUTO_RATIO times the
    contact's own frequency (highest_mode_ratio)."""
    for k in range(1, MAX_MODES + 1):
        if highest_mode_ratio(k, face_stiffness, column_stiffness) >= AUTO_RATIO:
            return k
    return MAX_MODES


def residual_fraction(xi: float, n_modes: int) -> float:
    """The part of a point load's local flexibility at ξ that n_modes local modes leave out:
    1 − (12/(4ξ³(1 − ξ)³))·Σ_k φ_k(ξ)²/β_k⁴ (the modes' static flexibility φ_k²·h³/(EI·β_k⁴)
    against a³b³/(3EIh³)); it stays in series with the overlap law (storey_contact)."""
    factor = 4.0 * xi**3 * (1.0 - xi) ** 3
    if n_modes <= 0 or factor <= 0.0:
        return 1.0
    modal = sum(clamped_mode(k, xi) ** 2 / clamped_beta(k) ** 4 for k in range(1, n_modes + 1))
    return max(0.0, 1.0 - 12.0 * float(modal) / factor)


def modal_mobility(xi: float, mass: float, n_modes: int) -> float:
    """Σ_k φ_k(ξ)²/m: what the local modes add to the struck outline's mobility, 1/kg."""
    if not mass > 0 or n_modes <= 0:
        return 0.0
    return float(sum(clamped_mode(k, xi) ** 2 for k in range(1, n_modes + 1))) / mass


@dataclass(frozen=True)
class BodyModes:
    """The local modes that move each storey body (contact.storeys order), for the solver:
    body k is moved by modes first[k] … first[k + 1] − 1, each by φ(ξ)·(y − w₀·T₀u₀ − w₁·T₁u₁)."""

    first: np.ndarray  # (n_s + 1,) int64
    floor: np.ndarray  # (n,) int64 global pseudo-floor of the mode
    phi: np.ndarray  # (n,) φ_k(ξ) of the body
    weights: np.ndarray  # (n, 2) w_k (below, above)
    arms: np.ndarray  # (n, 4) the bundle's point from the mass centre below (x, y) and above (x, y), m
    stiffness: np.ndarray  # (n, 2, 2) K_m, N/m
    theta: np.ndarray  # (n, 2) rotation_weights of the mode


NO_BODY_MODES = BodyModes(np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, 2)),
                          np.zeros((0, 4)), np.zeros((0, 2, 2)), np.zeros((0, 2)))  # fmt: skip


def mode_dashpot(mode: LocalMode) -> np.ndarray:
    """(2, 2) the mode's dashpot 2ζ·√m·K^½ (plan axes), N·s/m: damping ratio ζ along both of its
    principal axes."""
    w, v = np.linalg.eigh(mode.stiffness)
    return 2.0 * mode.damping_ratio * np.sqrt(mode.mass) * (v * np.sqrt(np.maximum(w, 0.0))) @ v.T


def _as_links(matrix: np.ndarray, below: int, above: int, pseudo: int) -> list[tuple[int, int, np.ndarray]]:
    """A 9 × 9 matrix on (floor below, floor above, pseudo-floor) as 6 × 6 two-floor links whose
    sum it is: (below, pseudo), (above, pseudo), (below, above); global floors, −1 the ground
    (whose DOFs are zero: its rows are dropped)."""
    b, a, p = slice(0, 3), slice(3, 6), slice(6, 9)

    def block(r0, r1, diag0=True, diag1=True):
        out = np.zeros((6, 6))
        if diag0:
            out[:3, :3] = matrix[r0, r0]
        out[:3, 3:] = matrix[r0, r1]
        out[3:, :3] = matrix[r1, r0]
        if diag1:
            out[3:, 3:] = matrix[r1, r1]
        return out

    if below < 0:
        return [(above, pseudo, block(a, p))]
    return [(below, pseudo, block(b, p)), (above, pseudo, block(a, p, diag1=False)),
            (below, above, block(b, a, diag0=False, diag1=False))]  # fmt: skip


def with_local_modes(system, contact, loaded):
    """(system, contact) with the struck columns' local modes as pseudo-floors: each building's
    floors are followed by the pseudo-floors of the bundles struck in it, and every floor index
    of both is renumbered; unchanged where no struck column has mass (module docstring)."""
    from dataclasses import replace

    from ..errors import InputError
    from .system import DampingLinkArrays

    model = loaded.model
    bundles: dict[tuple[int, int, tuple[int, ...]], list[LocalMode]] = {}
    body_bundle = []
    for body in contact.storeys:
        c = body.crossing
        key = (c.struck, c.storey, tuple(body.columns))
        if body.modes and key not in bundles:
            zeta = float(model.buildings[c.struck].damping.ratios[0])
            bundles[key] = bundle_modes(system.buildings[c.struck], c.struck, c.storey, body.columns, body.modes, zeta)
        body_bundle.append(key if body.modes else None)
    if not any(bundles.values()):
        return system, contact
    buildings = system.buildings
    n_b = len(buildings)
    per_building: list[list[LocalMode]] = [[] for _ in range(n_b)]
    for modes in bundles.values():
        for m in modes:
            per_building[m.building].append(m)
    old_start = system.floor_start
    counts = [int(old_start[b + 1] - old_start[b]) + len(per_building[b]) for b in range(n_b)]
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    n_old = int(old_start[-1])
    n_new = int(start[-1])

    def new(f: int) -> int:
        """A real floor's new global index (−1, the ground, stays)."""
        if f < 0:
            return f
        b = int(np.searchsorted(old_start, f, side="right")) - 1
        return int(start[b] + f - old_start[b])

    mode_floor: dict[int, int] = {}  # id(mode) → global pseudo-floor
    for b in range(n_b):
        for i, m in enumerate(per_building[b]):
            mode_floor[id(m)] = int(start[b] + old_start[b + 1] - old_start[b] + i)

    mass = np.zeros(3 * n_new)
    influence = np.zeros(3 * n_new)
    a0 = np.zeros(3 * n_new)
    a1 = np.zeros(3 * n_new)
    centre = np.zeros((n_new, 2))
    storey_k = np.zeros((n_new, 6, 6))
    bottom = np.full(n_new, -1, dtype=np.int64)
    top = np.arange(n_new, dtype=np.int64)
    axes = np.zeros((n_new, 2))
    for b in range(n_b):
        o0, o1, n0 = int(old_start[b]), int(old_start[b + 1]), int(start[b])
        real = slice(3 * n0, 3 * (n0 + o1 - o0))
        mass[real] = system.mass[3 * o0 : 3 * o1]
        influence[real] = np.tile([1.0, 1.0, 0.0], o1 - o0)
        a0[3 * n0 : 3 * int(start[b + 1])] = system.dof_a0[3 * o0]
        a1[3 * n0 : 3 * int(start[b + 1])] = system.dof_a1[3 * o0]
        centre[n0 : n0 + o1 - o0] = system.floor_centre[o0:o1]
        storey_k[n0 : n0 + o1 - o0] = system.storey_k[o0:o1]
        bottom[n0 : n0 + o1 - o0] = [new(int(f)) for f in system.storey_bottom[o0:o1]]
        axes[n0 : int(start[b + 1])] = system.storey_axes[o0]
    links, dashpots = [], []
    for b in range(n_b):
        bld = buildings[b]
        for m in per_building[b]:
            p = mode_floor[id(m)]
            total = sum(m.weights)
            above = new(int(old_start[b]) + m.above)
            below = new(int(old_start[b]) + m.below) if m.below >= 0 else -1
            for f, w, arm in ((below, m.weights[0], m.arm_below), (above, m.weights[1], m.arm_above)):
                if f < 0:
                    continue
                give = m.mass * w * total
                mass[3 * f : 3 * f + 2] -= give
                mass[3 * f + 2] -= give * float(arm @ arm)
            mass[3 * p : 3 * p + 3] = m.mass, m.mass, m.mass * INERT_RADIUS**2
            influence[3 * p : 3 * p + 2] = total
            centre[p] = bld.mass_centre[m.above] + m.arm_above
            storey_k[p, 5, 5] = m.mass * INERT_RADIUS**2 * m.omega**2  # the inert rotation, at the mode's ω
            spring = m.spring()
            links += _as_links(spring, below, above, p)
            e = m.coupling()
            # the mode's own dashpot in place of Rayleigh's a1·K on it (none where both are zero; the
            # inert rotation keeps a1·k_θ: nothing moves it)
            dashpots += [link for link in _as_links(e.T @ mode_dashpot(m) @ e - a1[3 * p] * spring, below, above, p)
                         if np.any(link[2])]  # fmt: skip
    bad = np.flatnonzero((mass[0::3] <= 0.0) | (mass[2::3] <= 0.0))
    if bad.size:
        b = int(np.searchsorted(start, bad[0], side="right")) - 1
        raise InputError(
            f"the local modes of the columns struck in building {buildings[b].name!r} take more mass (or rotational "
            f"inertia) from its floor {int(bad[0] - start[b]) + 1} than the floor has; the floors' masses must include "
            "their columns' (check the columns' density, kg/m³)",
            file=str(loaded.source),
            field="contact.column_modes",
        )
    old_links = system.damping_links
    damping_links = DampingLinkArrays(
        matrix=np.concatenate([old_links.matrix, np.array([d[2] for d in dashpots]).reshape(-1, 6, 6)]),
        bottom=np.array([new(int(f)) for f in old_links.bottom] + [d[0] for d in dashpots], dtype=np.int64),
        top=np.array([new(int(f)) for f in old_links.top] + [d[1] for d in dashpots], dtype=np.int64),
    )
    stiffness_links = DampingLinkArrays(
        matrix=np.array([k[2] for k in links]).reshape(-1, 6, 6),
        bottom=np.array([k[0] for k in links], dtype=np.int64),
        top=np.array([k[1] for k in links], dtype=np.int64),
    )
    members = system.members
    members = replace(members, bottom=np.array([new(int(f)) for f in members.bottom], dtype=np.int64),
                      top=np.array([new(int(f)) for f in members.top], dtype=np.int64))  # fmt: skip
    modes = [m for b in range(n_b) for m in per_building[b]]
    system = replace(system, floor_start=start, mass=mass, dof_a0=a0, dof_a1=a1, floor_centre=centre, storey_k=storey_k,
                     storey_bottom=bottom, storey_top=top, storey_axes=axes,
                     column_storey=np.array([new(int(s)) for s in system.column_storey], dtype=np.int64),
                     members=members, damping_links=damping_links, influence=influence,
                     stiffness_links=stiffness_links, local_modes=tuple(modes),
                     mode_floor=np.array([mode_floor[id(m)] for m in modes], dtype=np.int64))  # fmt: skip
    # the contact: floors renumbered, the storeys' virtual floors after the new ground, and the modes of each body
    body_floor = np.array([new(int(f)) if 0 <= f < n_old else (n_new + f - n_old if f > n_old else f)
                           for f in contact.body_floor], dtype=np.int64)  # fmt: skip
    first, floors, phis, weights, arms, stiffness, theta = [0], [], [], [], [], [], []
    for body, key in zip(contact.storeys, body_bundle):
        for m in bundles.get(key, []) if key is not None else []:
            floors.append(mode_floor[id(m)])
            phis.append(float(clamped_mode(m.number, body.crossing.xi)))  # the outline's motion per unit of q
            weights.append(m.weights)
            arms.append(np.concatenate([m.arm_below, m.arm_above]))
            stiffness.append(m.stiffness)
            theta.append(rotation_weights(m.number))
        first.append(len(floors))
    body_modes = BodyModes(np.array(first, dtype=np.int64), np.array(floors, dtype=np.int64), np.array(phis, dtype=float),
                           np.array(weights, dtype=float).reshape(-1, 2), np.array(arms, dtype=float).reshape(-1, 4),
                           np.array(stiffness, dtype=float).reshape(-1, 2, 2),
                           np.array(theta, dtype=float).reshape(-1, 2))  # fmt: skip
    contact = replace(contact, body_floor=body_floor,
                      storey_below=np.array([new(int(f)) for f in contact.storey_below], dtype=np.int64),
                      storey_above=np.array([new(int(f)) for f in contact.storey_above], dtype=np.int64),
                      body_modes=body_modes)  # fmt: skip
    return system, contact
