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
- ``POUND_MAX_MEMORY_GB`` — memory, default half the machine's physical memory: the time
  histories, which the solver holds until the file is written and writing copies
  (:func:`memory_bytes`: twice the histories), plus what setting the run up takes
  (:func:`setup_bytes`: the exact integrator's matrix exponentials, 8·(48 + 4·B)·(6N + 4)²
  bytes for B buildings of at most N storeys, measured; the assembled columns).
- ``POUND_MAX_HOURS`` — estimated wall time of one analysis, default 24 h: the set-up (the
  exact integrator's exponentials, 3e-8·(6N + 4)³ s per building; 0.3 ms per column
  instance to assemble) and the time loop (:func:`step_seconds`, per step: 1.2 ns per entry
  of each building's dense (3N)² step matrix, 10 ns per DOF, 5 ns per column instance, 10 ns
  per contact pair). The rates were measured on the 2-core machine of docs/bench.md; a run
  is refused only when the estimate is beyond the limit, so they need not be exact.
- ``POUND_MAX_STOREYS`` — storeys of one building, default 1000: a bound on the count, checked
  before anything else (whether such a building fits is then the memory and time estimates':
  1000 storeys take 16 GiB and about 2 hours to set up the exact integrator).

The set-up estimates are checked from the counts alone (storeys, column instances), before
anything is assembled or allocated (:func:`check_setup`); the time loop's, with the contact
pairs and the steps, once the time grid is chosen (:func:`check_run`). A floor entry's
`repeat` is at most :data:`MAX_REPEAT`, a storey's columns (and a base's isolators) at most
:data:`MAX_COLUMNS`: fixed bounds of the file format, checked while the file is read.

The limits fit together: at the step limit with the default output interval (0.01 s), the
paper's buildings at their contact step run 4300 s of analysis, whose histories take 0.3 GB:
well inside the disk and memory limits, which bind only for short output intervals, long
durations or large models.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
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


def max_hours() -> float:
    """Longest estimated wall time of one analysis, hours (POUND_MAX_HOURS, default 24)."""
    return limit("MAX_HOURS", 24)


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


MAX_COLUMNS = 10_000
"""Most columns in one storey (a grid's crossings and the ones given one by one), and most
isolators under one base slab: a fixed bound of the file format, checked from the grid's
line counts before any column is generated (a 1000 × 1000 grid made validation hang).
Checking and assembling a column instance takes about 0.3 ms, and every step 5 ns."""


def check_columns(count: int, what: str = "columns in one storey") -> None:
    """ValueError (for the model's validators) if a storey has more than MAX_COLUMNS."""
    if count > MAX_COLUMNS:
        raise ValueError(
            f"{count} {what}: at most {MAX_COLUMNS} (a fixed bound of the file format; each column is checked, "
            f"assembled and followed at every step: about {count * SECONDS_PER_COLUMN:.3g} s to set up one storey "
            "of them)"
        )


SECONDS_PER_COLUMN = 3e-4
"""Set-up time per column instance (validated, assembled), s, measured: 31 s for 10⁵."""
SECONDS_PER_PAIR = 3e-4
"""Set-up time per contact candidate (its parameters, its likely contact line), s, measured:
2.1 s for 8,850 (60 buildings of 5 storeys in a row)."""
BYTES_PER_COLUMN = 600
"""Memory per assembled column instance, bytes, measured: 276 MiB for 5·10⁵."""
EXACT_SECONDS = 3e-8
"""The exact integrator's set-up per building of augmented size s = 6N + 4: EXACT_SECONDS·s³
(its matrix exponentials and eigenvalues), measured: 158 s at N = 300, 64 s at N = 200."""
EXACT_MATRICES = 48
"""The exact integrator's peak memory in (6N + 4)² matrices of 8 bytes, for the largest
building, plus 4 per building for the propagators kept: 1408 MiB measured at N = 300 (two
buildings: 56 matrices of 26 MiB)."""
STEP_SECONDS = {"dense": 1.2e-9, "dof": 1e-8, "column": 5e-9, "pair": 1e-8, "exact": 4e-9}
"""The time loop's cost per step, s, measured on the CDM (fixed Δt, 2 s of record): per entry
of each building's dense step matrix B⁻¹ (3N)² (105 µs/step at N = 100), per DOF, per column
instance (43 µs/step for 9,000), per contact pair (7 µs for 1,050); an exact step costs "exact"
per entry of each building's (6N + 4)² propagator."""


@dataclass(frozen=True)
class Setup:
    """What a model's size is before it is assembled: the counts the estimates need."""

    storeys: tuple[int, ...]  # per building, the base slab of an isolated one included
    columns: tuple[int, ...]  # column instances per building (columns × the storeys they repeat in)
    exact: bool  # the exact (hybrid) integrator may run: its dense matrix exponentials
    pairs: int = 0  # contact candidates: floors of two buildings at one level, floors and obstacles

    @property
    def dofs(self) -> tuple[int, ...]:
        return tuple(3 * n for n in self.storeys)


def setup_bytes(setup: Setup) -> float:
    """Memory of setting a run up, bytes: the columns, each building's dense K, C and step
    matrix, and for the exact integrator its matrix exponentials (EXACT_MATRICES)."""
    n_max, n_b = max(setup.dofs), len(setup.dofs)
    dense = 8.0 * 4 * n_b * float(n_max) ** 2
    exact = 8.0 * (EXACT_MATRICES + 4 * n_b) * float(2 * n_max + 4) ** 2 if setup.exact else 0.0
    return BYTES_PER_COLUMN * float(sum(setup.columns)) + dense + exact


def setup_seconds(setup: Setup) -> float:
    """Wall time of setting a run up, s: the columns and, for the exact integrator, its
    matrix exponentials (cubic in each building's size)."""
    exact = sum(EXACT_SECONDS * float(2 * n + 4) ** 3 for n in setup.dofs) if setup.exact else 0.0
    return SECONDS_PER_COLUMN * float(sum(setup.columns)) + SECONDS_PER_PAIR * setup.pairs + exact


def step_seconds(setup: Setup, n_pairs: int, exact: bool = False) -> float:
    """Wall time of one step of the time loop, s (STEP_SECONDS): a CDM step, or an exact one."""
    c = STEP_SECONDS
    matrix = sum(c["exact"] * float(2 * n + 4) ** 2 if exact else c["dense"] * float(n) ** 2 for n in setup.dofs)
    return matrix + c["dof"] * sum(setup.dofs) + c["column"] * sum(setup.columns) + c["pair"] * n_pairs


def check_setup(setup: Setup, source: str | Path) -> None:
    """Refuse, before anything is assembled, a model whose set-up alone would take more memory
    or time than the limits, naming the floors of the building that causes it."""
    sizes = [(4 * n * n + (EXACT_MATRICES * (2 * n + 4) ** 2 if setup.exact else 0), b) for b, n in enumerate(setup.dofs)]
    b = max(sizes)[1] if sum(setup.columns) * BYTES_PER_COLUMN < max(sizes)[0] * 8 else int(np.argmax(setup.columns))
    memory, most = setup_bytes(setup), max_memory_bytes()
    what = (f"{setup.storeys[b]} storeys and {setup.columns[b]} column instances in building {b}"
            + (", with the exact integrator (integrator = \"cdm\" needs no matrix exponentials)" if setup.exact else "")
            + (f"; {setup.pairs} contact pairs" if setup.pairs else ""))  # fmt: skip
    if memory > most:
        raise InputError(
            f"setting the analysis up would take about {_gib(memory)} of memory ({what}), more than the limit of "
            f"{_gib(most)} (POUND_MAX_MEMORY_GB)",
            file=source,
            field=f"buildings[{b}].floors",
        )
    seconds, hours = setup_seconds(setup), max_hours()
    if seconds > 3600 * hours:
        raise InputError(
            f"setting the analysis up would take about {_duration(seconds)} ({what}, at the rates measured in "
            f"pounding_cli/limits.py), more than the limit of {hours:g} h (POUND_MAX_HOURS)",
            file=source,
            field=f"buildings[{b}].floors",
        )


def _duration(seconds: float) -> str:
    """A duration in s, min or h."""
    if seconds < 120:
        return f"{seconds:.3g} s"
    return f"{seconds / 60:.3g} min" if seconds < 7200 else f"{seconds / 3600:.3g} h"


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
    n_forces: int = 0  # storey shear and floor contact force values (force_values)
    n_column_forces: int = 0  # column force values, when their histories are asked for (force_values)
    building_item: int = 8  # bytes of a value of the buildings' histories (results.result.HISTORY_DTYPE)

    @property
    def per_sample(self) -> int:
        """Bytes of history per output sample: time (1), ground acceleration (2), energy (7),
        normal and tangential force, area, depth and action point of every contact pair (6), in
        float64; displacement, velocity and acceleration of every DOF (3 each), deflection and
        force of every yielding member (4) and the forces (force_values), in the buildings'
        history precision (building_item bytes)."""
        return (8 * (1 + 2 + 7 + 6 * self.n_pairs)
                + self.building_item * (3 * self.n_dof + 4 * self.n_members + self.n_forces + self.n_column_forces))  # fmt: skip


def force_values(buildings, column_histories: bool) -> tuple[int, int]:  # type: ignore[no-untyped-def]
    """Force values per output sample of the buildings (assembly BuildingArrays): 6 per storey
    and 6 for the base shear, 3 contact forces per floor; and with the column histories 4 per
    column line and storey (shears and moments along local x, y, NaN where a line is absent)."""
    storeys = sum(6 * b.n_floors + 6 + 3 * b.n_floors for b in buildings)
    columns = sum(4 * len(b.column_lines) * b.n_floors for b in buildings) if column_histories else 0
    return storeys, columns


def history_bytes(size: Size, samples: int) -> int:
    """Bytes of the time histories a run holds: about the size of its HDF5 file at most (contact
    histories are written only where they hold a value, results/sparse.py)."""
    return size.per_sample * samples


def memory_bytes(size: Size, samples: int) -> int:
    """Memory the run needs for its histories at most: the solver's arrays, as large as the
    histories, and the copies made while the results are cut per building and written, at
    most as large again (the peak memory of the shipped examples with 80–200 MiB of histories
    rose by 1.3–1.8 times their size), counted in float64 whatever the stored precision (the
    solver's are); plus the impact log's buffer."""
    return 2 * history_bytes(replace(size, building_item=8), samples) + (EVENT_BUFFER_BYTES if size.n_pairs else 0)


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
    contact_buildings: tuple[int, ...] = ()  # the buildings of the pair whose contact sets that step
    suspects: tuple[tuple[str, str], ...] = ()  # (field, message) of the plausibility warnings of values that
    # shorten the step (too light, too stiff): the likeliest cause, blamed before the step's own field


def check_run(run: Run, size: Size, source: str | Path, setup: Setup | None = None, exact_steps: int = 0) -> None:
    """Refuse a run beyond the step, disk, memory or time limit, naming the field that causes
    it. `setup`: the model's counts (for the set-up's memory and time); `exact_steps`: the
    hybrid's exact steps without contact (grid.free_steps), 0 for the CDM."""
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
    extra = setup_bytes(setup) if setup is not None else 0.0
    in_memory = replace(size, building_item=8)  # the solver's histories are float64 whatever is stored
    for held, estimate, most, what, variable, more in (
        (size, history_bytes(size, run.n_outputs), max_output_bytes(), "its result file would take",
         "POUND_MAX_OUTPUT_GB", 0.0),
        (in_memory, memory_bytes(size, run.n_outputs), max_memory_bytes(), "its time histories would hold",
         "POUND_MAX_MEMORY_GB", extra),
    ):  # fmt: skip
        if estimate + more > most:
            field, why = _sample_cause(run, held, estimate, most - more, stored=held is not in_memory)
            besides = f" beside the {_gib(more)} of setting it up" if more >= 2**20 else ""
            raise InputError(
                f"{what} {_gib(estimate)} ({run.n_outputs:.3g} samples every {run.output_interval:.3g} s × "
                f"{held.per_sample} bytes: {held.n_dof} DOFs, {held.n_pairs} contact pairs, {held.n_members} "
                f"yielding members, {held.n_forces + held.n_column_forces} force values){besides}, more than the limit of {_gib(most)} ({variable}); {why}",
                file=source,
                field=field,
            )
    if setup is not None:
        _check_time(run, size, setup, exact_steps, source)


def _check_time(run: Run, size: Size, setup: Setup, exact_steps: int, source: str | Path) -> None:
    """Refuse a run whose estimated wall time (set-up and time loop) is beyond POUND_MAX_HOURS:
    the time loop's steps (the CDM's, or the hybrid's exact ones where no contact is
    possible: contacts add CDM steps, so the estimate is a lower bound there) times their
    cost (step_seconds)."""
    per_step = step_seconds(setup, size.n_pairs, exact=exact_steps > 0)
    loop = per_step * (exact_steps or run.n_steps)
    total, hours = setup_seconds(setup) + loop, max_hours()
    if total <= 3600 * hours:
        return
    costs = f"set-up {_duration(setup_seconds(setup))}, {exact_steps or run.n_steps:.3g} steps of {per_step * 1e6:.3g} µs"
    if loop > 10 * setup_seconds(setup) and per_step < 1e-4:  # many steps of a small model: the steps' cause
        field, why = _step_cause(run, (3600 * hours - setup_seconds(setup)) / per_step)
    else:
        b = int(np.argmax([n * n + 4 * c for n, c in zip(setup.dofs, setup.columns)]))
        field = f"buildings[{b}].floors"
        why = (f"building {b} has {setup.storeys[b]} storeys and {setup.columns[b]} column instances, "
               f"and the scene {size.n_pairs} contact pairs")  # fmt: skip
    raise InputError(
        f"the analysis would take about {_duration(total)} ({costs}, at the rates measured in "
        f"pounding_cli/limits.py), more than the limit of {hours:g} h (POUND_MAX_HOURS); {why}",
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
    record_steps = run.record_duration / run.dt  # the steps of the record's own length
    if run.given_duration is not None and run.given_duration > run.record_duration and (
        record_steps <= most or run.given_duration / run.record_duration > record_steps / most
    ):  # the duration is what exceeds the limit, or exceeds the record by more than the record exceeds it
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
        within = ["materials."] + [f"buildings[{b}]" for b in run.contact_buildings]  # the stiffness itself: below
        if suspect := _suspect(run, within):
            return suspect[0], (f'Δt = "auto" follows the stiffest contact (stability limit {run.contact_limit:.3g} '
                                f"s), and {suspect[1]}")  # fmt: skip
        stiffness = field.rsplit(".", 1)[-1]
        unit = "N/m²" if stiffness == "k_normal" else "N/m"
        check = ("it is \"auto\": check the units of the materials' elastic_modulus (Pa)" if run.contact_auto
                 else f"check its unit ({unit})")  # fmt: skip
        return field, (
            f'Δt = "auto" follows the stiffest contact (stability limit {run.contact_limit:.3g} s), which '
            f"{stiffness} sets; {check}"
        )
    b, name = run.stiffest
    if suspect := _suspect(run, [f"buildings[{b}]", "materials."]):
        return suspect[0], (f'Δt = "auto" follows the highest natural frequency of building {name!r} (stability '
                            f"limit {run.structure_limit:.3g} s), and {suspect[1]}")  # fmt: skip
    return f"buildings[{b}]", (
        f'Δt = "auto" follows the highest natural frequency of building {name!r} (stability limit '
        f"{run.structure_limit:.3g} s); check the units of its column sections (m), storey heights (m), "
        "elastic_modulus (Pa) and masses (kg)"
    )


def _suspect(run: Run, within: list[str]) -> tuple[str, str] | None:
    """The first plausibility warning (field, message) of a value that shortens the step,
    whose field starts with one of `within` (a building, the materials, a stiffness)."""
    return next(((f, m) for f, m in run.suspects if any(f.startswith(w) for w in within)), None)


def _sample_cause(run: Run, size: Size, estimate: float, most: float, stored: bool) -> tuple[str, str]:
    """The field that makes the histories too large (`stored`: the file's, else memory's), and
    what to do about it."""
    if size.n_column_forces and estimate * (1 - size.building_item * size.n_column_forces / size.per_sample) <= most:
        return "analysis.column_force_histories", (
            "the column force histories take most of it: set column_force_histories = false (the columns' peak "
            "forces are stored regardless)"
        )
    if stored and size.building_item == 8 and history_bytes(replace(size, building_item=4), run.n_outputs) <= most:
        return "analysis.history_precision", (
            'the buildings\' histories in single precision would fit: set history_precision = "single" (7 '
            "significant digits; peaks, impact log and energies stay in double precision)"
        )
    if run.given_duration is not None and estimate * run.record_duration / run.duration <= most:
        return "analysis.duration", (
            f"a duration of {run.given_duration:g} s is {run.given_duration / run.record_duration:.3g} times the "
            "record's length; check its unit (s)"
        )
    return "analysis.output_interval", "store less often (a larger output interval) or shorten the analysis"


def _gib(n: float) -> str:
    """A byte count in GiB (or MiB below 1 GiB)."""
    return f"{n / GiB:.4g} GiB" if n >= GiB else f"{n / 2**20:.4g} MiB"
