"""The compiled time loop's arguments, grouped in a few named records.

Every kernel of the loop takes these records instead of loose arrays: the structure, the
ground motion, the CDM's step, the state it carries from step to step, the work buffers,
the peaks and outputs, the contact candidates and their state, the yielding members, and
for the hybrid integrator its exact propagators and the state of its exact branch. They are
named tuples, which numba compiles as plain structs: a field is read as `structure.mass`, and
the arrays inside are written in place. Scalars (a step, a count) are fields too; nothing
here is mutable but the arrays. Inside compiled code a record costs what its arrays would as
separate arguments; the phases that run every step or substep are inlined (no call at all).
A call from Python pays for checking every array's type: about 30 µs for the whole set
(20 µs as loose arrays), which is why integrate.simulate calls the loop in chunks that grow
while they are quick (integrate.CHUNK_SECONDS).

State vectors (u, v, forces) are n_dof + 3 long: 3 DOFs per floor (u_x, u_y in m, θ_z in
rad, at the floor's mass centre), and last an extra zero "floor", the ground, which is the
bottom floor of every ground storey (so no storey is a special case).

The records are built in integrate.py (simulate), from the arrays of
pounding_cli.assembly; the tests build small ones the same way.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Damping(NamedTuple):
    """C = a0·M + a1·K per DOF, plus 6×6 links between two floors (an isolated building's
    superstructure damping acting on its deformation, assembly/damping.py)."""

    a0: np.ndarray
    """(n_dof,) mass-proportional coefficient, 1/s"""
    a1: np.ndarray
    """(n_dof,) stiffness-proportional coefficient, s"""
    link: np.ndarray
    """(n_links, 6, 6) damping blocks on the DOFs of floors link_bottom and link_top, N·s/m"""
    link_bottom: np.ndarray
    """(n_links,) bottom floor of each link (the ground floor, n_floors, for the ground)"""
    link_top: np.ndarray
    """(n_links,) top floor of each link"""


class Structure(NamedTuple):
    """The buildings: mass, storey stiffness, damping, and where the columns stand."""

    mass: np.ndarray
    """(n_dof,) floor masses, kg (rotational inertia about the mass centre, kg·m², for θ)"""
    damping: Damping
    storey_k: np.ndarray
    """(n_storeys + n_links, 6, 6) storey stiffness on the DOFs of its bottom and top floors, N/m,
    N, N·m: storey s < n_floors is the one beneath floor s; the stiffness links after them
    (local modes' springs, assembly/local_modes.py) join any two floors of one building"""
    storey_bottom: np.ndarray
    """(n_storeys,) floor below each storey (n_floors, the ground, for a ground storey)"""
    storey_top: np.ndarray
    """(n_storeys,) floor above each storey"""
    dof_start: np.ndarray
    """(n_buildings,) first DOF of each building"""
    dof_count: np.ndarray
    """(n_buildings,) DOFs of each building (its blocks of M, K, C are dense; buildings are
    coupled only by contact)"""
    storey_axes: np.ndarray
    """(n_storeys, 2) cos φ, sin φ of the building axes, in which deflections are reported"""
    centre: np.ndarray
    """(n_floors + 1, 2) floor mass centres at rest, m, global; the ground's row is zero"""
    column_storey: np.ndarray
    """(n_columns,) storey of each column (columns are listed storey by storey)"""
    column_arm: np.ndarray
    """(n_columns, 2) ξ, η: the column's arm in building axes, m (peaks.update_peaks)"""
    buildings: np.ndarray
    """(n_buildings,) 0 … n_buildings − 1: every building, as a list of them (exact.propagate)"""
    influence: np.ndarray
    """(n_dof,) ground influence ι: how far a unit ground displacement along the DOF's axis moves
    it (1 on the floors' u_x, u_y, 0 on θ; Σw on a struck column's local mode, assembly/local_modes.py)"""
    ground_mass: np.ndarray
    """(n_dof,) M·ι, kg: the masses the ground drives (p = −M·ι·a_g)"""
    dof_real: np.ndarray
    """(n_buildings,) DOFs of each building's own floors (its local modes' pseudo-floors follow
    them up to dof_count; CdmStep.inverse holds the factored form there, cdm._solve_reduced)"""


class Ground(NamedTuple):
    """The ground acceleration, linear between samples and zero after the record."""

    acceleration: np.ndarray
    """(n, 2) along global X and Y, m/s²"""
    dt: float
    """sample interval, s"""


class CdmStep(NamedTuple):
    """One step size of the central difference method."""

    dt: float
    """the step, s"""
    inverse: np.ndarray
    """(n_buildings, n_max, n_max) B⁻¹ = (M/Δt + C/2)⁻¹ per building, padded (a building with
    local modes: its Schur complement's factors, integrate.step_matrices)"""
    per_output: int
    """steps per output sample"""
    per_substep: int
    """steps per exact substep of the hybrid integrator (1 for the plain CDM)"""


class Motion(NamedTuple):
    """The state the CDM carries from step to step (and across calls)."""

    u: np.ndarray
    """(n_dof + 3) u_n, relative to the ground, m and rad"""
    v_half: np.ndarray
    """(n_dof + 3) v_{n−½}, m/s and rad/s"""
    ku: np.ndarray
    """(n_dof + 3) K·u_n, N"""
    cv_half: np.ndarray
    """(n_dof + 3) C·v_{n−½}, N"""
    energy: np.ndarray
    """(cdm.N_ACC,) energy accumulators (cdm.ACC_*), J and W"""


class Work(NamedTuple):
    """Scratch vectors of a step ((n_dof + 3) each but storey_work)."""

    r: np.ndarray
    """the residual p − K·u − C·v + F_contact + g, N"""
    dv: np.ndarray
    """Δv_n = B⁻¹·r, m/s"""
    v: np.ndarray
    """v_n, the central-difference velocity, m/s"""
    a_abs: np.ndarray
    """absolute acceleration at t_n, m/s²"""
    z: np.ndarray
    """K·v_{n+½}, N/s"""
    cv_next: np.ndarray
    """C·v_{n+½} (or C·v at an exact state), N"""
    storey_work: np.ndarray
    """(n_storeys, 3) storey deflections (Ã_x, Ã_y, Δθ) at the state just peaked, m, rad"""


class Gauges(NamedTuple):
    """Storey shears and column forces as linear gauges of the storey deflections, less their
    members' plastic part (force_peaks.py; assembly/force_gauges.py builds them), listed storey
    by storey, and their running peaks."""

    storey: np.ndarray
    """(n_g,) the storey of each gauge"""
    weight: np.ndarray
    """(n_g, 3) on the storey deflection (Ã_x, Ã_y, Δθ), N/m, N/m, N/rad (N·m/m, N·m/rad)"""
    first: np.ndarray
    """(n_storeys + 1,) each storey's first gauge"""
    member: np.ndarray
    """(n_g,) a column gauge's yielding member (rows of plastic and kh), −1: none"""
    member_axis: np.ndarray
    """(n_g,) the member's local axis whose k_h·p is subtracted"""
    plastic_weight: np.ndarray
    """(n_g, 3) a storey gauge's weights on its storey's plastic resultant, subtracted (1, or m)"""
    storey_above: np.ndarray
    """(n_storeys,) the storey on top of each in its building, −1 for the top one"""
    top: np.ndarray
    """(n_storeys,) the floor above each storey (Structure.storey_top)"""
    centre: np.ndarray
    """(n_floors + 1, 2) the floors' mass centres, m (Structure.centre)"""
    kh: np.ndarray
    """(n_members, 2) the members' hysteretic stiffness, N/m (Yielding.law.kh)"""
    plastic: np.ndarray
    """(n_members, 4) the members' plastic deflections, m (Yielding.plastic: the same array)"""
    g: np.ndarray
    """(n_dof + 3) the members' plastic correction on the floors, N, N·m (Yielding.g: the same array)"""
    member_peak: np.ndarray
    """(n_members, 6) the members' running peaks (Yielding.peak: the same array; |f_x|, |f_y| in 3, 4)"""
    resultant: np.ndarray
    """(n_storeys, 3) work: each storey's plastic resultant P_s at the state peaked, N, N, N·m"""
    offset: np.ndarray
    """(n_g,) each gauge's plastic part at the last exact state (constant over the exact step
    from it, whatever a member's overshoot changes at its end), N (N·m)"""
    peak: np.ndarray
    """(n_g,) running max |q|, N (N·m)"""


class Peaks(NamedTuple):
    """Running maxima over every step (and between exact states)."""

    column: np.ndarray
    """(n_columns, 2) |Δu| along building x, y, m"""
    storey_rotation: np.ndarray
    """(n_storeys,) |Δθ|, rad"""
    displacement: np.ndarray
    """(n_dof,) |u|, m and rad"""
    acceleration: np.ndarray
    """(n_dof,) absolute |a|, m/s² and rad/s²"""
    gauges: Gauges
    """storey shears and column forces (force_peaks.py)"""


class Output(NamedTuple):
    """Histories at the output interval (row k: t = k × the interval)."""

    displacement: np.ndarray
    """(n_out, n_dof) relative, m and rad"""
    velocity: np.ndarray
    """(n_out, n_dof) relative, m/s and rad/s"""
    acceleration: np.ndarray
    """(n_out, n_dof) absolute, m/s² and rad/s²"""
    ground: np.ndarray
    """(n_out, 2) ground acceleration X, Y, m/s²"""
    energy: np.ndarray
    """(n_out, 7) J, columns cdm.ENERGY_NAMES"""
    contact: np.ndarray
    """(n_out, n_pairs, 6) per pair, columns layout.NOW_COLUMNS"""
    floor_contact: np.ndarray
    """(n_out, n_dof) the contact forces on the floors, N and N·m (Contact.force)"""


class Bodies(NamedTuple):
    """The outlines that may touch: floor slabs and fixed obstacles, as convex polygons."""

    poly: np.ndarray
    """(n_bodies, n_vertices, 2) outline at rest, counter-clockwise, m, global"""
    nv: np.ndarray
    """(n_bodies,) vertices of each outline"""
    floor: np.ndarray
    """(n_bodies,) the floor the body moves with; −1 for an obstacle (moves with the ground)"""
    centre: np.ndarray
    """(n_bodies, 2) the floor's mass centre at rest (an obstacle's reference point), m"""
    radius: np.ndarray
    """(n_bodies,) largest distance from centre to a vertex, m"""
    box: np.ndarray
    """(n_bodies, 4) x_min, y_min, x_max, y_max of the outline at rest, m"""


class PairLaw(NamedTuple):
    """The candidate pairs and their impact law (contact.py, paper eqs. 3–5)."""

    a: np.ndarray
    """(n_pairs,) body A of each pair (the normal points from A into B)"""
    b: np.ndarray
    """(n_pairs,) body B"""
    k_n: np.ndarray
    """(n_pairs,) normal stiffness per unit overlap area, N/m²"""
    k_t: np.ndarray
    """(n_pairs,) tangential stiffness, N/m"""
    mu_s: np.ndarray
    """(n_pairs,) static friction coefficient"""
    mu_k: np.ndarray
    """(n_pairs,) kinetic friction coefficient"""
    c_n: np.ndarray
    """(n_pairs,) normal dashpot, N·s/m"""
    zeta: np.ndarray
    """(n_pairs,) normal dashpot as a damping ratio of the contact (instead of c_n)"""
    c_t: np.ndarray
    """(n_pairs,) tangential dashpot, N·s/m"""
    m_eff: np.ndarray
    """(n_pairs,) effective mass of the pair, kg (for zeta)"""


class BroadPhase(NamedTuple):
    """Sweep and prune by level (broad_phase.py); without groups every pair is tested."""

    group_start: np.ndarray
    """(n_groups + 1,) first member of each group"""
    group_body: np.ndarray
    """(n_members,) body of each member"""
    group_axis: np.ndarray
    """(n_groups,) sweep axis of each group (0: x, 1: y); empty: test every pair"""
    index_start: np.ndarray
    """(n_groups,) where each group's local pair index starts in `index`"""
    index: np.ndarray
    """dense local pair index of each group (−1: not a candidate)"""
    order: np.ndarray
    """(n_members,) members by lower bound, carried from step to step"""
    bounds: np.ndarray
    """(n_members, 4) the members' bounds (broad_phase.LO_SWEEP …), m"""
    hits: np.ndarray
    """(n_pairs,) the pairs a sweep found"""
    live: np.ndarray
    """(n_pairs,) the pairs in contact at the last step"""
    n_live: np.ndarray
    """(1,) how many of `live` are set"""
    phase: np.ndarray
    """(n_pairs,) while buildings sleep (sleep.py): the pairs that may touch before the next
    substep boundary, ascending; the contact step visits these (and `live`) alone"""
    n_phase: np.ndarray
    """(1,) how many of `phase` are set; −1: no such list, the broad phase decides"""


class ClipWork(NamedTuple):
    """Work buffers of the narrow phase (contact.buffers)."""

    poly_a: np.ndarray
    poly_b: np.ndarray
    clip: np.ndarray
    clip_label: np.ndarray
    tmp: np.ndarray
    tmp_label: np.ndarray
    frame: np.ndarray
    """the contact frame of the last overlap (contact_geometry.RESULT_NAMES)"""


class StoreyBodies(NamedTuple):
    """The storeys that slabs strike between two floors, each moving as a virtual floor
    (storey_bodies.py): k is floor n_floors + 1 + k of the extended state vectors, read as
    (1 − s)·T·q_below + s·q_above."""

    below: np.ndarray
    """(n_s,) the floor below (an index of the state vectors: n_floors, the ground, for the first storey)"""
    above: np.ndarray
    """(n_s,) the floor above, whose slab is the outline"""
    shape: np.ndarray
    """(n_s,) s(ξ) = 3ξ² − 2ξ³"""
    arm: np.ndarray
    """(n_s, 2) G_above − G_below at rest, m"""
    u: np.ndarray
    """(n_dof + 3 + 3·n_s) work: a displacement vector extended by the virtual floors"""
    v: np.ndarray
    """(n_dof + 3 + 3·n_s) work: a velocity vector, extended"""
    w: np.ndarray
    """(n_dof + 3 + 3·n_s) work: a second velocity (or an acceleration) vector, extended"""
    mode_first: np.ndarray
    """(n_s + 1,) body k's outline is moved by the local modes mode_first[k] … mode_first[k + 1] − 1"""
    mode_floor: np.ndarray
    """(n_m,) each local mode's pseudo-floor (assembly/local_modes.py)"""
    mode_phi: np.ndarray
    """(n_m,) φ_k(ξ): the outline's displacement per unit of the mode's coordinate"""
    mode_weight: np.ndarray
    """(n_m, 2) w_k: the mode's coupling to the floors below and above"""
    mode_arm: np.ndarray
    """(n_m, 4) the struck columns' point from the mass centre below (x, y) and above (x, y), m"""
    mode_k: np.ndarray
    """(n_m, 2, 2) the mode's plan stiffness K_m, N/m"""
    mode_theta: np.ndarray
    """(n_m, 2) the mode's couplings to the end rotations, (∫ξ(1 − ξ)²φ dξ, ∫ξ²(ξ − 1)φ dξ)"""
    pair: np.ndarray
    """(n_s,) the contact pair of each body"""
    rotation_shape: np.ndarray
    """(n_s, 2) h·(ξ(1 − ξ)², ξ²(ξ − 1)): the end moments per unit of a point load at ξ on a column
    clamped at both ends, m"""
    height: np.ndarray
    """(n_s,) the struck storey's height, m"""
    bundle_k: np.ndarray
    """(n_s, 2, 2) the struck columns' summed plan stiffness ΣK_i, N/m (zero without local modes)"""
    residual_mass: np.ndarray
    """(n_s, 2, 2) the struck bundle's mass that moves with the floors, M_bb − Σ_m m·w_m·w_mᵀ, kg
    (assembly/local_modes.py; zero without local modes)"""
    load: np.ndarray
    """(n_s, 2) work: the force on each outline at the last contact evaluation (x, y), N"""
    last_event: np.ndarray
    """(n_s,) int64 work: the row of each body's latest impact in the log (−1: none yet)"""
    shear_peak: np.ndarray
    """(n_rows, 14) per impact (row of the log): |R|, t, the bundle's end shears at the foot (x, y)
    and top (x, y), N, global, its end moments' magnitudes (foot, top), N·m, and the floors'
    (u_x, u_y, θ) below and above, at the step where the larger end shear peaked (storey_bodies.track_column_shears; rows of scenes without local
    modes: none)"""


class Contact(NamedTuple):
    """The contact candidates, their state from step to step, and the impact log."""

    bodies: Bodies
    law: PairLaw
    broad: BroadPhase
    state: np.ndarray
    """(n_pairs, contact.N_STATE) each pair's episode so far (contact.ST_*)"""
    now: np.ndarray
    """(n_pairs, 6) each pair's force, area, action point and depth now (layout.NOW_COLUMNS)"""
    events: np.ndarray
    """(max_events, layout.EV_COLUMNS) the impact log, one row per episode"""
    n_events: np.ndarray
    """(1,) episodes so far (beyond max_events: counted, not logged)"""
    force: np.ndarray
    """(n_dof + 3 + 3·n_s) the contact forces of the step on the floors, N, N·m (on the virtual
    floors of storeys.u while the kernel runs; handed to the floors after)"""
    v_est: np.ndarray
    """(n_dof + 3) v_n ≈ v_{n−½} + Δv_{n−1}/2 for the dashpots, m/s"""
    clip: ClipWork
    storeys: StoreyBodies


class MemberLaw(NamedTuple):
    """Yielding members (inelastic columns, isolators): where they stand and their bilinear law
    along their local axes (hysteresis.py)."""

    bottom: np.ndarray
    """(n_members,) floor below (the ground floor, n_floors, for the ground)"""
    top: np.ndarray
    """(n_members,) floor above"""
    arm_bottom: np.ndarray
    """(n_members, 2) plan position relative to the bottom floor's mass centre, m"""
    arm_top: np.ndarray
    """(n_members, 2) the same for the top floor, m"""
    axes: np.ndarray
    """(n_members, 2) cos, sin of the local x axis"""
    k0: np.ndarray
    """(n_members, 2) initial stiffness along local x, y, N/m"""
    kh: np.ndarray
    """(n_members, 2) the hysteretic spring's stiffness, N/m"""
    fh: np.ndarray
    """(n_members, 2) the hysteretic spring's yield force, N"""
    coupled: np.ndarray
    """(n_members,) 1: the elliptical (biaxially coupled) yield surface"""


class Yielding(NamedTuple):
    """Yielding members and their state."""

    law: MemberLaw
    plastic: np.ndarray
    """(n_members, 4) plastic deflections p_x, p_y, and δ_x, δ_y at the last return map, m"""
    g: np.ndarray
    """(n_dof + 3) the plastic correction Σ Bᵀ·Q·(k_h ⊙ p), N"""
    history: np.ndarray
    """(n_out, n_members, 4) local δ_x, δ_y (m), f_x, f_y (N) at the output interval"""
    peak: np.ndarray
    """(n_members, 6) |δ_x|, |δ_y|, |δ| m, |f_x|, |f_y|, |f| N"""


class Propagator(NamedTuple):
    """Exact steps of one length per building (propagator.py), or of several lengths with a
    leading level axis (level j: h/2^j)."""

    phi: np.ndarray
    """(…, n_b, 2·n_max, 2·n_max) state transition e^{A·h} on (u, v)"""
    g0: np.ndarray
    """(…, n_b, 2·n_max, 2) response to the ground acceleration at the step's start"""
    g1: np.ndarray
    """(…, n_b, 2·n_max, 2) response to its change over the step"""
    mean_rows: np.ndarray
    """(…, n_b, 2, 2·n_max + 4) the mean of the mass-weighted translations over the step"""
    damping_form: np.ndarray
    """(…, n_b, 2·n_max + 4, 2·n_max + 4) the damping's work over the step, z₀ᵀ·G·z₀"""


class Crests(NamedTuple):
    """Work of the exact peaks between exact states (peaks.py)."""

    floor_ratio: float
    """the share of a running peak a quintic crest must pass to be valued exactly"""
    crests: np.ndarray
    """(n, 3) the crests listed (peaks.crest_arrays)"""
    series: np.ndarray
    """(R, n_dof + 3) the exact motion's derivatives at a state (exact.state_series)"""
    series_k: np.ndarray
    """(2, n_dof + 3) K times two of them"""
    coef: np.ndarray
    """(R,) one quantity's Taylor coefficients"""


class Propagators(NamedTuple):
    """The hybrid integrator's exact steps (propagator.py)."""

    levels: Propagator
    """steps of h/2^j for j = 0 … L (the approach levels)"""
    double: Propagator
    """steps of 2h (empty arrays where two substeps are never taken at once)"""
    k_inverse: np.ndarray
    """(n_b, n_max, n_max) K⁻¹ per building (yielding members' static offset)"""


class Exact(NamedTuple):
    """The state of the hybrid integrator's exact branch between calls, and its work."""

    u_static: np.ndarray
    """(n_dof + 3) K⁻¹·g, the static offset of the members' plastic deflections, m"""
    v: np.ndarray
    """(n_dof + 3) the exact state's velocity, m/s"""
    kv: np.ndarray
    """(n_dof + 3) K·v, N/s"""
    a_rel: np.ndarray
    """(n_dof + 3) acceleration relative to the ground, m/s²"""
    gap: np.ndarray
    """(1,) the last exact step, s"""
    x: np.ndarray
    """(2·n_max + 4) scratch of propagate"""
    y: np.ndarray
    """(2·n_max) scratch of propagate"""
    kept: np.ndarray
    """(peaks.KEPT_ROWS, n_dof + 3) what peaks_between keeps of the last exact state"""
    between: np.ndarray
    """(n_storeys, peaks.BT_COLUMNS) the same per storey"""
    first: np.ndarray
    """(n_storeys + 1,) each storey's first column"""
    rates: np.ndarray
    """(hybrid.N_RATES, n_dof + 3) exact_point's rates of the accelerations"""
    crest: Crests


class Substeps(NamedTuple):
    """The hybrid integrator's grid: exact substeps of h, each `per_substep` CDM steps."""

    h: float
    """the substep, s"""
    end: int
    """the substep at the end of the analysis (only the state there is taken)"""
    per_output: int
    """substeps per output sample"""
    per_record: int
    """substeps per record interval"""


class ContactLevels(NamedTuple):
    """The contact steps of the hybrid's CDM phases, finest first (step_levels.py): level ℓ
    takes per_substep[ℓ] steps of dt[ℓ] a substep, a whole number of them in each finest exact
    step; level 0 is the contact step."""

    dt: np.ndarray
    """(n_levels,) the step, s"""
    inverse: np.ndarray
    """(n_levels, n_buildings, n_max, n_max) B⁻¹ = (M/Δt + C/2)⁻¹ per building at each step"""
    per_output: np.ndarray
    """(n_levels,) int64 steps per output sample"""
    per_substep: np.ndarray
    """(n_levels,) int64 steps per exact substep"""
    pair_level: np.ndarray
    """(n_pairs,) int64 the coarsest level whose step each pair's contact allows"""
    current: np.ndarray
    """(1,) int64 the level of the CDM phase under way"""
    saved: np.ndarray
    """(n_dof + 3,) work: u_n while the step changes (step_levels.change_step)"""


class Progress(NamedTuple):
    """The hybrid's mode and counters (hybrid.MODE_*, hybrid.CNT_*)."""

    mode: np.ndarray
    """(1,) what the next substep does"""
    counters: np.ndarray
    """(hybrid.N_COUNTERS,) steps, hand-overs, the failed step"""


class Awake(NamedTuple):
    """Which buildings the CDM carries while it integrates contacts, and which sleep: propagated
    exactly, finest step by finest step (sleep.py). Floors, columns and force gauges are
    numbered building by building, so a run of consecutive buildings is one range of each."""

    enabled: int
    """1 where buildings may sleep (sleep.may_sleep), else 0: all stay awake"""
    floor_start: np.ndarray
    """(n_buildings + 1,) first floor of each building (storeys alike)"""
    column_start: np.ndarray
    """(n_buildings + 1,) first column of each building"""
    gauge_start: np.ndarray
    """(n_buildings + 1,) first force gauge of each building"""
    body_building: np.ndarray
    """(n_bodies,) the building each contact body moves with (a struck storey's: the struck one;
    −1: an obstacle, which never sleeps)"""
    flag: np.ndarray
    """(n_buildings,) 1: carried by the CDM; 0: asleep"""
    everyone: np.ndarray
    """(n_buildings,) ones: a flag under which every pair counts"""
    time: np.ndarray
    """(1,) the instant the sleeping buildings' state is at, s"""
    need: np.ndarray
    """(n_buildings,) work: 1 where a pair of the building may touch within the horizon"""
    runs: np.ndarray
    """(n_buildings, 8) the awake runs of consecutive buildings: floors f0, f1, columns c0, c1,
    gauges g0, g1, buildings b0, b1 (half-open ranges)"""
    n_runs: np.ndarray
    """(1,) how many runs"""
    sleepers: np.ndarray
    """(n_buildings,) the sleeping buildings"""
    n_sleepers: np.ndarray
    """(1,) how many"""
