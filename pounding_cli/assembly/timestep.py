"""The time grid of an analysis: step, output stride, number of steps, and the substeps of
the hybrid integrator.

The central difference method (CDM) is stable for Δt < 2/ω_max. `dt = "auto"` takes the
finest of what each part of the scene needs for accuracy (stability needs far less; see
docs/theory.md §6): AUTO_DT_FRACTION of the structure's limit 2/ω_max for linear buildings,
YIELD_DT_FRACTION of it with yielding members, CONTACT_DT_FRACTION of 2/ω_contact where
contact is possible, ω_contact the fastest vibration of the contacts the scene is likely to
make (pounding_cli.assembly.contact: omega_step, from the angles between the slabs' edges;
the run checks it against the contacts it met, api.execute).

The hybrid integrator (the default) advances the buildings exactly over substeps h while no
contact is possible: h divides the record's sample interval (so the ground acceleration is
linear within it) and is short enough to sample peaks well, ω_max,structure·h ≤
HYBRID_SAMPLING (YIELD_SAMPLING with yielding members); around contacts it runs the CDM at
Δt = h/sub. Where only yielding members need the CDM (no contact possible), the contact does
not limit the step: the CDM runs at h/sub_y, the same fraction of the structure's own limit
(sub_y ≤ sub). Toward a contact the hybrid halves its exact step down to h/2^L (its approach
levels, solver/step_plan.py: approach_levels): with `dt = "auto"` and contact possible, sub
is rounded up to a multiple of 2^L (L the largest with sub/2^L ≥ APPROACH_MIN_STEPS), a step
at most 1/8 finer. Everything is expressed in CDM steps at the contact step: n_steps and
stride are multiples of `substep` (= sub).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..errors import InputError
from ..limits import MAX_COUNT
from ..model import Analysis
from ..solver.tunables import (
    APPROACH_MIN_STEPS,
    AUTO_DT_FRACTION,
    CONTACT_DT_FRACTION,
    CREST_SPAN,
    HYBRID_SAMPLING,
    YIELD_DT_FRACTION,
    YIELD_SAMPLING,
)


def hybrid_sampling(yielding: bool) -> float:
    """The hybrid's ω_max·h: YIELD_SAMPLING where members yield, HYBRID_SAMPLING elsewhere."""
    return YIELD_SAMPLING if yielding else HYBRID_SAMPLING


@dataclass(frozen=True)
class TimeGrid:
    """CDM steps t_n = n·dt for n = 0 … n_steps; output every `stride` steps; the hybrid
    integrator's exact substeps are `substep` steps long (0: the CDM throughout)."""

    dt: float  # s
    stride: int  # steps per output sample
    n_steps: int  # a multiple of stride
    stability_limit: float  # 2/ω_max of the structure, s
    contact_limit: float = float("inf")  # 2/ω of the stiffest contact the outlines allow, s
    substep: int = 0  # CDM steps per exact substep; 0 = CDM only
    yield_substep: int = 0  # hybrid: CDM steps per substep while only members may yield (≤ substep)
    contact_step_limit: float = float("inf")  # 2/ω of the likely contacts the automatic step follows, s
    fastest_rate: float = 0.0  # ρ of the structure, 1/s (≥ ω_max; more where a mode is overdamped): hybrid_sampling bounds ρ·h

    @property
    def integrator(self) -> Literal["cdm", "hybrid"]:
        return "hybrid" if self.substep else "cdm"

    @property
    def contact_step_omega(self) -> float:
        """ω of the likely contacts the automatic contact step followed, rad/s (0 without contact)."""
        return 2.0 / self.contact_step_limit

    @property
    def yield_dt(self) -> float:
        """The hybrid's CDM step where only yielding members need the CDM, s."""
        return self.dt * self.substep / self.yield_substep if self.yield_substep else self.dt

    def free_steps(self, record_dt: float) -> int:
        """The steps the integrator takes if no contact is possible and nothing yields: the
        CDM's steps, or the hybrid's exact ones, two substeps at once where ω_max·2h ≤
        CREST_SPAN, except across an output or record sample (solver/hybrid.py)."""
        if not self.substep:
            return self.n_steps
        total = self.n_steps // self.substep
        if max(2.0 / self.stability_limit, self.fastest_rate) * 2.0 * self.dt * self.substep > CREST_SPAN:
            return total
        per_record = nearest(record_dt / (self.dt * self.substep))
        return paired_steps(total, self.stride // self.substep, per_record)

    @property
    def output_interval(self) -> float:
        return self.dt * self.stride

    @property
    def duration(self) -> float:
        return self.dt * self.n_steps

    @property
    def n_outputs(self) -> int:
        return self.n_steps // self.stride + 1


def whole(x: float) -> int:
    """ceil(x) as an integer, for a count derived from the input: at least 1 and at most
    MAX_COUNT, NaN and infinity included (their runs are refused by the limits)."""
    if not x < MAX_COUNT:  # also NaN and +inf
        return MAX_COUNT
    return max(1, math.ceil(x))


def nearest(x: float) -> int:
    """round(x) as an integer count, at least 1 and at most MAX_COUNT (as whole())."""
    if not x < MAX_COUNT:
        return MAX_COUNT
    return max(1, round(x))


def _ratio(a: float, b: float) -> float:
    """a/b for positive a, b; inf where b underflows to 0 or the quotient overflows."""
    return a / b if b > 0 else math.inf


def paired_steps(total: int, a: int, b: int) -> int:
    """Steps over `total` substeps taken two at once except across a mark: every a-th and
    every b-th substep, and the last (Σ ⌈gap/2⌉ over the gaps between marks). The marks repeat
    every lcm(a, b) substeps, so one period is counted and multiplied: no array as long as the
    run (2·10⁸ substeps would have taken 3 GB)."""
    period = math.lcm(a, b)
    if period // a + period // b > 10**6:  # marks too sparse to list: each gap counted as two steps at once
        return (total + 1) // 2 + total // a + total // b

    def count(end: int) -> int:
        marks = np.union1d(np.union1d(np.arange(0, end + 1, a), np.arange(0, end + 1, b)), [end])
        return int(np.sum((np.diff(marks) + 1) // 2))

    full, rest = divmod(total, period)
    return full * count(period) + (count(rest) if rest else 0)


def stability_limit(omega_max: float) -> float:
    """Critical step of the central difference method, 2/ω_max, s."""
    return 2.0 / omega_max


def governing_rule(limit: float, contact_limit: float, yielding: bool) -> tuple[str, float]:
    """Which limit sets the automatic step, "structure" or "contact", and the fraction of it
    taken: Δt_auto = fraction · that limit."""
    structure = YIELD_DT_FRACTION if yielding else AUTO_DT_FRACTION
    if CONTACT_DT_FRACTION * contact_limit < structure * limit:
        return "contact", CONTACT_DT_FRACTION
    return "structure", structure


def time_grid(
    analysis: Analysis,
    omega_max: float,
    record_duration: float,
    source: str = "",
    omega_contact: float = 0.0,
    record_dt: float | None = None,
    dt_fraction: float | None = None,
    sampling_scale: float = 1.0,
    yielding: bool = False,
    dt_scale: float = 1.0,
    omega_contact_step: float | None = None,
    fastest_rate: float = 0.0,
) -> TimeGrid:
    """Choose the integrator, Δt, the output stride and the step count for an analysis.
    omega_contact: the contacts' upper bound (rad/s, 0 without contact); omega_contact_step:
    the likely fastest contact, which the automatic step follows (default omega_contact);
    yielding: the structure has yielding members. For `pound bench`: dt_fraction replaces the
    automatic rule by dt_fraction · 2/ω_max (structure or contact, the smaller limit);
    dt_scale scales every automatic step; sampling_scale the hybrid's ω_max·h (hybrid_sampling).
    fastest_rate: ρ of the buildings, 1/s (System.fastest_rate; 0: omega_max): where a mode is
    overdamped its decay outpaces ω_max, and the exact steps are bounded by ρ·h instead, as the solver's
    crest search needs (solver/peaks.py: crest_series_order sums a series in ρ·h)."""
    limit = stability_limit(omega_max)
    contact_limit = stability_limit(omega_contact) if omega_contact > 0 else float("inf")
    omega_step = omega_contact if omega_contact_step is None else omega_contact_step
    step_limit = stability_limit(omega_step) if omega_step > 0 else float("inf")
    rate = fastest_rate if fastest_rate > 0 else omega_max  # ρ ≥ the buildings' ω_max (omega_max may hold local modes)
    if analysis.dt != "auto" and float(analysis.dt) >= limit:
        raise InputError(
            f"time step {float(analysis.dt):g} s is at or above the stability limit 2/ω_max = {limit:.4g} s "
            f"of the central difference method (ω_max = {omega_max:.4g} rad/s); use a "
            f'smaller step or "auto"',
            file=source or None,
            field="analysis.dt",
        )
    auto = analysis.dt == "auto" and dt_fraction is None
    if analysis.dt != "auto":
        target = float(analysis.dt)
    elif dt_fraction is not None:
        target = dt_fraction * min(limit, contact_limit)
    else:
        which, fraction = governing_rule(limit, step_limit, yielding)
        target = dt_scale * fraction * (step_limit if which == "contact" else limit)
    duration = analysis.duration if analysis.duration is not None else record_duration
    out = analysis.output_interval
    hybrid = analysis.integrator == "hybrid" or (analysis.integrator == "auto" and record_dt is not None)
    # every count below comes from whole(): a quotient that overflows (or a step that
    # underflows) gives MAX_COUNT, refused by the limits, not an OverflowError here
    if hybrid and record_dt is not None:
        h, stride_h = _substeps(record_dt, out, _ratio(sampling_scale * hybrid_sampling(yielding), rate))
        sub = whole(_ratio(h, target) - 1e-9)
        if omega_contact > 0 and analysis.dt == "auto":  # room for the approach levels (solver.step_plan.approach_levels)
            power = 2 ** max(0, int(math.log2(sub / APPROACH_MIN_STEPS)))
            sub = power * math.ceil(sub / power)
        dt = h / sub
        stride = stride_h * sub
        # yielding without contact: the structure's own limit (a given Δt holds everywhere)
        sub_y = min(sub, whole(_ratio(h, dt_scale * YIELD_DT_FRACTION * limit) - 1e-9)) if auto else sub
    else:
        sub = sub_y = 0
        if analysis.dt == "auto":  # the output interval a whole number of steps
            stride = whole(_ratio(out, target) - 1e-9)
            dt = max(out / stride, 5e-324)  # a step that underflows: held at the least float, refused as above
        else:
            dt = target
            stride = nearest(_ratio(out, dt))
    n_out = whole(_ratio(duration, stride * dt) - 1e-9)
    return TimeGrid(dt, stride, n_out * stride, limit, contact_limit, sub, sub_y, step_limit, rate)


def _substeps(record_dt: float, out: float, h_max: float) -> tuple[float, int]:
    """(h, substeps per output) with h = record_dt/m ≤ h_max, and the output interval a whole
    number of substeps when it is commensurate with the record's interval."""
    m = whole(_ratio(record_dt, h_max) - 1e-9)
    ratio = _ratio(record_dt, out)
    if ratio >= MAX_COUNT:  # outputs too close to count (5e-324 s): as many substeps as counts hold
        m = MAX_COUNT
    elif ratio > 1 and abs(ratio - round(ratio)) < 1e-9:  # several outputs per record sample
        q = round(ratio)
        m = q * math.ceil(m / q)
    h = record_dt / m
    return h, nearest(_ratio(out, h))
