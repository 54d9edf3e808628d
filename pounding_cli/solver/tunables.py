"""Every tuned constant of the integrator, in one place.

Each entry says what it means, its unit, where its value comes from (the measurement or the
test that set it, or that it was chosen by hand and not yet measured), and what moves if it
changes. Where a value was measured, the figures are in docs/bench.md (`pound bench`) or in
the test named. The compiled kernels read these as compile-time constants: changing one
recompiles them (solver/kernel_cache.py), and changes the results.

Three groups: the time grid (how long steps are), the hybrid's switches (when it leaves and
re-enters exact propagation), and the contact, yielding and peak details inside a step.
"""

from __future__ import annotations

# --- The time grid (assembly/timestep.py, assembly/contact.py, api.py) -------------------

AUTO_DT_FRACTION = 0.05
"""Δt_auto = AUTO_DT_FRACTION · 2/ω_max for linear buildings without contact (the plain CDM's
step; 1). Measured: the CDM's error is second order, 1e-4 on the peaks at this fraction
(docs/validation.md). Larger: the CDM's runs of linear scenes faster and less accurate
(quadratically); the hybrid's exact steps are unaffected."""

CONTACT_DT_FRACTION = 0.00625
"""Δt_auto ≤ CONTACT_DT_FRACTION · 2/ω_contact where contact is possible (1). Measured on the
paper's Kobe example against a converged run: 0.39 % off at 0.0125, 0.081 % at 0.00625,
0.022 % at 0.003125 (docs/bench.md, "The Kobe example"); this keeps a margin of 6 under the
0.5 % of issue 5. It sets the CDM's step around every impact: halving it doubles the CDM
steps of every contact scene (docs/bench/bench.md, rows "Δt / 2") and cuts their error by
about 4."""

YIELD_DT_FRACTION = 0.0125
"""The hybrid's CDM step while only yielding members need it: YIELD_DT_FRACTION · 2/ω_max of
the structure (1). Measured in the inelastic bench scene: peaks within 3.6e-5 of a converged
CDM at 0.0125, 2.0e-4 at 0.025, 5.8e-4 at 0.05 (docs/bench.md, "This release"; the members'
law is second order along each step's chord). Larger: fewer CDM steps in yielding stretches,
error growing as its square."""

HYBRID_SAMPLING = 4.0
"""The exact substep satisfies ω_max·h ≤ HYBRID_SAMPLING where no member yields (rad): in
most scenes a whole record interval (h must divide it). Set by the peaks' search, the only
thing an exact step's length can spoil: the quintic locates every crest within Newton's
reach of the exact one up to ω·H = 5 in random mode sums (3,000 cases each; wrong basins at
6), and tests/test_peaks.py holds crests exact to 1e-12 at 3.9 (docs/theory.md §6). Measured
against 0.4: every scene without yielding members the same or fewer seconds at the same or
smaller errors (docs/bench.md, "Is the default on the front?"). It equals CREST_SPAN, the
crests' own limit: raising it past that loses crests."""

YIELD_SAMPLING = 0.2
"""ω_max·h with yielding members (rad): their yield check looks h ahead, and a member that
may yield within it sends the whole substep to the CDM at the yielding step, so longer
substeps cost more CDM steps than they save. Measured: the inelastic and isolated bench
scenes are slower and less accurate at 0.4 (docs/bench.md)."""

APPROACH_MIN_STEPS = 8
"""The hybrid's finest exact step toward a contact spans at least this many CDM steps (the
approach levels, step_plan.approach_levels). Chosen by hand with the approach levels
(028e389), not swept: a shorter finest step brings the hand-over closer to the impact (fewer
CDM steps before it) at the cost of more levels of propagators; `dt = "auto"` rounds the CDM
steps per substep up to a multiple of 2^L for it (at most 1/8 finer)."""

APPROACH_MEMORY = 64 * 2**20
"""The propagators of all approach levels together take at most this many bytes (a
resource bound, not an accuracy one): scenes with large buildings get fewer levels, and so
hand over to the CDM earlier before an impact."""

LIKELY_DEPTH = 1e-3
"""The overlap depth (m) at which the likely contacts' line is measured (assembly/contact.py,
likely_contact_line), which sets their stiffness k_N·length and so the automatic contact
step: pounding with k_N of concrete (10⁹–10¹¹ N/m²) overlaps by micrometres to a few
millimetres. The run checks the contacts it met against it (RERUN_MARGIN)."""

STEP_BOUND = 0.0125
"""omega_step ≥ STEP_BOUND·omega_max (1): however soft the likely contacts, the automatic
contact step (CONTACT_DT_FRACTION of 2/omega_step) stays below half the CDM's stability
limit 2/omega_max of the stiffest contact the outlines allow. Derived from the two fractions,
not measured."""

RERUN_MARGIN = 1.25
"""A run that met a contact stiffer than the likely contacts' ω by more than this factor is
repeated at the step that contact needs (api.execute; 1). Chosen with the automatic contact
step (9e83489): at 1.25 the step was at most 25 % too long, within the bench's error budget
(CONTACT_DT_FRACTION's margin of 6). Smaller: more reruns; larger: longer steps kept."""

MAX_RERUNS = 2
"""How many times a run is repeated at a stiffer contact's step before it takes the
outlines' upper bound (a bound on the work, chosen by hand)."""

# --- The hybrid's switches (solver/hybrid.py) ---------------------------------------------

ENTER_HORIZON = 2.0
"""Substeps ahead a contact (or a member's yield) must be ruled out for the hybrid to stay
exact (1). Chosen by hand when the hybrid was written (44a1d30), not swept; with the
approach levels it only decides when the finer exact steps begin. Smaller: risks a contact
beginning inside an exact step, whose bounds (velocity and acceleration of the instant) are
then stretched further; larger: more approach steps."""

LEAVE_HORIZON = 4.0
"""Substeps (or finest exact steps) ahead every contact must be ruled out for the CDM to hand
back to exact propagation (1). Twice ENTER_HORIZON, so that the switch does not chatter
(docs/theory.md §6, "Back from the CDM"); chosen by hand, not swept."""

CLOSING_SAFETY = 2.0
"""contact.contact_ruled_out_within doubles what two outlines can close within the horizon
(1): it takes the accelerations of the instant as bounds, and they change within the horizon.
Guarded by tests/test_approach.py (the check is sound: no run with the levels met a contact
it had ruled out, and runs with and without the levels agree to 1e-6 of each peak). Smaller:
the approach hands over later; too small and a contact begins inside an exact step."""

DIVERGENCE_LIMIT = 100.0
"""A relative displacement beyond this many metres means the run has diverged (m): it stops
with exit 1 at the step that made it. Far beyond any storey drift a building survives; a
bound against blow-up, not an accuracy setting."""

ENERGY_LIMIT = 0.05
"""A run whose energy balance error passes this fraction of the energy in play has gone
unstable (1): it stops with cdm.STATUS_ENERGY. So does a run whose contacts have given out
more energy than they took, by more than this fraction of the input (passive contacts store
what they take while compressed and lose the rest to friction and dashpots: their account
never falls below zero in a healthy run; an impact integrated with too long a step creates
energy). A healthy run stays below 1e-4 (`pound bench --stability`, docs/bench/stability.md:
every completed case within 7e-8 but the CDM step sweep, 2.2e-3 at 0.9 × its limit)."""

ENERGY_FLOOR_SPEED = 0.01
"""Energies below those of the structure's floors moving at this speed (m/s) are too small
to judge the balance by (ENERGY_LIMIT): at rest and in the first steps of a record the
balance error's relative size means nothing. Chosen by hand."""

# --- Inside a step: broad phase, contact, yielding, peaks -------------------------------

SWEEP_PAIRS_PER_MEMBER = 1.5
"""Sweep and prune replaces the all-pairs loop when the candidate pairs number at least this
many times the group members (1; broad_phase.py). Measured: testing a pair costs about 8 ns,
sweeping a member about 12 ns, plus a fixed cost per step; the two break even near 1.4 pairs
per member for the contact step and 1.7 for the hybrid's horizon check (docs/bench/
crossover.md, `python -m pounding_cli.bench.crossover`). Results are the same bit for bit
either way; only the cost moves."""

SHALLOW_MARGIN = 1.25
"""contact_geometry.shallow_moments skips an overlap whose ends are deeper than this many
times the step's rate of closing (1): none of it touched within the last step or can part
within the next. The rate of the next step is a prediction; an overlap that parts after all
though deeper than this is counted nowhere, so the margin is above 1. Set with the point-
by-point kinks (e4ee121), not swept; what it guards is tested in tests/test_contact.py
(test_faces_turned_slightly_rebound_wherever_the_touch_falls)."""

NEAR_SLOPE = 0.1
"""An overlap edge counts as nearly shared with a line of the other polygon when both its
endpoints lie closer to the line than this fraction of its length (about 6°) and than the
overlap's mean thickness (contact_geometry._share; 1). It decides the contact line's
direction as faces meet nearly parallel; chosen by hand with the contact frame (2f91fdc); the
frame's continuity as the overlap changes shape is tested in tests/test_contact_geometry.py
(test_normal_is_continuous_while_the_overlap_changes_shape)."""

PLASTIC_SUBSTEP = 0.05
"""The elliptical flow with unequal axes is integrated by RK4 in pieces of at most this
normalised path length |r|·Δs times the axes' ratio max(a)/min(a), the flow's fastest rate
(1; hysteresis.return_map). Its error is fourth order in the pieces, far below the CDM's;
tests/test_hysteresis.py (test_path_return_follows_the_flow_rule) holds it within 1e-8 of
solve_ivp of the flow rule."""

CREST_SPAN = 4.0
"""The longest exact step the peaks allow, as ω_max·H (rad): the quintic locates every crest
within Newton's reach of the exact one (peaks.py; the figures under HYBRID_SAMPLING)."""

CREST_MARGIN = 4.0
"""A quintic crest is valued exactly where it comes within CREST_MARGIN·(ρ·H)⁶/46080 of its
running peak (relative; 1): four times the quintic's error bound, as a mode's share of a
quantity may exceed the quantity. Smaller: crests missed; larger: more Taylor series summed
(cost only)."""

SERIES_REMAINDER = 1e-16
"""The Taylor series of the exact motion over an exact step is summed until its remainder
(ρ·H)^R/R! falls below this share of the motion (1; peaks.crest_series_order): rounding."""

SERIES_MIN_ORDER = 8
"""…and to at least this many terms (1)."""

SERIES_MAX_ORDER = 512
"""…and to at most this many (1): a bound on the loop, never reached in a scene whose exact
steps keep ω_max·H ≤ CREST_SPAN (ρ·H = 4 needs 26 terms); an overdamped mode so fast that
ρ·H passes about 150 is refused (peaks.crest_series_order raises)."""

CREST_NEWTON_STEPS = 16
"""Newton's steps on a crest's Taylor series at most (peaks.settle_crests; 1): a bound on the
loop; from the quintic's crest they converge quadratically and stop at 1e-15·H."""
