"""Running sweeps: the shipped sweep, bitwise equality with `pound run` and across --jobs and
Dask (threads, worker processes, a scheduler file), resuming (after a kill -9 of a real sweep
too, its temporaries removed), failures that stop nothing, the summary's three forms and
their values against the case files, the worker pool, the progress bar, and the CLI's exit
codes."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import jsonschema
import numpy as np
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.errors import InputError
from pounding_cli.model import read_document
from pounding_cli.schema import sweep_summary_schema
from pounding_cli.sweep import plan_sweep, read_summary, rebuild_summary, run_sweep
from pounding_cli.sweep.pool import LocalPool
from pounding_cli.sweep.store import OutputFolder

from conftest import INPUTS, SHARED, sweep_then_kill

SMALL = INPUTS / "pounding_angle_gap.sweep.toml"
BASE = INPUTS / "paper_pounding.toml"
TIMES = ("solver_time_s", "wall_time_s")
runner = CliRunner()


def datasets(path: Path) -> dict[str, np.ndarray]:
    """Every dataset of an HDF5 file by name."""
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return out


def same_bits(x: np.ndarray, y: np.ndarray) -> bool:
    """Equal bit for bit: numbers by their bytes, strings (object fields) by value."""
    if x.dtype != y.dtype or x.shape != y.shape:
        return False
    if x.dtype.names:
        return all(same_bits(x[name], y[name]) for name in x.dtype.names)
    if x.dtype == object:
        return x.tolist() == y.tolist()
    return x.tobytes() == y.tobytes()


def assert_bitwise_equal(a: Path, b: Path) -> None:
    da, db = datasets(a), datasets(b)
    assert sorted(da) == sorted(db), f"{a.name}, {b.name}: different datasets"
    for name in da:
        assert same_bits(da[name], db[name]), f"{a} and {b} differ in {name}"


def without_times(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in r.items() if k not in TIMES} for r in rows]


def write_sweep(tmp: Path, text: str, name: str = "s.sweep.toml") -> Path:
    path = tmp / name
    path.write_text(f'base = "{BASE.as_posix()}"\n' + text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def two_jobs(tmp_path_factory):
    """The shipped sweep, run with --jobs 2 through the API."""
    out = tmp_path_factory.mktemp("two") / "out"
    rows = []
    outcome = run_sweep(SMALL, out, jobs=2, on_row=rows.append)
    return outcome, rows


# --- the shipped sweep -------------------------------------------------------------------------


def test_shipped_sweep_runs(two_jobs):
    outcome, rows = two_jobs
    assert outcome.ok and outcome.counts == {"cases": 8, "complete": 8, "failed": 0, "pending": 0}
    assert outcome.ran == 8 and outcome.reused == 0 and not outcome.interrupted
    files = sorted((outcome.folder / "cases").iterdir())
    assert [f.name for f in files] == sorted(f"{r['hash']}.h5" for r in outcome.rows)
    assert {r["hash"] for r in rows} == {r["hash"] for r in outcome.rows}, "on_row saw every case"
    by_gap = {(r["excitation.angle"], r["buildings.right.origin[0]"]): r for r in outcome.rows}
    assert by_gap[(0.0, 8.02)]["impacts"] > by_gap[(0.0, 8.05)]["impacts"] >= 1, "a narrower gap, more impacts"
    for r in outcome.rows:
        assert r["energy_balance_error"] < 0.01
        assert r["peak_isd_x_m[left]"] >= max(r[f"peak_isd_x_m[left/C9/{s}]"] for s in range(1, 5))


def test_jobs_1_and_2_give_bitwise_identical_case_files(two_jobs, tmp_path):
    outcome, _ = two_jobs
    one = run_sweep(SMALL, tmp_path / "one", jobs=1)
    assert one.ok
    for row in outcome.rows:
        assert_bitwise_equal(outcome.folder / row["file"], one.folder / row["file"])
    assert without_times(one.rows) == without_times(outcome.rows)


def test_a_case_file_is_what_pound_run_writes(two_jobs, tmp_path):
    """Two cases run one by one with `pound run` (their model written beside the base model,
    so that the record is found) give the same datasets, bit for bit, and the same hash."""
    outcome, _ = two_jobs
    plan = plan_sweep(SMALL)
    for case in (plan.cases[0], plan.cases[5]):
        model = BASE.parent / f".test-case-{case.hash}.json"
        model.write_text(json.dumps(case.document), encoding="utf-8")
        try:
            result = runner.invoke(app, ["run", str(model), "-o", str(tmp_path / f"{case.hash}.h5")])
        finally:
            model.unlink()
        assert result.exit_code == 0, result.output
        assert_bitwise_equal(outcome.folder / "cases" / f"{case.hash}.h5", tmp_path / f"{case.hash}.h5")
        with h5py.File(tmp_path / f"{case.hash}.h5") as f:
            assert f.attrs["input_sha256"] == case.input_sha256


def test_rerun_skips_complete_cases_and_rebuilds_the_summary(two_jobs):
    outcome, _ = two_jobs
    stamps = {p: p.stat().st_mtime_ns for p in (outcome.folder / "cases").iterdir()}
    (outcome.folder / "summary.csv").unlink()
    again = run_sweep(SMALL, outcome.folder, jobs=2)
    assert again.ran == 0 and again.reused == 8 and again.ok
    assert {p: p.stat().st_mtime_ns for p in (outcome.folder / "cases").iterdir()} == stamps
    assert (outcome.folder / "summary.csv").is_file()
    assert without_times(again.rows) == without_times(outcome.rows)


def test_summary_forms_agree(two_jobs):
    outcome, rows = two_jobs
    schema = sweep_summary_schema()
    for row in outcome.rows:
        jsonschema.validate(row, schema)
    folder = outcome.folder
    header, *lines = (folder / "summary.csv").read_text(encoding="utf-8").splitlines()
    names = list(outcome.rows[0])
    assert header.split(",")[:5] == names[:5] and len(lines) == 8
    with h5py.File(folder / "summary.h5") as f:
        table = f["cases"][()]
        columns = json.loads(f["cases"].attrs["columns"])
        assert [c["name"] for c in columns] == names == list(table.dtype.names)
        assert f["cases"].attrs["units"].split(", ")[names.index("peak_impact_force_N")] == "N"
        assert f.attrs["complete"] == 8 and f.attrs["failed"] == 0
        for row, line in zip(outcome.rows, table):
            assert line["hash"].decode() == row["hash"]
            assert line["peak_isd_y_m[left/C9/2]"] == row["peak_isd_y_m[left/C9/2]"]
            assert line["impacts"] == row["impacts"]
    assert read_summary(folder) == outcome.rows == rebuild_summary(folder)


def test_summary_values_are_the_case_files_datasets(two_jobs):
    """Each row's impacts, peak impact force, energy balance error and peak interstorey
    deflections, against the case file's datasets read directly: the number of rows of
    /impacts/events (none beyond the log's limit here), their largest peak_normal_force,
    max |balance_error| / max |input| of /energy, and /buildings/<B>/peaks — exactly (the same
    doubles, reduced by max)."""
    outcome, _ = two_jobs
    assert any(r["impacts"] for r in outcome.rows), "some case has impacts"
    for row in outcome.rows:
        with h5py.File(outcome.folder / row["file"]) as f:
            events = f["impacts/events"][()]
            assert row["impacts"] == events.shape[0]
            assert row["peak_impact_force_N"] == (events["peak_normal_force"].max() if events.size else 0.0)
            columns = f["energy"].attrs["columns"].split(", ")
            energy = f["energy"][()]
            ratio = np.abs(energy[:, columns.index("balance_error")]).max() / np.abs(energy[:, columns.index("input")]).max()
            assert row["energy_balance_error"] == ratio
            for building in ("left", "right"):
                isd = f[f"buildings/{building}/peaks/interstorey_deflection"][()]
                for k, suffix in enumerate(("x_m", "y_m", "theta_rad")):
                    assert row[f"peak_isd_{suffix}[{building}]"] == np.nanmax(isd[:, :, k])
            names = [n.decode() for n in f["buildings/left/columns"]["name"]]
            c9 = f["buildings/left/peaks/interstorey_deflection"][names.index("C9")]
            assert [row[f"peak_isd_x_m[left/C9/{s}]"] for s in range(1, 5)] == c9[:, 0].tolist()


def test_dry_run_lists_and_writes_nothing(two_jobs, tmp_path):
    fresh = run_sweep(SMALL, tmp_path / "never", jobs=1, dry_run=True)
    assert not (tmp_path / "never").exists()
    assert [r["status"] for r in fresh.rows] == ["pending"] * 8 and fresh.ran == 0
    outcome, _ = two_jobs
    listed = run_sweep(SMALL, outcome.folder, jobs=1, dry_run=True)
    assert [r["status"] for r in listed.rows] == ["complete"] * 8


# --- resuming ------------------------------------------------------------------------------------


def test_missing_corrupt_and_foreign_files_are_rerun(two_jobs, tmp_path):
    outcome, _ = two_jobs
    folder = tmp_path / "copy"
    (folder / "cases").mkdir(parents=True)
    (folder / ".pound-sweep").write_bytes((outcome.folder / ".pound-sweep").read_bytes())  # a sweep's folder
    files = [outcome.folder / r["file"] for r in outcome.rows]
    for f in files[2:]:
        (folder / "cases" / f.name).write_bytes(f.read_bytes())
    (folder / "cases" / files[2].name).write_bytes(files[2].read_bytes()[:5000])  # truncated
    with h5py.File(folder / "cases" / files[3].name, "r+") as f:  # a file of other inputs
        f.attrs["input_sha256"] = "0" * 64
    again = run_sweep(SMALL, folder, jobs=2)
    assert again.ok and again.reused == 4 and again.ran == 4
    for f in files:
        assert_bitwise_equal(f, folder / "cases" / f.name)


def test_kill_9_mid_sweep_loses_no_completed_case(tmp_path):
    """A real `pound sweep` killed with SIGKILL (the process group: workers too) as soon as
    its first cases are done: every final-named file is complete, and the rerun completes
    the rest, running each case once."""
    sweep = write_sweep(tmp_path, 'set = { "analysis.integrator" = "cdm", "analysis.duration" = 12.0 }\n'
                        'parameters = { "excitation.angle" = [0, 15, 30, 45, 60, 75, 90, 105] }\n')  # fmt: skip
    out = tmp_path / "out"
    sweep_then_kill(sweep, out, 2)
    plan = plan_sweep(sweep)
    done = sorted(p.name for p in (out / "cases").glob("*.h5"))
    assert 2 <= len(done) < 8, done
    folder = OutputFolder(out)
    for case in plan.cases:
        if (out / "cases" / f"{case.hash}.h5").exists():
            assert folder.state(case.hash, case.input_sha256).complete, f"{case.hash}.h5 is incomplete"
    again = run_sweep(sweep, out, jobs=2)
    assert again.ok and again.reused == len(done) and again.ran == 8 - len(done)
    assert sorted(p.name for p in (out / "cases").iterdir()) == sorted(f"{c.hash}.h5" for c in plan.cases)


def test_temporaries_of_a_killed_sweep_are_removed_on_rerun(tmp_path):
    """Temporary case files (``.<hash>.h5.<pid>.tmp``, ``.<hash>.failed.json.<pid>.tmp``) of a
    process killed with SIGKILL are deleted by the next sweep into the folder, which says so;
    one of a process still running (another sweep's worker writing) is left alone."""
    sweep = write_sweep(tmp_path, 'set = { "analysis.duration" = 1.0 }\nparameters = { "excitation.angle" = [0] }\n')
    out = tmp_path / "out"
    assert run_sweep(sweep, out, jobs=1).ok
    killed = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    killed.kill()
    killed.wait(timeout=30)
    h = plan_sweep(sweep).cases[0].hash
    stale = [out / "cases" / f".{h}.h5.{killed.pid}.tmp", out / "cases" / f".{h}.failed.json.{killed.pid}.tmp"]
    alive = out / "cases" / f".{h}.h5.{os.getpid()}.tmp"
    for path in (*stale, alive):
        path.write_bytes(b"half a file")
    said = []
    again = run_sweep(sweep, out, jobs=1, log=said.append)
    assert again.ok and again.ran == 0
    assert not any(p.exists() for p in stale) and alive.exists()
    assert "removed 2 temporary files left by an interrupted sweep" in said
    assert sorted(p.name for p in (out / "cases").iterdir()) == sorted([f"{h}.h5", alive.name])


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_interrupted_sweep_writes_its_summary_and_exits_1(sig, tmp_path):
    """Ctrl-C or SIGTERM to the sweep process: the workers stop, the summary is rebuilt with the
    cases done so far (the others pending), exit 1, and the rerun completes the rest."""
    sweep = write_sweep(tmp_path, 'set = { "analysis.integrator" = "cdm", "analysis.duration" = 12.0 }\n'
                        'parameters = { "excitation.angle" = [0, 20, 40, 60, 80, 100] }\n')  # fmt: skip
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "pounding_cli", "sweep", str(sweep), "-o", str(out), "--jobs", "2"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None and not list((out / "cases").glob("*.h5")):
        time.sleep(0.02)
    assert proc.poll() is None, "the sweep ended before it could be interrupted"
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 1, stderr
    assert "interrupted; rerun the same command to go on" in stderr and "Traceback" not in stderr
    rows = read_summary(out)
    assert (out / "summary.csv").is_file() and "pending" in {r["status"] for r in rows}
    assert all(r["status"] in ("complete", "pending") for r in rows)
    assert run_sweep(sweep, out, jobs=2).ok


# --- failures ----------------------------------------------------------------------------------


def test_a_failing_case_stops_nothing_and_exits_1(tmp_path):
    """Δt = 4 ms is below the structural stability limit (checked) but ten times the contact's
    (2/ω_contact = 0.43 ms; found while running): that case fails, with partial results; the
    other, at 0.2 ms within both limits, runs."""
    sweep = write_sweep(tmp_path, 'set = { "analysis.integrator" = "cdm", "analysis.duration" = 20.0, '
                        '"buildings.right.origin[0]" = 8.02 }\nparameters = { "analysis.dt" = [0.0002, 0.004] }\n')  # fmt: skip
    out = tmp_path / "out"
    result = runner.invoke(app, ["sweep", str(sweep), "-o", str(out), "--jobs", "2", "--json"])
    assert result.exit_code == 1, result.output
    rows = [json.loads(line) for line in result.stdout.splitlines()]
    status = {r["analysis.dt"]: r["status"] for r in rows}
    assert status[0.0002] == "complete" and status[0.004].startswith("failed: unstable")
    assert "1 failed" in result.stderr and status[0.004] in result.stderr
    failed = next(r for r in rows if r["analysis.dt"] == 0.004)
    assert (out / failed["file"]).exists() and failed["impacts"] is not None, "partial results are kept"
    again = run_sweep(sweep, out, jobs=1)
    assert again.reused == 1 and again.ran == 1 and not again.ok, "a failed case is run again"


def test_progress_bar_counts_done_and_failed_with_an_eta(tmp_path, monkeypatch):
    """`pound sweep --progress` on a terminal (a rich console forced to be one): the bar of
    the checks and the bar of the runs, each with done/total, failed and the time left; the
    run bar ends at 2/2 with the one failing case counted."""
    import io

    from rich.console import Console

    import pounding_cli.cli as cli

    screen = io.StringIO()
    monkeypatch.setattr(cli, "err", Console(file=screen, force_terminal=True, width=160, highlight=False,
                                            soft_wrap=True, color_system=None))  # fmt: skip
    sweep = write_sweep(tmp_path, 'set = { "analysis.integrator" = "cdm", "analysis.duration" = 20.0, '
                        '"buildings.right.origin[0]" = 8.02 }\nparameters = { "analysis.dt" = [0.0002, 0.004] }\n')  # fmt: skip
    result = runner.invoke(app, ["sweep", str(sweep), "-o", str(tmp_path / "out"), "--jobs", "2", "--progress"])
    assert result.exit_code == 1, result.output
    text = screen.getvalue()
    final = text.rsplit("\r", 1)[-1]  # the bars as last drawn
    assert re.search(r"checking cases .*2/2 0 failed .*ETA", final), final
    assert re.search(r"running cases +\S+ 2/2 1 failed \d+:\d\d:\d\d ETA \d+:\d\d:\d\d", final), final
    assert "2 cases: 1 complete (0 already were), 1 failed" in text


def test_a_dead_worker_fails_only_its_task():
    tasks = [(0, pow, (2, 10)), (1, os._exit, (3,)), (2, pow, (3, 2)), (3, os.abort, ()), (4, pow, (5, 2))]
    with LocalPool(2) as pool:
        outcomes = {key: (ok, value) for key, ok, value in pool.run(tasks)}
    assert outcomes[0] == (True, 1024) and outcomes[2] == (True, 9) and outcomes[4] == (True, 25)
    assert outcomes[1] == (False, "the worker process running this case died (exit code 3)")
    assert outcomes[3][0] is False and "SIGABRT" in outcomes[3][1]


def test_pool_workers_run_with_one_thread():
    before = {k: os.environ.get(k) for k in ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS")}
    with LocalPool(1) as pool:
        outcomes = sorted(pool.run([(k, os.getenv, (k,)) for k in before]))
    assert outcomes == [("NUMBA_NUM_THREADS", True, "1"), ("OMP_NUM_THREADS", True, "1")]
    assert {k: os.environ.get(k) for k in before} == before, "the parent's environment is left as it was"


def test_a_task_that_cannot_be_sent_fails_alone():
    with LocalPool(1) as pool:
        outcomes = sorted(pool.run([(0, pow, (2, 3)), (1, pow, (lambda: 0, 2)), (2, pow, (3, 3))]))
    assert outcomes[0] == (0, True, 8) and outcomes[2] == (2, True, 27)
    assert outcomes[1][1] is False and "cannot be sent to a worker" in outcomes[1][2]


def test_a_second_sweep_into_a_busy_folder_is_refused(tmp_path):
    folder = OutputFolder(tmp_path / "busy")
    folder.prepare()
    with folder.locked():
        with pytest.raises(InputError, match="another pound sweep is writing into this folder"):
            run_sweep(SMALL, folder.root, jobs=1)


# --- Dask ------------------------------------------------------------------------------------------


def _square(x):
    return x * x


def test_dask_executor_keeps_at_most_twice_the_worker_threads_of_tasks_untaken():
    """A worker holds a finished task's result until it is taken; a district's groups return
    a hundred buildings' histories each. DaskExecutor.run submits at most 2 × the cluster's
    threads ahead of what it has yielded, so the results waiting never exceed that (+ the
    one being taken), and still yields every outcome once."""
    distributed = pytest.importorskip("distributed")
    from pounding_cli.sweep.cluster import DaskExecutor

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            held, seen = [], {}
            for key, ok, value in DaskExecutor(client).run([(k, _square, (k,)) for k in range(20)]):
                held.append(len(client.who_has()))
                seen[key] = (ok, value)
    assert seen == {k: (True, k * k) for k in range(20)}
    assert max(held) <= 2 * 2 + 1, held


def test_dask_cluster_gives_the_same_results(two_jobs, tmp_path):
    distributed = pytest.importorskip("distributed")
    outcome, _ = two_jobs
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = run_sweep(SMALL, tmp_path / "dask", client=client)
        result = runner.invoke(app, ["sweep", str(SMALL), "-o", str(tmp_path / "cli"), "--scheduler",
                                     cluster.scheduler_address, "--json"])  # fmt: skip
    assert remote.ok and without_times(remote.rows) == without_times(outcome.rows)
    for row in outcome.rows:
        assert_bitwise_equal(outcome.folder / row["file"], tmp_path / "dask" / row["file"])
    assert result.exit_code == 0, result.output
    assert len(result.stdout.splitlines()) == 8 and "Dask cluster" in result.stderr


def test_dask_worker_processes_give_the_same_results(two_jobs, tmp_path):
    """A LocalCluster of two worker processes (each its own interpreter under a nanny, as on
    a real cluster, unlike processes=False's threads): the same rows and case files, bit for
    bit."""
    distributed = pytest.importorskip("distributed")
    outcome, _ = two_jobs
    try:
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None, silence_logs=50)  # fmt: skip
    except (OSError, TimeoutError, RuntimeError) as exc:
        pytest.skip(f"cannot start a local Dask cluster of processes here: {exc}")
    with cluster, distributed.Client(cluster) as client:
        client.wait_for_workers(2, timeout=120)
        assert len(set(client.run(os.getpid).values()) - {os.getpid()}) == 2, "two processes, not this one"
        remote = run_sweep(SMALL, tmp_path / "dask", client=client)
    assert remote.ok and without_times(remote.rows) == without_times(outcome.rows)
    for row in outcome.rows:
        assert_bitwise_equal(outcome.folder / row["file"], tmp_path / "dask" / row["file"])


@pytest.fixture
def scheduler_file(tmp_path):
    """A Dask scheduler and two one-thread workers started as `dask scheduler` and `dask worker`
    would be on a cluster, meeting through a scheduler file; stopped (process groups) after.
    Every wait is bounded; the test is skipped if they cannot start (no free port, say)."""
    pytest.importorskip("distributed")
    path = tmp_path / "scheduler.json"
    started = []

    def start(module, *args):
        proc = subprocess.Popen([sys.executable, "-m", f"distributed.cli.{module}", *args], stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True, start_new_session=True)  # fmt: skip
        started.append(proc)
        return proc

    try:
        scheduler = start("dask_scheduler", "--scheduler-file", str(path), "--host", "127.0.0.1", "--port", "0",
                          "--no-dashboard", "--idle-timeout", "300s")  # fmt: skip
        deadline = time.monotonic() + 60
        while not path.exists() and scheduler.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        if not path.exists():
            pytest.skip(f"the Dask scheduler did not start: {scheduler.stderr.read() if scheduler.poll() is not None else 'timed out'}")
        start("dask_worker", "--scheduler-file", str(path), "--nworkers", "2", "--nthreads", "1", "--no-dashboard",
              "--death-timeout", "60")  # fmt: skip
        import distributed

        with distributed.Client(scheduler_file=str(path), timeout=30) as client:
            try:
                client.wait_for_workers(2, timeout=120)
            except TimeoutError:
                pytest.skip("the Dask workers did not join the scheduler within 120 s")
        yield path
    finally:
        for proc in reversed(started):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=30)


def test_scheduler_file_sweep_gives_the_same_results(two_jobs, scheduler_file, tmp_path):
    """`pound sweep --scheduler-file` against a scheduler and workers started from the command
    line: exit 0, the same rows (--json and the summary) and case files as the local run."""
    outcome, _ = two_jobs
    out = tmp_path / "cluster"
    result = runner.invoke(app, ["sweep", str(SMALL), "-o", str(out), "--scheduler-file", str(scheduler_file), "--json"])
    assert result.exit_code == 0, result.output
    assert "on the Dask cluster at tcp://127.0.0.1:" in result.stderr and "(2 worker threads)" in result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]  # in the order the cases finished
    assert sorted(map(json.dumps, without_times(lines))) == sorted(map(json.dumps, without_times(outcome.rows)))
    assert without_times(read_summary(out)) == without_times(outcome.rows)
    for row in outcome.rows:
        assert_bitwise_equal(outcome.folder / row["file"], out / row["file"])


def test_dask_workers_get_absolute_paths(tmp_path, monkeypatch):
    """A Dask worker's current folder is not the submitter's: with relative sweep and output
    paths, every path a task carries is absolute."""
    import pounding_cli.sweep.cluster as cluster

    class Recording:
        description = "a recording stand-in for a Dask cluster"

        def __init__(self, client):
            self.paths = []

        def run(self, tasks):
            for key, function, args in tasks:
                self.paths += [a for a in args if isinstance(a, str) and a.endswith((".toml", ".h5", ".json"))]
                yield key, True, function(*args)

        def close(self):
            recorded.extend(self.paths)

    recorded: list[str] = []
    monkeypatch.setattr(cluster, "DaskExecutor", Recording)
    monkeypatch.chdir(SMALL.parent)
    outcome = run_sweep(SMALL.name, os.path.relpath(tmp_path / "out"), client=object())
    assert outcome.ok
    assert recorded and all(Path(p).is_absolute() for p in recorded), recorded


# --- the CLI ----------------------------------------------------------------------------------------


def test_cli_json_lines_are_summary_rows(two_jobs):
    outcome, _ = two_jobs
    result = runner.invoke(app, ["sweep", str(SMALL), "-o", str(outcome.folder), "--json", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in result.stdout.splitlines()]
    assert without_times(rows) == without_times(outcome.rows), "complete cases are printed too"
    assert "8 complete (8 already were)" in result.stderr


def test_cli_dry_run_lists_cases(tmp_path):
    result = runner.invoke(app, ["sweep", str(SMALL), "-o", str(tmp_path / "x"), "--dry-run", "--jobs", "1"],
                           env={"COLUMNS": "200"})  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "8 cases (8 distinct runs)" in result.stdout and result.stdout.count("pending") == 8
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--study", "6.1"], "--study: no study '6.1' in"),
        (["--jobs", "0"], "--jobs: expected a number of processes ≥ 1, got 0"),
        (["--jobs", "2", "--scheduler", "tcp://127.0.0.1:1"], "--jobs: applies to local runs only"),
        (["--scheduler", "tcp://a:1", "--scheduler-file", "s.json"], "--scheduler and --scheduler-file: give one of them"),
        (["--scheduler-file", "no-such-scheduler.json"], "no-such-scheduler.json: --scheduler-file: no such file"),
    ],
)
def test_cli_usage_errors(args, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["sweep", str(SMALL), *args])
    assert result.exit_code == 2, result.output
    assert message in result.stderr and result.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_default_output_folder_is_the_sweep_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sweep = write_sweep(tmp_path, 'set = { "analysis.duration" = 1.0 }\nparameters = { "excitation.angle" = [0] }\n',
                        name="tiny.sweep.toml")  # fmt: skip
    result = runner.invoke(app, ["sweep", str(sweep), "--jobs", "1"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "tiny" / "summary.csv").is_file() and (tmp_path / "tiny" / "sweep.json").is_file()


def test_study_option_runs_only_that_study(tmp_path):
    sweep = write_sweep(tmp_path, 'set = { "analysis.duration" = 1.0 }\n[studies.a]\nparameters = { "excitation.angle" = [0, 10] }\n'
                        '[studies.b]\nparameters = { "excitation.scale" = [2.0] }\n')  # fmt: skip
    outcome = run_sweep(sweep, tmp_path / "out", jobs=1, studies=["b"])
    assert outcome.ok and outcome.ran == 1
    assert [r["status"] for r in outcome.rows] == ["pending", "pending", "complete"]
    assert [r["study"] for r in outcome.rows] == ["a", "a", "b"]


# --- the paper's studies --------------------------------------------------------------------------


def test_paper_studies_sweep_checks(tmp_path):
    if not SHARED.exists():
        pytest.skip("the Kobe record is kept in ../shared, which is absent")
    plan = plan_sweep(INPUTS / "paper_studies.sweep.toml")
    assert len(plan.cases) == 81 and len(plan.runs()) == 79
    by_label = {c.spec.label: c for c in plan.cases}
    assert by_label["6.2/X only: L along x only"].hash == by_label["6.1/case 1: no eccentricity, pounding"].hash
    assert by_label["6.2/X+Y: both components: L along x, T along y"].hash == by_label["6.3/excitation.angle=0"].hash
    assert by_label["6.1/case 3: e_y = +0.4 m left, −0.4 m right, pounding"].values[
        "buildings.right.floors[*].eccentricity"] == [0.0, -0.4]  # fmt: skip
    assert read_document(INPUTS / "paper_kobe.toml")["excitation"]["angle"] == 0.0
