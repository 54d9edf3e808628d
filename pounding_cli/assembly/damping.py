"""Viscous damping of a building: Rayleigh damping, and for a base-isolated building the
superstructure's Rayleigh damping on its own deformation plus optional viscous damping of
the isolation system (docs/theory.md §4 and §12, "Damping of an isolated building").

A fixed-base building: C = a0·M + a1·K, (a0, a1) from two of its modes.

A base-isolated building (floor 0 the base slab, floors 1… the superstructure):

    C = Tᵀ·(a0·M_s + a1·K_s)·T + C_b,

T = [−R, I] the superstructure's displacements relative to the rigid motion of the base
slab (R_j maps the slab's (u_x, u_y, θ) to floor j's mass centre), M_s, K_s the mass and
stiffness of the superstructure on a fixed base and (a0, a1) Rayleigh coefficients from
two of its fixed-base modes; C_b = (2ζ_b/ω_b)·K_b,2, dashpots in parallel with the
isolators in proportion to their post-yield stiffness K2, ω_b = √(ΣK2/M) (M the building's
mass), so that the building moving rigidly on its bearings' K2 has ζ_b along x and y.
C·r = C_b·r for every rigid plan motion r of the whole building: the isolators' initial
stiffness and the building's mass no longer damp the isolated modes (Ryan & Polanco 2008).

The solver applies C as a0·M + a1·K DOF by DOF (what it always did) plus "links", 6×6
blocks on two floors (the ground for the bottom of one), which carry the difference:

    link (base slab, floor j) = a0·[[R_jᵀM_jR_j, −R_jᵀM_j], [−M_jR_j, 0]]
    link (ground, base slab)  = top-left zero, bottom-right −a0·M_b − a1·K_iso + C_b

(K_iso the isolation storey's stiffness on the slab). A fixed-base building has no links.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .columns import rigid_arm


@dataclass(frozen=True)
class DampingLink:
    """A 6×6 damping block on the DOFs (floor `bottom`, floor `top`) of one building, added
    to a0·M + a1·K; bottom −1 is the ground."""

    bottom: int
    top: int
    matrix: np.ndarray  # (6, 6), N·s/m, N·s, N·m·s


def rigid_map(centre: np.ndarray, base: int = 0) -> np.ndarray:
    """R (3N × 3): every floor's (u_x, u_y, θ) at its mass centre when the building moves
    rigidly with floor `base`'s (u_x, u_y, θ); centre (N, 2) mass centres, m."""
    n = centre.shape[0]
    r = np.zeros((3 * n, 3))
    for j in range(n):
        r[3 * j : 3 * j + 2] = rigid_arm(centre[j] - centre[base])
        r[3 * j + 2, 2] = 1.0
    return r


def isolation_links(mass: np.ndarray, centre: np.ndarray, k_iso: np.ndarray, c_iso: np.ndarray,
                    a0: float, a1: float) -> list[DampingLink]:  # fmt: skip
    """The links that turn a0·M + a1·K of an isolated building (floor 0 the base slab) into
    Tᵀ·(a0·M_s + a1·K_s)·T + C_b. mass (3N,) diagonal of M; centre (N, 2) mass centres;
    k_iso (3, 3) the isolation storey's stiffness on the slab (K1); c_iso (3, 3) C_b."""
    links = [DampingLink(-1, 0, np.zeros((6, 6)))]
    links[0].matrix[3:, 3:] = -a0 * np.diag(mass[:3]) - a1 * k_iso + c_iso
    for j in range(1, centre.shape[0]):
        r = np.vstack([rigid_arm(centre[j] - centre[0]), [0.0, 0.0, 1.0]])
        m = np.diag(mass[3 * j : 3 * j + 3])
        block = np.zeros((6, 6))
        block[:3, :3] = r.T @ m @ r
        block[:3, 3:] = -r.T @ m
        block[3:, :3] = -m @ r
        links.append(DampingLink(0, j, a0 * block))
    return links


def isolation_dashpots(k2_storey: np.ndarray, total_mass: float, zeta_b: float) -> np.ndarray:
    """C_b (3, 3) on the base slab: (2ζ_b/ω_b)·K_b,2 with K_b,2 the isolation storey's
    stiffness from the bearings' post-yield stiffness K2 (k2_storey, its 3×3 on the slab) and
    ω_b = √(ΣK2/M) the building's isolated frequency, rad/s. Zero when ζ_b = 0."""
    if zeta_b == 0.0:
        return np.zeros((3, 3))
    omega_b = isolated_frequency(k2_storey, total_mass)
    return 2.0 * zeta_b / omega_b * k2_storey


def isolated_frequency(k2_storey: np.ndarray, total_mass: float) -> float:
    """ω_b = √(ΣK2/M), rad/s: the building rigid on its bearings' post-yield stiffness, along
    a translation (the trace of the storey's translational block is 2·ΣK2)."""
    return float(np.sqrt(0.5 * (k2_storey[0, 0] + k2_storey[1, 1]) / total_mass))


def damping_matrix(mass: np.ndarray, stiffness: np.ndarray, a0: float, a1: float,
                   links: list[DampingLink]) -> np.ndarray:  # fmt: skip
    """Dense C (3N × 3N) of one building: a0·M + a1·K plus its links."""
    c = a0 * np.diag(mass) + a1 * stiffness
    for link in links:
        top = slice(3 * link.top, 3 * link.top + 3)
        c[top, top] += link.matrix[3:, 3:]
        if link.bottom >= 0:
            bot = slice(3 * link.bottom, 3 * link.bottom + 3)
            c[bot, bot] += link.matrix[:3, :3]
            c[bot, top] += link.matrix[:3, 3:]
            c[top, bot] += link.matrix[3:, :3]
    return c


def modal_damping_ratios(c: np.ndarray, shapes: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """ζ_n = φ_nᵀ·C·φ_n/(2ω_n) of mass-normalised modes (the diagonal of the modal damping
    matrix; C need not be classical), NaN for a mode of zero frequency."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.einsum("in,ij,jn->n", shapes, c, shapes) / (2.0 * omega)
