"""Driving the compiled time loop: prepare the step matrices, run in chunks (so progress can
be shown and Ctrl-C honoured between chunks), and collect the response.

The solver takes plain arrays (any object with the attributes of :class:`StructureArrays`);
it never imports pydantic, h5py or obspy.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Protocol

import numpy as np

from ..interrupts import stop_if_requested
from . import cdm, hybrid
from .sleep import awake_record
from .step_levels import contact_levels
from .step_plan import approach_levels
from . import contact as contact_kernel
from .broad_phase import sweep_arrays
from .layout import EV_COLUMNS, NOW_COLUMNS
from .peaks import KEPT_ROWS, between_arrays, crest_arrays, crest_series_order
from .propagator import building_propagators, state_matrix
from .records import (
    Bodies,
    CdmStep,
    Contact,
    Crests,
    Damping,
    Exact,
    Gauges,
    Ground,
    MemberLaw,
    Motion,
    Output,
    PairLaw,
    Peaks,
    Progress,
    Propagator,
    Propagators,
    StoreyBodies,
    Structure,
    Substeps,
    Work,
    Yielding,
)
from .tunables import (
    CREST_MARGIN,
    CREST_SPAN,
    DIVERGENCE_LIMIT,
    ENERGY_FLOOR_SPEED,
    ENERGY_LIMIT,
)

if TYPE_CHECKING:  # arrays only: the solver takes any object with these fields
    from ..assembly.force_gauges import ForceGauges


class StructureArrays(Protocol):
    """What the solver needs of a structure (see pounding_cli.assembly.system.System)."""

    mass: np.ndarray
    dof_a0: np.ndarray
    dof_a1: np.ndarray
    floor_start: np.ndarray
    floor_centre: np.ndarray
    storey_k: np.ndarray
    storey_bottom: np.ndarray
    storey_top: np.ndarray
    storey_axes: np.ndarray
    column_storey: np.ndarray
    column_plan: np.ndarray
    members: "MemberData"
    damping_links: "DampingLinkData"


class DampingLinkData(Protocol):
    """6×6 damping blocks added to a0·M + a1·K (see pounding_cli.assembly.system.DampingLinkArrays)."""

    matrix: np.ndarray
    bottom: np.ndarray
    top: np.ndarray


class MemberData(Protocol):
    """Yielding members (see pounding_cli.assembly.system.MemberArrays)."""

    bottom: np.ndarray
    top: np.ndarray
    arm_bottom: np.ndarray
    arm_top: np.ndarray
    axes: np.ndarray
    k0: np.ndarray
    kh: np.ndarray
    fh: np.ndarray
    coupled: np.ndarray


class ContactData(Protocol):
    """What the solver needs of the contact candidates (see pounding_cli.assembly.contact)."""

    body_poly: np.ndarray
    body_nv: np.ndarray
    body_floor: np.ndarray
    body_centre: np.ndarray
    body_radius: np.ndarray
    pair_a: np.ndarray
    pair_b: np.ndarray
    pair_kn: np.ndarray
    pair_kt: np.ndarray
    pair_mu_s: np.ndarray
    pair_mu_k: np.ndarray
    pair_cn: np.ndarray
    pair_zeta: np.ndarray
    pair_ct: np.ndarray
    pair_meff: np.ndarray
    storey_below: np.ndarray
    storey_above: np.ndarray
    storey_shape: np.ndarray
    storey_arm: np.ndarray


class NoContact:
    """No candidate pairs: the contact phase of the step costs nothing."""

    def __init__(self) -> None:
        self.body_poly = np.zeros((1, 3, 2))
        self.body_nv = np.zeros(1, dtype=np.int64)
        self.body_floor = np.zeros(1, dtype=np.int64)
        self.body_centre = np.zeros((1, 2))
        self.body_radius = np.zeros(1)
        self.pair_a = np.zeros(0, dtype=np.int64)
        self.pair_b = np.zeros(0, dtype=np.int64)
        for name in ("kn", "kt", "mu_s", "mu_k", "cn", "zeta", "ct", "meff"):
            setattr(self, f"pair_{name}", np.zeros(0))
        self.storey_below = np.zeros(0, dtype=np.int64)
        self.storey_above = np.zeros(0, dtype=np.int64)
        self.storey_shape = np.zeros(0)
        self.storey_arm = np.zeros((0, 2))


class NoMembers:
    """No yielding members: the structure is linear."""

    def __init__(self) -> None:
        self.bottom = np.zeros(0, dtype=np.int64)
        self.top = np.zeros(0, dtype=np.int64)
        self.coupled = np.zeros(0, dtype=np.int64)
        for name in ("arm_bottom", "arm_top", "axes", "k0", "kh", "fh"):
            setattr(self, name, np.zeros((0, 2)))


class NoDampingLinks:
    """No base-isolated building: C = a0·M + a1·K."""

    def __init__(self) -> None:
        self.matrix = np.zeros((0, 6, 6))
        self.bottom = np.zeros(0, dtype=np.int64)
        self.top = np.zeros(0, dtype=np.int64)


def damping_arrays(structure: StructureArrays) -> Damping:
    """The damping record of the compiled loop (cdm.damping_force): a0, a1 per DOF, the link
    matrices and their floors, bottoms on the ground mapped to the extra zero floor."""
    links = getattr(structure, "damping_links", None) or NoDampingLinks()
    bottom = np.where(links.bottom < 0, structure.mass.size // 3, links.bottom).astype(np.int64)
    return Damping(structure.dof_a0, structure.dof_a1, np.ascontiguousarray(links.matrix, dtype=float), bottom,
                   links.top)  # fmt: skip


CHUNK_SECONDS = 0.05
"""The time loop runs in calls of about this many seconds at most (beyond the first chunk):
progress is shown and Ctrl-C honoured between calls, and each call costs some tens of µs to
dispatch its arguments. Chunks double while calls are shorter than half of it; they do not
change the results (tests/test_bit_for_bit.py runs a scene in one-sample chunks too)."""

MAX_EVENTS = 200_000
"""Contact episodes logged at most; more are counted but not stored."""


@dataclass
class Response:
    """What a run produced. Histories are at the output interval, peaks over every step."""

    time: np.ndarray  # (n_out,) s
    displacement: np.ndarray  # (n_out, n_dof) relative to the ground, m / rad
    velocity: np.ndarray  # (n_out, n_dof) relative to the ground, m/s / rad/s
    acceleration: np.ndarray  # (n_out, n_dof) absolute, m/s² / rad/s²
    ground: np.ndarray  # (n_out, 2) ground acceleration X, Y, m/s²
    energy: np.ndarray  # (n_out, 7) J, columns cdm.ENERGY_NAMES
    peak_column: np.ndarray  # (n_columns, 2) peak |Δu| along building x, y, m
    peak_storey_rotation: np.ndarray  # (n_storeys,) peak |Δθ|, rad
    peak_displacement: np.ndarray  # (n_dof,) peak |u|
    peak_acceleration: np.ndarray  # (n_dof,) peak absolute |a|
    contact: np.ndarray  # (n_out, n_pairs, 6) per pair, columns layout.NOW_COLUMNS
    events: np.ndarray  # (n_events, layout.EV_COLUMNS) impact log rows
    events_total: int  # episodes, including any beyond MAX_EVENTS
    contact_steps: int  # steps in which some pair was in contact
    dt: float
    steps: int  # steps taken: CDM steps plus exact substeps
    wall_time: float  # s, time loop only
    status: str  # "complete" or "failed: …"
    compile_time: float = 0.0  # s, compiling or loading the kernel (first call in a process)
    integrator: str = "cdm"  # "cdm", or "hybrid" (exact propagation, CDM around contacts)
    exact_substeps: int = 0  # hybrid: steps taken by exact propagation (substeps, and shorter ones toward impacts)
    exact_steps_of_dt: int = 0  # hybrid: the time propagated exactly, in steps of dt
    cdm_steps: int = 0  # steps taken by the CDM
    slept_building_steps: int = 0  # hybrid: CDM steps the sleeping buildings were spared, summed over them
    sleeps: int = 0  # hybrid: how often a building fell asleep through a contact phase
    wakes: int = 0  # hybrid: how often a sleeping building woke inside a contact phase
    switches: int = 0  # hybrid: hand-overs between the two
    step_changes: int = 0  # hybrid: changes of a contact phase's step (step_levels.py)
    pair_dt_ratio: np.ndarray | None = None  # (n_pairs,) the longest step each pair's contacts took, over dt
    failure_dof: int = -1  # a failed run: the DOF that went bad first (or moved fastest)
    failure_step: int = -1  # a failed run: the step m whose state (at t_m = m·dt) failed a check first
    member_history: np.ndarray | None = None  # (n_out, n_members, 4) local δ_x, δ_y m, f_x, f_y N
    peak_member: np.ndarray | None = None  # (n_members, 6) |δ_x|, |δ_y|, |δ| m, |f_x|, |f_y|, |f| N
    residual_member: np.ndarray | None = None  # (n_members, 2) local deflection at rest after the run, m
    peak_gauge: np.ndarray | None = None  # (n_gauges,) running max |q| of the force gauges, N or N·m
    floor_contact: np.ndarray | None = None  # (n_out, n_dof) contact forces on the floors, N and N·m
    storey_shear_peak: np.ndarray | None = None  # (n_events, 14) struck columns with local modes: records.StoreyBodies.shear_peak


def ground_as_floor(structure: StructureArrays) -> np.ndarray:
    """Storey bottoms with the ground (−1) mapped to the extra zero floor at the end."""
    return np.where(structure.storey_bottom < 0, structure.mass.size // 3, structure.storey_bottom)


def influence_of(structure: StructureArrays) -> np.ndarray:
    """(n_dof,) the ground influence ι (System.influence; 1 on every floor's u_x, u_y without it)."""
    iota = getattr(structure, "influence", None)
    return np.tile([1.0, 1.0, 0.0], structure.mass.size // 3) if iota is None else np.asarray(iota, dtype=float)


def storeys_and_links(structure: StructureArrays) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(k, bottom, top) of the storeys followed by the stiffness links (the local modes'
    springs, System.stiffness_links), the ground as the extra floor: what the storey kernels
    (cdm._storey_product) take."""
    links = getattr(structure, "stiffness_links", None)
    bottom = ground_as_floor(structure)
    if links is None or links.matrix.shape[0] == 0:
        return structure.storey_k, bottom, structure.storey_top
    ground = structure.mass.size // 3
    return (np.ascontiguousarray(np.concatenate([structure.storey_k, links.matrix])),
            np.concatenate([bottom, np.where(links.bottom < 0, ground, links.bottom)]).astype(np.int64),
            np.concatenate([structure.storey_top, links.top]).astype(np.int64))  # fmt: skip


def stiffness_times(structure: StructureArrays, x: np.ndarray) -> np.ndarray:
    """K·x for a vector of n_dof + 3 entries (ground last), storey by storey and link by link,
    with numpy (for set-up: calling a compiled kernel from Python would load it from numba's
    cache)."""
    k, bottom, top = storeys_and_links(structure)
    dofs = np.array([0, 1, 2])
    index = np.hstack([3 * bottom[:, None] + dofs, 3 * top[:, None] + dofs])
    out = np.zeros_like(x)
    np.add.at(out, index, np.einsum("sij,sj->si", k, x[index]))
    return out


def ground_rate_response(structure: StructureArrays) -> np.ndarray:
    """The hybrid's exact_point work array (hybrid.N_RATES, n_dof + 3) with rows 5 and 6 set to
    M⁻¹·C·e_X and M⁻¹·C·e_Y (1/s), e_X, e_Y the floors' unit translations: the floor
    accelerations' second rate ä = −M⁻¹(K·a_rel + C·(ȧ − ȧ_g)) gains sx·row 5 + sy·row 6
    from the ground acceleration's rate (sx, sy), m/s³."""
    n = structure.mass.size
    rates = np.zeros((hybrid.N_RATES, n + 3))
    iota = influence_of(structure)
    for axis in range(2):
        unit = np.zeros(n + 3)
        unit[axis:n:3] = iota[axis::3]
        rates[5 + axis, :n] = damping_times(structure, unit)[:n] / structure.mass
    return rates


def damping_times(structure: StructureArrays, x: np.ndarray) -> np.ndarray:
    """C·x = a0·M·x + a1·K·x + Σ links·x for a vector of n_dof + 3 entries (the ground entries
    stay 0), with numpy, as cdm.damping_force computes it."""
    n = structure.mass.size
    out = np.zeros_like(x)
    out[:n] = structure.dof_a0 * structure.mass * x[:n] + structure.dof_a1 * stiffness_times(structure, x)[:n]
    _, _, link, bottom, top = damping_arrays(structure)
    if link.shape[0]:
        dofs = np.array([0, 1, 2])
        index = np.hstack([3 * bottom[:, None] + dofs, 3 * top[:, None] + dofs])
        np.add.at(out, index, np.einsum("sij,sj->si", link, x[index]))
        out[n:] = 0.0
    return out


def building_dofs(structure: StructureArrays) -> tuple[np.ndarray, np.ndarray]:
    """(first DOF, number of DOFs) of every building."""
    starts = 3 * np.asarray(structure.floor_start[:-1], dtype=np.int64)
    counts = 3 * np.diff(structure.floor_start).astype(np.int64)
    return starts, counts


def stiffness_blocks(structure: StructureArrays, times: Callable = stiffness_times) -> list[np.ndarray]:
    """Dense K of every building, column by column from the solver's own storey kernel (or
    the dense matrix of another operator `times`, e.g. damping_times). Buildings share no
    storey or damping link, so column j of every building comes from one product with a unit
    entry in each of them: the same sums, storey by storey, as one building at a time, in
    (DOFs of the largest building) products rather than (all DOFs)."""
    starts, counts = building_dofs(structure)
    x = np.zeros(structure.mass.size + 3)
    blocks = [np.empty((n, n)) for n in counts]
    for j in range(int(counts.max(initial=0))):
        x[:] = 0.0
        x[(starts + j)[counts > j]] = 1.0
        column = times(structure, x)
        for k, d0, n in zip(blocks, starts, counts):
            if j < n:
                k[:, j] = column[d0 : d0 + n]
    return blocks


def fastest_rate(stiffness: list[np.ndarray], damping: list[np.ndarray], mass: np.ndarray, starts, counts) -> float:
    """The largest |λ| of the buildings' state matrices [[0, I], [−M⁻¹K, −M⁻¹C]], 1/s: ω_max
    where every mode is underdamped, more where a mode is overdamped. The exact motion's
    derivatives grow as its powers (peaks.crest_series_order)."""
    rho = 0.0
    for k, c, d0, n in zip(stiffness, damping, starts, counts):
        rho = max(rho, float(np.max(np.abs(np.linalg.eigvals(state_matrix(k, c, mass[d0 : d0 + n]))))))
    return rho


def damping_blocks(structure: StructureArrays) -> list[np.ndarray]:
    """Dense C of every building, column by column, as the time loop applies it."""
    return stiffness_blocks(structure, damping_times)


def step_matrices(structure: StructureArrays, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(B⁻¹ blocks padded to (n_b, n_max, n_max), DOF start, DOF count) with B = M/Δt + C/2."""
    starts, counts = building_dofs(structure)
    n_max = int(counts.max())
    binv = np.zeros((starts.size, n_max, n_max))
    for b, (d0, n, nr, c) in enumerate(zip(starts, counts, real_dofs(structure, counts), damping_blocks(structure))):
        m = structure.mass[d0 : d0 + n]
        binv[b, :n, :n] = _factored(np.diag(m / dt) + c / 2, int(nr)) if nr < n else np.linalg.inv(np.diag(m / dt) + c / 2)
    return binv, starts, counts


def real_dofs(structure: StructureArrays, counts: np.ndarray) -> np.ndarray:
    """(n_buildings,) the DOFs of each building's own floors (System.real_floors; all of them
    where it has no local modes)."""
    buildings = getattr(structure, "buildings", None)
    if not getattr(structure, "local_modes", ()) or buildings is None:
        return np.asarray(counts, dtype=np.int64)
    return np.array([3 * b.n_floors for b in buildings], dtype=np.int64)


def _factored(b: np.ndarray, nr: int) -> np.ndarray:
    """[[S⁻¹, B_rp], [G, B_pp⁻¹]] of B with its DOFs nr… the local modes' (cdm._solve_reduced):
    S = B_rr − B_rp·G, G = B_pp⁻¹·B_pr, B_pp⁻¹ by 3 × 3 blocks."""
    n = b.shape[0]
    bpp_inv = np.zeros((n - nr, n - nr))
    blocks = np.zeros_like(bpp_inv)
    for j in range(0, n - nr, 3):
        blocks[j : j + 3, j : j + 3] = b[nr + j : nr + j + 3, nr + j : nr + j + 3]
        bpp_inv[j : j + 3, j : j + 3] = np.linalg.inv(blocks[j : j + 3, j : j + 3])
    if not np.array_equal(blocks, b[nr:, nr:]):
        raise ValueError("the local modes' block of M/Δt + C/2 is not block-diagonal: a mode linked to another")
    g = bpp_inv @ b[nr:, :nr]
    out = np.zeros_like(b)
    out[:nr, :nr] = np.linalg.inv(b[:nr, :nr] - b[:nr, nr:] @ g)
    out[:nr, nr:] = b[:nr, nr:]
    out[nr:, :nr] = g
    out[nr:, nr:] = bpp_inv
    return out


def peak_geometry(structure: StructureArrays) -> tuple[np.ndarray, np.ndarray]:
    """(mass centres with a zero ground row appended, column (ξ, η)) for cdm.update_peaks."""
    centre = np.vstack([structure.floor_centre, np.zeros((1, 2))])
    axes = structure.storey_axes[structure.column_storey]
    px, py = structure.column_plan[:, 0], structure.column_plan[:, 1]
    c, s = axes[:, 0], axes[:, 1]
    return centre, np.column_stack([-c * py + s * px, s * py + c * px])


def bounding_boxes(contact: ContactData) -> np.ndarray:
    """(n_bodies, 4) x_min, y_min, x_max, y_max of each outline at rest, m."""
    box = np.empty((contact.body_nv.size, 4))
    for k, n in enumerate(contact.body_nv):
        pts = contact.body_poly[k, : max(int(n), 1)]
        box[k] = pts[:, 0].min(), pts[:, 1].min(), pts[:, 0].max(), pts[:, 1].max()
    return box


def _leading_good_rows(out_u: np.ndarray, out_energy: np.ndarray) -> int:
    """How many output rows from the start were written and hold a sane state."""
    with np.errstate(invalid="ignore"):
        good = np.isfinite(out_energy[:, 0]) & (np.abs(out_u) <= DIVERGENCE_LIMIT).all(axis=1)
    return int(good.size if good.all() else np.argmin(good))


def simulate(
    structure: StructureArrays,
    ground: np.ndarray,
    ground_dt: float,
    dt: float,
    stride: int,
    n_steps: int,
    progress: Callable[[int, int], None] | None = None,
    chunk: int = 20_000,
    contact: ContactData | None = None,
    initial_velocity: np.ndarray | None = None,
    substep: int = 0,
    sweep: bool | None = None,
    yield_substep: int = 0,
    gauges: ForceGauges | None = None,
    pair_step_ratio: np.ndarray | None = None,
) -> Response:
    """Integrate over n_steps steps of dt; ground is (n, 2) m/s² every ground_dt.

    substep = 0: the CDM at every step. substep = s > 0: the hybrid integrator, exact
    propagation over substeps of s·dt while no contact is possible, the CDM at dt around
    contacts (n_steps and stride must then be multiples of s, and s·dt must divide
    ground_dt so that the ground acceleration is linear within each substep).
    yield_substep = s_y (1 ≤ s_y ≤ s; 0: s): the hybrid's CDM takes s_y steps per substep
    where only yielding members need it (no contact possible).
    gauges: the storey shears and column forces whose running peaks to follow
    (assembly.force_gauges; none if None). pair_step_ratio (n_pairs,): how many times longer
    than dt each pair's own contact lets the step be (≥ 1): the hybrid's contact phases then
    take the longest step that the pairs which may touch in them allow (step_levels.py);
    None: every phase at dt. Plain CDM runs and runs with yielding members take dt throughout.
    The structure starts undeformed, at rest or with `initial_velocity` (n_dof,) relative to
    the ground, and out of contact. The contact broad phase sweeps and prunes (sweep=True) or
    tests every pair (False); None chooses the cheaper for the scene (broad_phase.sweep_pays).
    The results are the same, bit for bit; only the cost differs.
    """
    n_dof = structure.mass.size
    n_storeys = structure.storey_k.shape[0]
    n_out = n_steps // stride + 1
    binv, starts, counts = step_matrices(structure, dt)
    centre, col_arm = peak_geometry(structure)
    storey_k, storey_bottom, storey_top = storeys_and_links(structure)
    iota = influence_of(structure)
    structure_rec = Structure(structure.mass, damping_arrays(structure), storey_k, storey_bottom, storey_top, starts,
                              counts, structure.storey_axes, centre, structure.column_storey, col_arm,
                              np.arange(starts.size, dtype=np.int64), iota, structure.mass * iota,
                              real_dofs(structure, counts))  # fmt: skip
    ground_rec = Ground(ground, ground_dt)
    # classical CDM start: v_{-1/2} = v_0 − Δt/2·a_0 with M·a_0 = −M·ι·a_g(0) − C·v_0
    v0 = np.zeros(n_dof + 3)
    if initial_velocity is not None:
        v0[:n_dof] = initial_velocity
    c_v0 = damping_times(structure, v0)
    a0 = np.zeros(n_dof + 3)
    a0[0:n_dof:3] = -ground[0, 0] * iota[0::3]
    a0[1:n_dof:3] = -ground[0, 1] * iota[1::3]
    a0[:n_dof] -= c_v0[:n_dof] / structure.mass
    v_half = v0 - 0.5 * dt * a0
    v_half[n_dof:] = 0.0
    acc = np.zeros(cdm.N_ACC)
    acc[cdm.ACC_FRESH] = 1.0
    acc[cdm.ACC_ENERGY_FLOOR] = 0.5 * float(structure.mass[0::3].sum()) * ENERGY_FLOOR_SPEED**2
    acc[cdm.ACC_INPUT] = 0.5 * float(np.sum(structure.mass * v0[:n_dof] ** 2))  # an initial motion's energy
    motion = Motion(np.zeros(n_dof + 3), v_half, np.zeros(n_dof + 3), damping_times(structure, v_half), acc)
    work = Work(*(np.zeros(n_dof + 3) for _ in range(6)), np.zeros((n_storeys, 3)))
    yielding = yielding_state(structure, n_out)
    n_members = yielding.plastic.shape[0]
    gauge_rec = gauge_state(gauges, structure_rec, yielding)
    peaks = Peaks(np.zeros((structure.column_storey.size, 2)), np.zeros(n_storeys), np.zeros(n_dof), np.zeros(n_dof),
                  gauge_rec)  # fmt: skip
    c = contact if contact is not None else NoContact()
    n_pairs = c.pair_a.size
    out = Output(*(np.full((n_out, n_dof), np.nan) for _ in range(3)), np.full((n_out, 2), np.nan),
                 np.full((n_out, 7), np.nan),
                 np.full((n_out, n_pairs, len(NOW_COLUMNS)), np.nan),
                 np.full((n_out, n_dof), np.nan))  # fmt: skip
    contact_rec = contact_state(c, n_dof, sweep)
    floor_start = np.append(starts, n_dof).astype(np.int64) // 3
    counters = np.zeros(hybrid.N_COUNTERS, dtype=np.int64)
    counters[hybrid.CNT_FAILED_STEP] = -1
    if substep > 0:
        if n_steps % substep or stride % substep:
            raise ValueError("n_steps and stride must be multiples of substep")
        h = substep * dt
        sub_y = yield_substep if 0 < yield_substep < substep else substep
        grid = Substeps(h, n_steps // substep, stride // substep, int(round(ground_dt / h)))
        contact_step = CdmStep(h / substep, binv, stride // substep * substep, substep)
        binv_y = step_matrices(structure, h / sub_y)[0] if sub_y != substep else binv
        yield_step = CdmStep(h / sub_y, binv_y, stride // substep * sub_y, sub_y)
        propagators, exact = exact_branch(structure, structure_rec, v0, h, substep, stride, ground_dt, n_pairs > 0,
                                          n_members > 0, gauge_rec.storey.size)  # fmt: skip
        fine = 1 << (propagators.levels.phi.shape[0] - 1)
        phase_steps = contact_levels(contact_step, fine, sub_y, lambda step: step_matrices(structure, step)[0],
                                     pair_step_ratio if n_members == 0 and fine > 1 else None, n_pairs, n_dof)  # fmt: skip
        progress_state = Progress(np.zeros(1, dtype=np.int64), counters)
        awake = awake_record(may_sleep(propagators, n_pairs, n_members, structure_rec, floor_start), floor_start,
                             structure.column_storey, gauge_rec.first, contact_rec.bodies.floor,
                             contact_rec.storeys.above)  # fmt: skip
        unit, total = substep, n_steps // substep

        def advance(start: int, stop: int) -> tuple[int, int]:
            return hybrid.hybrid_advance(start, stop, grid, structure_rec, ground_rec, contact_step, phase_steps,
                                         yield_step, propagators, exact, motion, work, peaks, out, contact_rec,
                                         yielding, progress_state, awake)  # fmt: skip
    else:
        unit, total = 1, n_steps
        step = CdmStep(dt, binv, stride, 1)
        phase_steps = None
        awake = awake_record(False, floor_start, structure.column_storey, gauge_rec.first, contact_rec.bodies.floor,
                             contact_rec.storeys.above)  # fmt: skip

        def advance(start: int, stop: int) -> tuple[int, int]:
            status, done = cdm.advance(start, stop, step, structure_rec, ground_rec, motion, work, peaks, out,
                                       contact_rec, yielding, awake)  # fmt: skip
            counters[hybrid.CNT_CDM] += min(done, total) - start  # the pass at t_N ends the run: not a step
            if status != cdm.STATUS_OK:
                counters[hybrid.CNT_FAILED_STEP] = done
            return status, done

    chunk = max(1, chunk // unit)
    per_output = stride // substep if substep > 0 else 1  # hybrid chunks end at output samples,
    chunk = max(per_output, chunk // per_output * per_output)  # never inside a double substep
    t0 = time.perf_counter()
    advance(0, 0)  # nothing to do: compiles the kernel, or loads it from numba's cache
    compile_time = time.perf_counter() - t0
    status, done = cdm.STATUS_OK, 0
    wall = 0.0
    try:
        while done <= total and status == cdm.STATUS_OK:
            stop = min(done + chunk, total + 1)
            t0 = time.perf_counter()
            status, done = advance(done, stop)
            took = time.perf_counter() - t0
            wall += took
            if took < 0.5 * CHUNK_SECONDS and chunk < total:  # a call costs tens of µs: make them few
                chunk *= 2
            stop_if_requested()
            if progress is not None:
                progress(min(done, total), total)
            if done > total:
                break
    except KeyboardInterrupt:
        status = -1
    done *= unit
    failed_step = int(counters[hybrid.CNT_FAILED_STEP])
    u = motion.u
    if status == cdm.STATUS_OK:
        text, valid = "complete", n_out
    elif status == cdm.STATUS_DIVERGED:
        valid = _leading_good_rows(out.displacement, out.energy)
        what = (f"a displacement exceeded {DIVERGENCE_LIMIT:g} m" if np.isfinite(u[:n_dof]).all()
                else "the state became NaN or infinite")  # fmt: skip
        text = f"failed: diverged at step {failed_step} (t = {failed_step * dt:.6g} s): {what}; Δt = {dt:.3g} s may be too large"
    elif status == cdm.STATUS_ENERGY:
        valid = _leading_good_rows(out.displacement, out.energy)
        text = (
            f"failed: unstable at step {failed_step} (t = {failed_step * dt:.6g} s): the energy balance error passed "
            f"{100 * ENERGY_LIMIT:g} % of the energy in play, or the contacts gave out more energy than they took "
            f"by {100 * ENERGY_LIMIT:g} % of the input; Δt = {dt:.3g} s is too large for the "
            'stiffest vibration (structure or contact): use dt = "auto" or a smaller step'
        )
    else:
        text = "failed: interrupted"
        valid = _leading_good_rows(out.displacement, out.energy)
    cut = slice(0, valid)
    events, n_events = contact_rec.events, int(contact_rec.n_events[0])
    return Response(
        time=np.arange(valid) * stride * dt,
        displacement=out.displacement[cut],
        velocity=out.velocity[cut],
        acceleration=out.acceleration[cut],
        ground=out.ground[cut],
        energy=out.energy[cut],
        peak_column=peaks.column,
        peak_storey_rotation=peaks.storey_rotation,
        peak_displacement=peaks.displacement,
        peak_acceleration=peaks.acceleration,
        contact=out.contact[cut],
        events=events[: min(n_events, events.shape[0])].copy() if n_pairs else events[:0].copy(),
        events_total=n_events,
        contact_steps=int(motion.energy[cdm.ACC_CONTACT_STEPS]),
        dt=dt,
        steps=int(counters[hybrid.CNT_EXACT] + counters[hybrid.CNT_CDM]),
        wall_time=wall,
        status=text,
        compile_time=compile_time,
        integrator="hybrid" if substep > 0 else "cdm",
        exact_substeps=int(counters[hybrid.CNT_EXACT]),
        exact_steps_of_dt=int(counters[hybrid.CNT_EXACT_SPAN]),
        cdm_steps=int(counters[hybrid.CNT_CDM]),
        slept_building_steps=int(counters[hybrid.CNT_SLEPT]),
        sleeps=int(counters[hybrid.CNT_SLEEPS]),
        wakes=int(counters[hybrid.CNT_WAKES]),
        switches=int(counters[hybrid.CNT_SWITCHES]),
        step_changes=int(counters[hybrid.CNT_STEP_CHANGES]),
        pair_dt_ratio=(phase_steps.dt[phase_steps.pair_level] / dt if phase_steps is not None else np.ones(n_pairs)),
        failure_dof=(_failure_dof(u[:n_dof], motion.v_half[:n_dof])
                     if status in (cdm.STATUS_DIVERGED, cdm.STATUS_ENERGY) else -1),  # fmt: skip
        failure_step=failed_step if status in (cdm.STATUS_DIVERGED, cdm.STATUS_ENERGY) else -1,
        member_history=yielding.history[cut] if n_members else None,
        peak_member=yielding.peak if n_members else None,
        residual_member=residual_deflections(structure, yielding.plastic, yielding.law) if n_members else None,
        peak_gauge=gauge_rec.peak,
        floor_contact=out.floor_contact[cut],
        storey_shear_peak=(contact_rec.storeys.shear_peak[: min(n_events, events.shape[0])].copy()
                           if contact_rec.storeys.shear_peak.shape[0] else None),  # fmt: skip
    )


def contact_state(contact: ContactData, n_dof: int, sweep: bool | None = None) -> Contact:
    """The contact record of the time loop (records.Contact): the candidates' outlines and
    law, the broad phase (sweep and prune where `sweep`, or where None and it pays), and their
    state, out of contact, with room for MAX_EVENTS episodes."""
    c = contact
    box = bounding_boxes(c)
    n_pairs = c.pair_a.size
    n_storeys = getattr(c, "storey_shape", np.zeros(0)).size
    return Contact(
        Bodies(c.body_poly, c.body_nv, c.body_floor, c.body_centre, c.body_radius, box),
        PairLaw(c.pair_a, c.pair_b, c.pair_kn, c.pair_kt, c.pair_mu_s, c.pair_mu_k, c.pair_cn, c.pair_zeta, c.pair_ct,
                c.pair_meff),  # fmt: skip
        sweep_arrays(c.pair_a, c.pair_b, c.body_floor, box, sweep),
        np.zeros((n_pairs, contact_kernel.N_STATE)),
        np.zeros((n_pairs, len(NOW_COLUMNS))),
        np.zeros((MAX_EVENTS if n_pairs else 1, EV_COLUMNS)),
        np.zeros(1, dtype=np.int64),
        np.zeros(n_dof + 3 + 3 * n_storeys),
        np.zeros(n_dof + 3),
        contact_kernel.buffers(int(c.body_poly.shape[1])),
        storey_bodies(c, n_dof, MAX_EVENTS if n_pairs else 1),
    )


def storey_bodies(contact: ContactData, n_dof: int, n_rows: int = 1) -> StoreyBodies:
    """The struck storeys as virtual floors (records.StoreyBodies, storey_bodies.py): the
    ground's slot n_dof/3 stands for the floor below the first storey; with local modes, room
    for the struck columns' shears of n_rows impacts."""
    none = NoContact()
    shape, below, above, arm = (getattr(contact, name, getattr(none, name))
                                for name in ("storey_shape", "storey_below", "storey_above", "storey_arm"))  # fmt: skip
    size = n_dof + 3 + 3 * shape.size
    modes = getattr(contact, "body_modes", None)
    if modes is None or modes.floor.size == 0:
        first = np.zeros(shape.size + 1, dtype=np.int64)
        floor, phi, weight, arms = np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, 2)), np.zeros((0, 4))
        stiffness, theta, n_rows = np.zeros((0, 2, 2)), np.zeros((0, 2)), 0
    else:
        first, floor, phi, weight, arms = modes.first, modes.floor, modes.phi, modes.weights, modes.arms
        stiffness, theta = modes.stiffness, modes.theta
    storeys = getattr(contact, "storeys", [])
    xi = np.array([b.crossing.xi for b in storeys], dtype=float)
    height = np.array([b.crossing.height for b in storeys], dtype=float)
    n_pairs = contact.pair_a.size
    return StoreyBodies(np.where(below < 0, n_dof // 3, below).astype(np.int64), above.astype(np.int64),
                        shape.astype(float), np.ascontiguousarray(arm, dtype=float).reshape(-1, 2),
                        np.zeros(size), np.zeros(size), np.zeros(size), np.asarray(first, dtype=np.int64),
                        np.asarray(floor, dtype=np.int64), np.asarray(phi, dtype=float),
                        np.ascontiguousarray(weight, dtype=float).reshape(-1, 2),
                        np.ascontiguousarray(arms, dtype=float).reshape(-1, 4),
                        np.ascontiguousarray(stiffness, dtype=float).reshape(-1, 2, 2),
                        np.ascontiguousarray(theta, dtype=float).reshape(-1, 2),
                        np.arange(n_pairs - shape.size, n_pairs, dtype=np.int64),  # storey pairs come last
                        np.column_stack([xi * (1 - xi) ** 2, xi**2 * (xi - 1)]).reshape(-1, 2) * height[:, None],
                        height, bundle_stiffness(contact, first), residual_masses(contact, first),
                        np.zeros((shape.size, 2)),
                        np.full(shape.size, -1, dtype=np.int64), np.zeros((n_rows, 14)))  # fmt: skip


def bundle_stiffness(contact: ContactData, first: np.ndarray) -> np.ndarray:
    """(n_s, 2, 2) each storey body's struck columns' summed plan stiffness, N/m (from its first
    local mode's, (β₁⁴/12)·ΣK_i); zero where it has no local modes."""
    from ..assembly.local_modes import clamped_beta

    storeys = getattr(contact, "storeys", [])
    out = np.zeros((len(storeys), 2, 2))
    for k in range(len(storeys)):
        if first[k + 1] > first[k]:
            out[k] = contact.body_modes.stiffness[first[k]] * 12.0 / clamped_beta(1) ** 4
    return out


def residual_masses(contact: ContactData, first: np.ndarray) -> np.ndarray:
    """(n_s, 2, 2) each storey body's struck bundle's mass that moves with the floors,
    m·[[13/35, 9/70], [9/70, 13/35]] − Σ_m m·w_m·w_mᵀ (the storey shapes' consistent mass less
    what the modes carry), kg; zero where it has no local modes."""
    storeys = getattr(contact, "storeys", [])
    out = np.zeros((len(storeys), 2, 2))
    modes = getattr(contact, "body_modes", None)
    for k, body in enumerate(storeys):
        if first[k + 1] > first[k]:
            w = modes.weights[first[k] : first[k + 1]]
            out[k] = body.bundle_mass * (np.array([[13 / 35, 9 / 70], [9 / 70, 13 / 35]]) - w.T @ w)
    return out


def may_sleep(propagators: Propagators, n_pairs: int, n_members: int, structure: Structure,
              floor_start: np.ndarray) -> bool:
    """Whether buildings may sleep through contact phases (solver/sleep.py): the hybrid's
    contact phases run finest step by finest step (approach levels), there are several
    buildings and contact pairs, and the buildings are coupled by contact alone (no damping
    links; no yielding members, whose return map and static offset work on the whole
    structure)."""
    levels = propagators.levels.phi.shape[0] - 1
    return (levels > 0 and n_pairs > 0 and n_members == 0 and structure.damping.link.shape[0] == 0
            and floor_start.size > 2)  # fmt: skip


def yielding_state(structure: StructureArrays, n_out: int) -> Yielding:
    """The yielding members' record (records.Yielding), elastic at the start; none for a
    linear structure."""
    mem = getattr(structure, "members", None) or NoMembers()
    n_members = mem.top.size
    n_floors = structure.mass.size // 3
    bottom = np.where(mem.bottom < 0, n_floors, mem.bottom).astype(np.int64)
    law = MemberLaw(bottom, mem.top, mem.arm_bottom, mem.arm_top, mem.axes, mem.k0, mem.kh, mem.fh, mem.coupled)
    return Yielding(law, np.zeros((n_members, 4)), np.zeros(structure.mass.size + 3),
                    np.full((n_out if n_members else 0, n_members, 4), np.nan), np.zeros((n_members, 6)))  # fmt: skip


def gauge_state(gauges: ForceGauges | None, structure: Structure, yielding: Yielding) -> Gauges:
    """The force gauges' record (records.Gauges) on the structure's and the yielding members'
    own arrays, their peaks at zero; none where gauges is None."""
    n_storeys = structure.storey_top.size
    if gauges is None:
        ints = np.zeros(0, dtype=np.int64)
        return Gauges(ints, np.zeros((0, 3)), np.zeros(n_storeys + 1, dtype=np.int64), ints, ints, np.zeros((0, 3)),
                      np.full(n_storeys, -1, dtype=np.int64), structure.storey_top, structure.centre,
                      yielding.law.kh, yielding.plastic, yielding.g, yielding.peak, np.zeros((n_storeys, 3)),
                      np.zeros(0), np.zeros(0))  # fmt: skip
    return Gauges(gauges.storey, gauges.weight, gauges.first, gauges.member, gauges.member_axis, gauges.plastic_weight,
                  gauges.storey_above, structure.storey_top, structure.centre, yielding.law.kh, yielding.plastic,
                  yielding.g, yielding.peak, np.zeros((n_storeys, 3)), np.zeros(gauges.storey.size),
                  np.zeros(gauges.storey.size))  # fmt: skip


def exact_branch(
    structure: StructureArrays, structure_rec: Structure, v0: np.ndarray, h: float, substep: int, stride: int,
    ground_dt: float, has_pairs: bool, has_members: bool, n_gauges: int = 0,
) -> tuple[Propagators, Exact]:
    """The hybrid's exact branch (records.Propagators, records.Exact) for substeps of h s (substep CDM steps each,
    output every `stride` steps, record samples every ground_dt s) from the velocity v0: the
    propagators of the approach levels (where contact is possible) and of a double substep
    (where its span allows it and two fit between record and output samples: ω_max·2h ≤
    CREST_SPAN), K⁻¹ (with yielding members), and the peaks' work."""
    starts, counts = structure_rec.dof_start, structure_rec.dof_count
    n_dof = structure.mass.size
    n_storeys = structure.storey_k.shape[0]
    blocks = stiffness_blocks(structure)
    levels = approach_levels(substep, int(counts.max()), starts.size) if has_pairs else 0
    damping_dense = damping_blocks(structure)
    # steps of h/2^L, … h/2, h, 2h, from one set of matrix exponentials (the finest)
    steps = building_propagators(blocks, damping_dense, structure.mass, starts, counts, h / 2**levels, levels + 1,
                                 influence_of(structure))  # fmt: skip
    by_level = Propagator(*(np.ascontiguousarray(m[levels::-1]) for m in steps))  # level j: h/2^j
    kinv = inverse_blocks(blocks, counts) if has_members else np.zeros((1, 1, 1))
    rho = fastest_rate(blocks, damping_dense, structure.mass, starts, counts)
    if getattr(structure, "local_modes", ()):  # the buildings' own: the crests' series need not follow local modes
        rho = structure.fastest_rate()[0]
    doubles = rho * 2 * h <= CREST_SPAN and round(ground_dt / h) > 1 and stride // substep > 1
    double = Propagator(*(m[levels + 1] if doubles else m[levels + 1, :0] for m in steps))
    span = rho * (2 * h if doubles else h)
    series = np.zeros((crest_series_order(span), n_dof + 3))
    crest = Crests(1.0 - min(0.5, CREST_MARGIN * span**6 / 46080),
                   crest_arrays(structure_rec.column_arm.shape[0], n_storeys, n_dof, n_gauges), series,
                   np.zeros((2, n_dof + 3)),
                   np.zeros(series.shape[0]))  # fmt: skip
    n2 = by_level.phi.shape[2]
    between, first = between_arrays(structure.column_storey, structure_rec.column_arm, n_storeys)
    return Propagators(by_level, double, kinv), Exact(
        np.zeros(n_dof + 3), v0.copy(), np.zeros(n_dof + 3), np.zeros(n_dof + 3), np.full(1, h), np.zeros(n2 + 4),
        np.zeros(n2), np.zeros((KEPT_ROWS, n_dof + 3)), between, first, ground_rate_response(structure), crest)


def inverse_blocks(blocks: list[np.ndarray], counts: np.ndarray) -> np.ndarray:
    """K⁻¹ of every building, padded to (n_b, n_max, n_max)."""
    n_max = int(counts.max())
    out = np.zeros((len(blocks), n_max, n_max))
    for b, k in enumerate(blocks):
        out[b, : k.shape[0], : k.shape[0]] = np.linalg.inv(k)
    return out


def residual_deflections(structure: StructureArrays, plastic: np.ndarray, members: tuple) -> np.ndarray:
    """(n_members, 2) local deflections of the members once the motion has died away
    elastically from the final state: at u = K⁻¹·g, where the springs balance the plastic
    deflections (the residual deflection of a yielded structure), m."""
    from .hysteresis import member_deflection, plastic_correction

    n_dof = structure.mass.size
    g = np.zeros(n_dof + 3)
    plastic_correction(members, plastic, g)
    u = np.zeros(n_dof + 3)
    starts, counts = building_dofs(structure)
    for (d0, n), k in zip(zip(starts, counts), stiffness_blocks(structure)):
        u[d0 : d0 + n] = np.linalg.solve(k, g[d0 : d0 + n])
    bottom, top, arm_b, arm_t, axes = members[:5]
    return np.array([member_deflection(m, u, bottom, top, arm_b, arm_t, axes) for m in range(top.size)]).reshape(-1, 2)


def _failure_dof(u: np.ndarray, v: np.ndarray) -> int:
    """The first DOF whose displacement is not finite or past the limit, else the fastest."""
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(~np.isfinite(u) | (np.abs(u) > DIVERGENCE_LIMIT))
    if bad.size:
        return int(bad[0])
    speed = np.where(np.isfinite(v), np.abs(v), np.inf)
    return int(np.argmax(speed))
