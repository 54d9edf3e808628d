"""Resource limits: a model that would need more time, memory or disk than is sensible is
refused before it runs, with the estimate, the limit, and the input field that causes it.

Each limit bounds one resource and is read from the environment when it is checked, so one
run can raise it (``POUND_MAX_STEPS=1e9 pound run …``):

- ``POUND_MAX_STEPS`` — time steps of one analysis, default 2 × 10⁸: run time. Nothing is
  allocated per step, so steps cost time only: at the 0.065 µs per step and DOF of the
  central difference method (docs/bench.md) 2 × 10⁸ steps of the paper's two buildings
  (21 DOFs) take about 5 minutes, of 40 buildings (360 DOFs) 80 minutes. It is 4000 s of
  analysis at the paper's contact step of 20 µs; the issue's example of 10⁹ steps is refused.
- ``POUND_MAX_OUTPUT_GB`` — the result file, default 8 GiB: disk. Estimated by
  :func:`history_bytes`, every time history the file holds: the shipped examples' files are
  0.4–1.7 % larger (their tables, peaks and attributes; tests/test_limits.py).
- ``POUND_MAX_MEMORY_GB`` — memory for the time histories, default half the machine's
  physical memory: the solver holds every history in memory until the file is written, and
  writing copies some of them (:func:`memory_bytes`: twice the histories).
- ``POUND_MAX_STOREYS`` — storeys of one building, default 1000: the exact integrator holds
  a dense (6N)² state-transition matrix of a building of N storeys (0.27 GiB at 1000).

The limits fit together: at the step limit with the default output interval (0.01 s), the
paper's buildings at their contact step run 4300 s of analysis, whose histories take 0.3 GB:
well inside the disk and memory limits, which bind only for short output intervals, long
durations or large models. A floor entry's `repeat` is at most :data:`MAX_REPEAT`.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import InputError

MAX_COUNT = 2**62
"""The largest step or sample count a time grid holds (assembly/timestep.py: whole): a count
that would be larger, or not finite (a duration of 1e308 s, a step of 5e-324 s), is held at
MAX_COUNT, which the step limit refuses naming the field that causes it, rather than
overflowing on its way to an integer."""

GiB = 2**30
EVENT_BUFFER_BYTES = 200_000 * 11 * 8
"""The solver's impact log buffer when the model has contact pairs (MAX_EVENTS × EV_COLUMNS
floats, pounding_cli.solver), allocated whatever the run's length."""


def limit(name: str, default: float) -> float:
    """The limit POUND_<name> from the environment (a positive number), else `default`."""
    text = os.environ.get(f"POUND_{name}")
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"expected a positive number, got {text!r}", field=f"POUND_{name}") from None
    if not value > 0:
        raise InputError(f"expected a positive number, got {text!r}", field=f"POUND_{name}")
    return value


def max_steps() -> float:
    """Most time steps of one analysis (POUND_MAX_STEPS, default 2e8)."""
    return limit("MAX_STEPS", 2e8)


def max_output_bytes() -> float:
    """Largest result file, bytes (POUND_MAX_OUTPUT_GB, default 8 GiB)."""
    return limit("MAX_OUTPUT_GB", 8) * GiB


def max_memory_bytes() -> float:
    """Most memory for the time histories, bytes (POUND_MAX_MEMORY_GB, default half the
    machine's physical memory, 16 GiB where it cannot be read)."""
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        physical = 32 * GiB
    return limit("MAX_MEMORY_GB", physical / 2 / GiB) * GiB


def max_storeys() -> float:
    """Most storeys of one building (POUND_MAX_STOREYS, default 1000)."""
    return limit("MAX_STOREYS", 1000)


MAX_REPEAT = 500
"""Most storeys one floor entry may stand for (`repeat`). A fixed bound of the file format,
checked while the file is read, before anything is expanded: a slip such as 10⁶ cannot make a
million storeys. More storeys take several entries, up to max_storeys() in all."""


def check_repeat(repeat: int) -> None:
    """ValueError (for the model's validator) if one floor entry repeats too often."""
    if repeat > MAX_REPEAT:
        raise ValueError(
            f"{repeat} storeys in one floor entry: at most {MAX_REPEAT}, so that a slip of the pen cannot expand into "
            f"millions of storeys before the model is checked ({repeat} storeys would need "
            f"{_gib(propagator_bytes(repeat))} for the exact integrator's (6N)² matrix); a building of more storeys "
            f"takes several entries, up to {max_storeys():.0f} storeys in all (POUND_MAX_STOREYS)"
        )


def propagator_bytes(storeys: int) -> float:
    """Memory of the dense state-transition matrix of a building of `storeys` storeys, bytes:
    (2 · 3N)² floats of 8 bytes."""
    return float(6 * storeys) ** 2 * 8


@dataclass(frozen=True)
class Size:
    """What a run stores at each output sample."""

    n_dof: int
    n_pairs: int
    n_members: int

    @property
    def per_sample(self) -> int:
        """Bytes of history per output sample: time (1), ground acceleration (2), displacement,
        velocity and acceleration of every DOF (3 each), energy (7), normal and tangential force,
        area, depth and action point of every contact pair (6), deflection and force of every
        yielding member (4); float64 throughout."""
        return 8 * (1 + 2 + 3 * self.n_dof + 7 + 6 * self.n_pairs + 4 * self.n_members)


def history_bytes(size: Size, samples: int) -> int:
    """Bytes of the time histories a run writes: about the size of its HDF5 file."""
    return size.per_sample * samples


def memory_bytes(size: Size, samples: int) -> int:
    """Memory the run needs for its histories at most: the solver's arrays, as large as the
    histories, and the copies made while the results are cut per building and written, at
    most as large again (the peak memory of the shipped examples with 80–200 MiB of histories
    rose by 1.3–1.8 times their size); plus the impact log's buffer."""
    return 2 * history_bytes(size, samples) + (EVENT_BUFFER_BYTES if size.n_pairs else 0)


def check_structure(system, source: str | Path) -> None:  # type: ignore[no-untyped-def]
    """Refuse a building whose natural frequencies or damped decay rates are not finite
    (numbers at the ends of their ranges overflow in K or M⁻¹K): nothing derived from them
    could be trusted, and the time step would divide by them."""
    for b, bld in enumerate(system.buildings):
        omega = bld.modes.omega
        rate = bld.fastest_rate()[0]
        if not (np.all(np.isfinite(omega)) and math.isfinite(rate) and omega[-1] > 0):
            raise InputError(
                f"building {bld.name!r} has natural frequencies that are not finite numbers (ω_max = {omega[-1]:.4g} "
                f"rad/s, fastest decay {rate:.4g} 1/s): its stiffness, masses or damping reach beyond floating-point "
                "range; check the units of its column sections (m), storey heights (m), elastic_modulus (Pa), "
                "masses (kg) and rotational_inertia (kg·m²)",
                file=source,
                field=f"buildings[{b}]",
            )


def check_storeys(storeys: int, source: str | Path, field: str) -> None:
    """Refuse a building of more storeys than max_storeys()."""
    most = max_storeys()
    if storeys > most:
        raise InputError(
            f"{storeys} storeys: more than the limit of {most:.0f} (POUND_MAX_STOREYS): the exact integrator "
            f"holds a dense (6N)² state-transition matrix per building, {_gib(propagator_bytes(storeys))} for "
            f"{storeys} storeys against {_gib(propagator_bytes(int(most)))} at the limit",
            file=source,
            field=field,
        )


@dataclass(frozen=True)
class Run:
    """What the limits need to know of a prepared run (plain numbers, no model objects)."""

    dt: float  # s
    n_steps: int
    n_outputs: int
    output_interval: float  # s, as stored (a whole number of steps)
    duration: float  # s
    record_duration: float  # s, the record's length (the default duration)
    given_dt: float | None  # s, analysis.dt when not "auto"
    given_duration: float | None  # s, analysis.duration when given
    given_output_interval: float  # s, analysis.output_interval as given
    auto_dt: float  # s, the step "auto" would take for this structure and contact
    structure_limit: float  # s, 2/ω_max of the structure
    contact_limit: float  # s, 2/ω of the stiffest contact estimate (inf without contact)
    stiffest: tuple[int, str]  # (index, name) of the building of the highest natural frequency
    overdamped: tuple[int, str, int, float, float] | None = None  # (building, name, mode, ζ, ρ 1/s) where an
    # overdamped mode's decay rate ρ exceeds ω_max and bounds the hybrid's exact step
    contact_field: str = "contact.k_normal"  # the field that sets the contact the automatic step follows
    contact_auto: bool = False  # that field is "auto": the materials' elastic_modulus set it


def check_run(run: Run, size: Size, source: str | Path) -> None:
    """Refuse a run beyond the step, disk or memory limit, naming the field that causes it."""
    steps = max_steps()
    if run.n_steps > steps:
        field, why = _step_cause(run, steps)
        count = f"more than {MAX_COUNT:.3g}" if run.n_steps >= MAX_COUNT else f"{run.n_steps:.3g}"
        asked = run.given_duration if run.given_duration is not None else run.record_duration
        dt = run.given_dt if run.given_dt is not None and run.given_dt < run.dt else run.dt
        raise InputError(
            f"the analysis would take {count} time steps ({asked:.4g} s at Δt = {dt:.3g} s), "
            f"more than the limit of {steps:.3g} (POUND_MAX_STEPS); {why}",
            file=source,
            field=field,
        )
    for estimate, most, what, variable in (
        (history_bytes(size, run.n_outputs), max_output_bytes(), "its result file would take", "POUND_MAX_OUTPUT_GB"),
        (memory_bytes(size, run.n_outputs), max_memory_bytes(), "its time histories would hold", "POUND_MAX_MEMORY_GB"),
    ):
        if estimate > most:
            field, why = _sample_cause(run, size, estimate, most)
            raise InputError(
                f"{what} {_gib(estimate)} ({run.n_outputs:.3g} samples every {run.output_interval:.3g} s × "
                f"{size.per_sample} bytes: {size.n_dof} DOFs, {size.n_pairs} contact pairs, {size.n_members} "
                f"yielding members), more than the limit of {_gib(most)} ({variable}); {why}",
                file=source,
                field=field,
            )


def _step_cause(run: Run, most: float) -> tuple[str, str]:
    """The field that makes the run take too many steps, and what to do about it."""
    natural = run.given_dt if run.given_dt is not None else run.auto_dt
    forced = run.dt < natural * (1 - 1e-9) and run.output_interval <= max(run.given_output_interval, run.dt) * (1 + 1e-9)
    if run.given_output_interval < natural and (run.dt <= run.given_output_interval * (1 + 1e-9) or forced):
        return "analysis.output_interval", (
            f"an output interval of {run.given_output_interval:g} s forces the time step down to it (else Δt = "
            f"{natural:.3g} s); check its unit (s) and store less often"
        )
    if run.given_duration is not None and run.record_duration / run.dt <= most:
        return "analysis.duration", (
            f"a duration of {run.given_duration:g} s is {run.given_duration / run.record_duration:.3g} times the "
            "record's length; check its unit (s)"
        )
    if run.given_dt is not None:
        return "analysis.dt", f'a time step of {run.given_dt:g} s is far below what the model needs; check its unit (s) or use "auto"'
    if run.overdamped is not None and run.dt < natural * (1 - 1e-9):
        b, name, mode, zeta, rate = run.overdamped
        return f"buildings[{b}].damping", (
            f"its Rayleigh damping gives mode {mode} of building {name!r} a damping ratio of {zeta:.3g}: that "
            f"overdamped mode decays at {rate:.3g} 1/s, faster than any vibration (ω_max = "
            f"{2 / run.structure_limit:.3g} rad/s), and the exact steps must resolve it; anchor the damping at "
            "modes that vibrate (damping.modes) or check the masses and rotational_inertia (kg, kg·m²)"
        )
    if run.contact_limit < run.structure_limit:
        field = run.contact_field
        stiffness = field.rsplit(".", 1)[-1]
        unit = "N/m²" if stiffness == "k_normal" else "N/m"
        check = ("it is \"auto\": check the units of the materials' elastic_modulus (Pa)" if run.contact_auto
                 else f"check its unit ({unit})")  # fmt: skip
        return field, (
            f'Δt = "auto" follows the stiffest contact (stability limit {run.contact_limit:.3g} s), which '
            f"{stiffness} sets; {check}"
        )
    b, name = run.stiffest
    return f"buildings[{b}]", (
        f'Δt = "auto" follows the highest natural frequency of building {name!r} (stability limit '
        f"{run.structure_limit:.3g} s); check the units of its column sections (m), storey heights (m), "
        "elastic_modulus (Pa) and masses (kg)"
    )


def _sample_cause(run: Run, size: Size, estimate: float, most: float) -> tuple[str, str]:
    """The field that makes the stored histories too large, and what to do about it."""
    if run.given_duration is not None and estimate * run.record_duration / run.duration <= most:
        return "analysis.duration", (
            f"a duration of {run.given_duration:g} s is {run.given_duration / run.record_duration:.3g} times the "
            "record's length; check its unit (s)"
        )
    return "analysis.output_interval", "store less often (a larger output interval) or shorten the analysis"


def _gib(n: float) -> str:
    """A byte count in GiB (or MiB below 1 GiB)."""
    return f"{n / GiB:.4g} GiB" if n >= GiB else f"{n / 2**20:.4g} MiB"
