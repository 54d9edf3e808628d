"""Running a sweep: check every case, skip those already complete, run the others in
parallel, and rebuild the summary.

    outcome = run_sweep("angles.sweep.toml", "angles/", jobs=2)
    outcome.counts            # {"cases": 73, "complete": 73, "failed": 0, "pending": 0}

Cases whose inputs are identical (the same input_sha256) run once and share their file. A
case is skipped when its file exists with its input_sha256 and status "complete"; failed
and partial ones run again. However the sweep stops (Ctrl-C, kill -9, a power cut after
the rename), every case file with its final name is complete, and the next run picks up
where this one stopped.
"""

from __future__ import annotations

import os
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator

from ..errors import InputError, WriteError
from ..interrupts import stop_if_requested
from ..model.sweep import LoadedSweep, load_sweep
from .plan import Plan, plan_sweep
from .pool import LocalPool
from .store import OutputFolder
from .summary import case_row_values, counts, make_row, summary_rows, write_summary
from .tasks import run_case, write_failure

Row = dict[str, Any]


@dataclass
class SweepOutcome:
    """What a sweep did, and the summary rows as its case files stand at the end."""

    folder: Path
    rows: list[Row]
    ran: int = 0  # distinct runs started by this call
    reused: int = 0  # selected cases already complete before it
    interrupted: bool = False
    wall_time_s: float = 0.0
    summary: tuple[Path, Path] | None = None  # summary.h5, summary.csv (None for a dry run)
    selected: list[int] = field(default_factory=list)  # indices of the rows this call was to complete
    warnings: list[str] = field(default_factory=list)  # the cases' plausibility warnings (plan_sweep), one line each

    @property
    def counts(self) -> dict[str, int]:
        return counts(self.rows)

    @property
    def failed(self) -> list[Row]:
        """Selected rows whose status is a failure."""
        return [self.rows[i] for i in self.selected if self.rows[i]["status"].startswith("failed")]

    @property
    def ok(self) -> bool:
        """Every selected case complete."""
        return all(self.rows[i]["status"] == "complete" for i in self.selected)


def default_output(sweep_file: Path) -> Path:
    """The sweep file's name without .sweep.toml (or .toml, .json), in the current folder."""
    name = sweep_file.name
    for suffix in (".sweep.toml", ".sweep.json", ".toml", ".json"):
        if name.lower().endswith(suffix):
            return Path(name[: -len(suffix)] or "sweep")
    return Path(name)


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def run_sweep(
    sweep: str | Path | LoadedSweep,
    output: str | Path | None = None,
    *,
    jobs: int | None = None,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    client: Any = None,
    studies: list[str] | None = None,
    dry_run: bool = False,
    on_row: Callable[[Row], None] | None = None,
    on_progress: Callable[[str, int, int, int], None] | None = None,
    log: Callable[[str], None] | None = None,
    force: bool = False,
    strict: bool = False,
) -> SweepOutcome:
    """Run a sweep into `output` (default: :func:`default_output`) and rebuild its summary.

    Local processes (`jobs`, default all cores) unless a Dask `scheduler` address,
    `scheduler_file` or `client` is given. `studies` restricts which studies run (all are
    checked and listed). `dry_run` checks and lists without running or writing anything.
    `on_row(row)` is called with each selected case's summary row once it is known (cases
    already complete first); `on_progress(stage, done, failed, total)` as work finishes,
    stage "check" or "run"; `log(text)` with what the sweep is doing. The output folder must
    be new, empty or a sweep's (OutputFolder.check_owner) unless `force`, which is logged; a
    file the sweep writes there must not be one of its inputs (the sweep file, the base
    model, its record files). The cases' plausibility warnings are in `outcome.warnings`
    (and logged); with `strict` they are an InputError, before anything runs."""
    t0 = time.perf_counter()
    say = log or (lambda text: None)
    loaded = sweep if isinstance(sweep, LoadedSweep) else load_sweep(sweep)
    _check_studies(loaded, studies)
    folder = Path(output) if output is not None else default_output(loaded.source)
    if scheduler is not None or scheduler_file is not None or client is not None:
        # a Dask worker's current folder is not ours: it gets absolute paths
        loaded = LoadedSweep(loaded.sweep, loaded.source.absolute())
        folder = folder.absolute()
    folder = OutputFolder(folder)
    if not dry_run:
        note = folder.check_owner(force)  # before anything is checked or written
        if note:
            say(note)
    with open_executor(jobs, scheduler, scheduler_file, client) as executor:
        say(f"checking the cases of {loaded.source} on {executor.description}")
        checked = (lambda done, total: on_progress("check", done, 0, total)) if on_progress else None
        plan = plan_sweep(loaded, executor.run, checked, strict=strict)
        selected = [i for i, c in enumerate(plan.cases) if studies is None or c.spec.study in studies]
        if dry_run:
            rows = summary_rows(folder, plan.manifest())  # reads the folder, writes nothing
            return SweepOutcome(folder.root, rows, selected=selected, wall_time_s=time.perf_counter() - t0,
                                warnings=plan.warnings)  # fmt: skip
        _refuse_inputs(folder, loaded, plan)
        folder.prepare()
        with folder.locked():
            if removed := folder.remove_stale_temporaries():
                say(f"removed {len(removed)} temporary files left by an interrupted sweep")
            manifest = plan.manifest()
            folder.write_manifest(manifest)
            for line in plan.warnings:
                say(line)
            outcome = SweepOutcome(folder.root, [], selected=selected, warnings=plan.warnings)
            from ..interrupts import terminate_as_interrupt

            try:
                with terminate_as_interrupt():  # a batch system's SIGTERM stops it like Ctrl-C
                    _run(plan, selected, folder, executor, outcome, on_row, on_progress, say)
            except KeyboardInterrupt:
                outcome.interrupted = True
                executor.close()  # stop the workers before reading what they left
            outcome.rows = summary_rows(folder, manifest)
            outcome.summary = write_summary(folder, manifest, outcome.rows)
    outcome.wall_time_s = time.perf_counter() - t0
    return outcome


def _run(
    plan: Plan,
    selected: list[int],
    folder: OutputFolder,
    executor: Any,
    outcome: SweepOutcome,
    on_row: Callable[[Row], None] | None,
    on_progress: Callable[[str, int, int, int], None] | None,
    say: Callable[[str], None],
) -> None:
    """Report the complete cases, run the others, report each as it finishes."""
    manifest_cases = plan.manifest()["cases"]
    columns = [c.name for c in plan.columns()]
    by_hash: dict[str, list[int]] = {}
    for i in selected:
        by_hash.setdefault(plan.cases[i].hash, []).append(i)
    states = {h: folder.state(h, plan.cases[ix[0]].input_sha256) for h, ix in by_hash.items()}
    todo = [h for h, state in states.items() if not state.complete]
    done = [h for h in by_hash if h not in todo]
    outcome.reused = sum(len(by_hash[h]) for h in done)
    shared = len(selected) - len(by_hash)
    say(f"{len(selected)} cases" + (f" ({len(by_hash)} distinct: {shared} share inputs with another)" if shared else "")
        + f"; {outcome.reused} complete already, {len(todo)} to run")  # fmt: skip
    for h in done:
        _report(h, by_hash, manifest_cases, columns, folder, on_row)
    tasks = []
    for h in todo:
        case = plan.cases[by_hash[h][0]]
        args = (case.document, str(plan.base), case.input_sha256, str(folder.case_file(h)), str(folder.failure_file(h)))
        tasks.append((h, run_case, args))
    failed = 0
    if on_progress is not None:
        on_progress("run", 0, 0, len(tasks))
    for finished, (h, ok, value) in enumerate(executor.run(tasks), start=1):
        stop_if_requested()
        outcome.ran += 1
        if ok and isinstance(value, dict) and value.get("write_error"):  # a full disk: no case can be written
            raise WriteError(value["write_error"])
        if not ok:  # the worker died, or the cluster gave up on the task
            write_failure(folder.failure_file(h), plan.cases[by_hash[h][0]].input_sha256, f"failed: {value}")
        row_status = _report(h, by_hash, manifest_cases, columns, folder, on_row)
        failed += row_status != "complete"
        if on_progress is not None:
            on_progress("run", finished, failed, len(tasks))


def _report(
    h: str, by_hash: dict[str, list[int]], cases: list[dict[str, Any]], columns: list[str], folder: OutputFolder,
    on_row: Callable[[Row], None] | None,
) -> str:  # fmt: skip
    """Read a finished case's file and hand its row (one per case sharing it) to on_row."""
    found = case_row_values(folder, h, cases[by_hash[h][0]]["input_sha256"])
    if on_row is not None:
        for i in by_hash[h]:
            on_row(make_row(cases[i], found, columns))
    return found["status"]


def _refuse_inputs(folder: OutputFolder, loaded: LoadedSweep, plan: Plan) -> None:
    """InputError if a file the sweep writes at the top of its folder is one of its inputs:
    the sweep file, the base model, the base's record definition and record files."""
    from ..assembly.ground import resolve_record
    from ..model import load_model
    from ..outputs import refuse_inputs
    from .store import WRITES

    inputs = [(Path(loaded.source), "the file of this sweep"), (Path(plan.base), "the base model of this sweep")]
    try:
        base = load_model(plan.base)
        record, origin, record_file = resolve_record(base)
    except InputError:
        pass  # the cases were checked; a base that does not load alone has no files of its own
    else:
        inputs += [(Path(record_file), "the base's record definition")] if record_file is not None else []
        inputs += [(origin.resolve(c.file), f"the base's record file of component {name}")
                   for name, c in record.components().items()]  # fmt: skip
    for name in WRITES:
        refuse_inputs(folder.root / name, inputs, "another output folder (-o)")


def _check_studies(loaded: LoadedSweep, studies: list[str] | None) -> None:
    if studies is None:
        return
    known = list(loaded.sweep.studies)
    for name in studies:
        if name not in known:
            have = ", ".join(known) if known else "none (the sweep is one study)"
            raise InputError(f"no study {name!r} in {loaded.source}; its studies: {have}", field="--study")


@contextmanager
def open_executor(jobs: int | None, scheduler: str | None, scheduler_file: str | Path | None, client: Any = None) -> Iterator[Any]:
    """The local pool, or a Dask client (given, or connected to a scheduler), closed after: what
    sweeps, `pound gap --suite` and a run's independent groups (city/grouped.py) run on."""
    from .cluster import DaskExecutor

    if client is not None:
        executor: Any = DaskExecutor(client)
    elif scheduler or scheduler_file:
        if jobs is not None:
            raise InputError("applies to local runs only; a Dask cluster's workers decide how many cases "
                             "run at once", field="--jobs")  # fmt: skip
        executor = DaskExecutor.connect(scheduler, scheduler_file)
    else:
        if jobs is not None and jobs < 1:
            raise InputError(f"expected a number of processes ≥ 1, got {jobs}", field="--jobs")
        executor = LocalPool(jobs or default_jobs())
    try:
        yield executor
    finally:
        executor.close()
