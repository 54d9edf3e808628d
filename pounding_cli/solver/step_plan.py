"""The hybrid's plan of steps, as plain Python (no numba): how often its exact step may halve
toward a contact, and which steps its contact phases take (step_levels.py). `pound validate`
shows the plan without loading the compiled kernels; the time loop builds its records from it."""

from __future__ import annotations

import math

import numpy as np

from .tunables import APPROACH_MEMORY, APPROACH_MIN_STEPS


def approach_levels(substep: int, n_max: int, n_buildings: int) -> int:
    """How many times the hybrid may halve its exact step toward a contact: the largest L
    with substep a multiple of 2^L, substep/2^L ≥ APPROACH_MIN_STEPS CDM steps, and the
    L + 1 sets of propagators (n_buildings × ((2·n_max)² + (2·n_max + 4)²) each: Φ and the
    damping form) within APPROACH_MEMORY."""
    per_level = 8 * n_buildings * ((2 * n_max) ** 2 + (2 * n_max + 4) ** 2)
    levels = 0
    while (substep % 2 ** (levels + 1) == 0 and substep // 2 ** (levels + 1) >= APPROACH_MIN_STEPS
           and (levels + 2) * per_level <= APPROACH_MEMORY):  # fmt: skip
        levels += 1
    return levels


def phase_plan(substep: int, yield_substep: int, fine: int, pair_step_ratio: np.ndarray | None,
               n_pairs: int) -> tuple[list[int], np.ndarray]:  # fmt: skip
    """(q_ℓ, level of each pair) of a hybrid run with `substep` contact steps a substep, `fine`
    finest exact steps in it and the yielding step's `yield_substep` steps a substep: the contact
    phases' levels take q_ℓ = ⌈q0/2^ℓ⌉ CDM steps in each finest exact step (q0 = substep/fine,
    at the contact step; never fewer than the yielding step's, each level fewer than the one
    before), up to the coarsest a pair uses; pair p belongs to the coarsest with
    q0/q_ℓ ≤ pair_step_ratio[p] (how many times longer than the contact step its own contact
    allows, ≥ 1; None: one level, every pair at 0)."""
    q0 = substep // fine
    q_min = max(1, math.ceil(yield_substep / fine))
    counts = [q0]
    while pair_step_ratio is not None and n_pairs and math.ceil(q0 / 2 ** len(counts)) >= q_min:
        q = math.ceil(q0 / 2 ** len(counts))
        if q == counts[-1]:
            break
        counts.append(q)
    level = np.zeros(n_pairs, dtype=np.int64)
    if len(counts) > 1:
        ratio = np.asarray(pair_step_ratio, dtype=float)
        for ell, q in enumerate(counts):
            level[q0 / q <= ratio * (1 + 1e-12)] = ell
        counts = counts[: int(level.max(initial=0)) + 1]
    return counts, level
