"""A contact step per CDM phase: the pairs that may touch in it set it.

The automatic contact step Δt follows the stiffest contact the scene is likely to make
(assembly/contact.py: omega_step). A pair whose own contact is softer (ω_p < ω_step: a slab
meeting the mid-height of a flexible storey, a light slab against a heavy one) needs a step
ω_step/ω_p times longer for the same accuracy, CONTACT_DT_FRACTION of its own 2/ω_p. So the
hybrid's CDM phases take one of a few steps, the levels: level ℓ takes q_ℓ = ⌈q₀/2^ℓ⌉ steps in
each finest exact step (q₀ those of the contact step), no fewer than the yielding step's
(the structure's own fraction of its stability limit, timestep.py), and pair p belongs to the
coarsest level with q₀/q_ℓ ≤ ω_step/ω_p. A phase runs at the finest level of the pairs that
cannot be ruled out within the entry horizon (contact.contact_finest_level_within), so a
stiff pair that never comes near costs nothing, and it switches between levels at finest
exact steps' boundaries: finer as soon as a finer pair can no longer be ruled out within
ENTER_HORIZON finest steps (before it can touch, as the approach toward a contact needs),
coarser once those pairs are ruled out within LEAVE_HORIZON of them (so the step does not
chatter).

Changing the step from Δt_a to Δt_b at t_n, in contact or not (change_step): the step at t_n
is taken at Δt_a (contact forces, the state at t_n, Δv_n = B_a⁻¹·r_n, the output and
energy of t_n), so that v_n = v_{n−½} + Δv_n/2 and a_n = Δv_n/Δt_a satisfy
M·a_n + C·v_n + K·u_n = p_n + F_n exactly; then it continues as the CDM at Δt_b would from
that state, v_{n+½} = v_n + (Δt_b/2)·a_n, u_{n+1} = u_n + Δt_b·v_{n+½}, with the last Δv
that the dashpots' velocity estimate reads rescaled to Δt_b·a_n. Nothing is lost but the
one-sided estimate of that step's crest (contact.crest assumes equal steps).
"""

from __future__ import annotations

import numpy as np

from .cdm import STATUS_OK, advance, damping_force_range, storey_matvec_range
from .jit import INTERNAL, kernel, phase
from .records import CdmStep, ContactLevels
from .step_plan import phase_plan


def contact_levels(contact_step: CdmStep, fine: int, yield_per_substep: int, inverse_of, pair_step_ratio,
                   n_pairs: int, n_dof: int) -> ContactLevels:  # fmt: skip
    """The levels (step_plan.phase_plan) of a hybrid run whose contact step is `contact_step`
    (level 0), with `fine` finest exact steps a substep and the yielding step's
    `yield_per_substep` steps a substep, as the time loop's record; inverse_of(dt) gives the
    B⁻¹ blocks of a step; pair_step_ratio (n_pairs,) how many times longer than the contact
    step each pair's own contact allows the step to be (≥ 1; None: one level)."""
    counts, level = phase_plan(contact_step.per_substep, yield_per_substep, fine, pair_step_ratio, n_pairs)
    q0 = counts[0]
    per_output = contact_step.per_output // contact_step.per_substep
    dts = [contact_step.dt * q0 / q for q in counts]
    inverse = np.stack([contact_step.inverse] + [inverse_of(dt) for dt in dts[1:]])
    return ContactLevels(np.array(dts), inverse, np.array([per_output * q * fine for q in counts], dtype=np.int64),
                         np.array([q * fine for q in counts], dtype=np.int64), level, np.zeros(1, dtype=np.int64),
                         np.zeros(n_dof + 3))  # fmt: skip


@kernel(inline="always")
def level_step(levels, level):
    """The CdmStep of a level (a view of its B⁻¹ blocks: nothing is copied)."""
    return CdmStep(levels.dt[level], levels.inverse[level], levels.per_output[level], levels.per_substep[level])


@phase
def finest_step_changing(n_old, old, new, n_new, q_new, structure, ground, motion, work, peaks, out, contact, yielding,
                         awake, saved):  # fmt: skip
    """One finest exact step of the CDM from t_n = n_old·Δt_a = n_new·Δt_b, changing the step
    from `old` to `new` (module docstring): the step at t_n at Δt_a, then the rest of the
    finest step, q_new − 1 steps at Δt_b. Returns (status, the failed step in steps of `new`,
    as advance)."""
    runs = awake.runs
    u = motion.u
    for i in range(awake.n_runs[0]):
        for d in range(3 * runs[i, 0], 3 * runs[i, 1]):
            saved[d] = u[d]
    status, failed_at = advance(n_old, n_old + 1, old, structure, ground, motion, work, peaks, out, contact, yielding,
                                awake)  # fmt: skip
    if status != STATUS_OK:
        return status, n_new
    change_step(old.dt, new.dt, structure, motion, work, saved, awake)
    return advance(n_new + 1, n_new + q_new, new, structure, ground, motion, work, peaks, out, contact, yielding, awake)


@kernel(**INTERNAL)
def change_step(old_dt, new_dt, structure, motion, work, saved, awake):
    """After the step at t_n at old_dt (u_n in `saved`): the half-step velocity, the position
    and the carried K·u, K·v, C·v of the awake buildings as the CDM at new_dt would have them
    from the same state at t_n (module docstring)."""
    rho = new_dt / old_dt
    u, v_half, dv = motion.u, motion.v_half, work.dv
    runs = awake.runs
    for i in range(awake.n_runs[0]):
        f0 = runs[i, 0]
        f1 = runs[i, 1]
        for d in range(3 * f0, 3 * f1):
            v_half[d] -= 0.5 * (1.0 - rho) * dv[d]
            dv[d] *= rho
            u[d] = saved[d] + new_dt * v_half[d]
        storey_matvec_range(u, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, motion.ku)
        storey_matvec_range(v_half, structure.storey_k, structure.storey_bottom, structure.storey_top, f0, f1, work.z)
        damping_force_range(v_half, work.z, structure.mass, structure.damping, 3 * f0, 3 * f1, motion.cv_half)
