"""Faults while writing: a full disk, and SIGTERM at every instant of a run.

Disk full: HDF5 writes through pounding_cli.atomic.DiskSink, which never fails a write to
the C library (after a failed one, libhdf5 segfaulted on closing the file and printed a
traceback for every object it freed) and raises the OSError once the file is closed. Every
writer then reports exit 2 "cannot write the file (No space left on device)", one line,
with nothing left behind: `pound run` (also with --force over an older file, which stays),
a sweep's workers (the sweep stops at the first case it cannot write) and its summary.
Tested on a real 1 MiB tmpfs where the machine lets the test mount one (root), else
skipped; and by a simulated ENOSPC at every write of the file, in-process.

SIGTERM: at every instant of `pound run`, the outcome is exit 1 with nothing written (or,
once the time loop runs, its partial results marked "failed: interrupted"), or — once the
result file has its final name — death by the signal with that complete file. Never exit 0:
the signal is never swallowed.
"""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.model import read_document

from conftest import INPUTS

runner = CliRunner()


def model_file(folder: Path, duration: float = 0.5, **analysis) -> Path:
    doc = read_document(INPUTS / "paper_wide_gap.toml")
    doc["analysis"].update(duration=duration, **analysis)
    path = folder / "m.json"
    path.write_text(json.dumps(doc))
    if not (folder / "records").exists():
        (folder / "records").symlink_to(INPUTS / "records")
    return path


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*") if p.name.endswith((".tmp", ".claim")))


# --- a real full disk ------------------------------------------------------------------------


@pytest.fixture
def small_disk(tmp_path: Path):
    """A 1 MiB tmpfs mounted at tmp_path/disk, or skip where mounting is not allowed."""
    disk = tmp_path / "disk"
    disk.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(disk)], capture_output=True)
    if done.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here ({done.stderr.decode().strip() or done.returncode})")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


def fill(disk: Path, leave: int) -> None:
    """Fill the disk but `leave` bytes (about: tmpfs counts in pages)."""
    for p in disk.iterdir():
        p.unlink()
    free = os.statvfs(disk).f_bavail * os.statvfs(disk).f_frsize
    if free > leave:
        (disk / "junk").write_bytes(b"\0" * (free - leave))


def pound(*args: str, cwd: Path, **env: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pounding_cli", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=300, env={**os.environ, **env})  # fmt: skip


@pytest.mark.parametrize("leave", [150_000, 40_000, 4096, 0])
def test_run_into_a_full_disk(small_disk: Path, tmp_path: Path, leave: int) -> None:
    """The result file (190 kB) does not fit in what is left: exit 2, one line, no
    traceback, no segfault (it was exit 139 with a page of HDF5 tracebacks), nothing left."""
    model = model_file(tmp_path, duration=2.0)
    fill(small_disk, leave)
    done = pound("run", model, "-o", small_disk / "out.h5", "--no-progress", cwd=tmp_path)
    assert done.returncode == 2, (done.returncode, done.stderr[-2000:])
    assert done.stderr == (f"{small_disk / 'out.h5'}: cannot write the file (No space left on device); the analysis "
                           "ran (complete) but its results were not written: make room or give another output file, "
                           "and run again\n")  # fmt: skip
    assert sorted(p.name for p in small_disk.iterdir()) == (["junk"] if leave < 900_000 else [])


def test_run_with_force_over_an_older_file_on_a_full_disk(small_disk: Path, tmp_path: Path) -> None:
    model = model_file(tmp_path, duration=2.0)
    fill(small_disk, 200_000)
    older = small_disk / "out.h5"
    older.write_bytes(b"an older result" * 1000)
    done = pound("run", model, "-o", older, "--no-progress", "--force", cwd=tmp_path)
    assert done.returncode == 2 and "cannot write the file (No space left on device)" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr and len(done.stderr.splitlines()) == 1
    assert older.read_bytes() == b"an older result" * 1000
    assert leftovers(small_disk) == []


def test_sweep_into_a_full_disk(small_disk: Path, tmp_path: Path) -> None:
    """A sweep's workers cannot write their cases: the sweep stops at the first, exit 2."""
    model_file(tmp_path, duration=2.0)
    (tmp_path / "s.sweep.toml").write_text('base = "m.json"\nparameters = { "excitation.angle" = [0.0, 45.0, 90.0] }\n')
    fill(small_disk, 100_000)
    done = pound("sweep", "s.sweep.toml", "-o", small_disk / "sweep", "--jobs", "1", cwd=tmp_path)
    assert done.returncode == 2, done.stderr[-2000:]
    assert "cannot write the file (No space left on device)" in done.stderr.splitlines()[-1], done.stderr
    assert "Traceback" not in done.stderr
    assert leftovers(small_disk) == []


def test_run_in_groups_into_a_full_disk(small_disk: Path, tmp_path: Path) -> None:
    """`pound run --jobs 1` of three independent groups, each written into the file as it
    ends (results/grouped_file.py), on a disk with room for part of it: exit 2 "cannot write
    the file", nothing left on the disk."""
    import tomli_w

    from pounding_cli.city.block import Block, city_document, district_buildings

    doc = city_document(district_buildings(Block(rows=2, cols=2), 3, 1), "three blocks",
                        record_dir=str(Path(__file__).resolve().parents[1] / "inputs" / "records"), duration=4.0)  # fmt: skip
    model = tmp_path / "blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    fill(small_disk, 300_000)
    done = pound("run", model, "-o", small_disk / "out.h5", "--no-progress", "--jobs", "1", cwd=tmp_path)
    assert done.returncode == 2, done.stderr[-2000:]
    assert f"{small_disk / 'out.h5'}: cannot write the file (No space left on device)" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    assert leftovers(small_disk) == []


# --- a simulated full disk, at every write ------------------------------------------------


def _count_writes(tmp_path: Path) -> int:
    """How many writes the sink makes for the test model's result file."""
    from pounding_cli import atomic

    model = model_file(tmp_path)
    calls = []
    real = os.pwrite

    def counting(fd, data, offset):
        calls.append(len(data))
        return real(fd, data, offset)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(atomic.os, "pwrite", counting)
        assert runner.invoke(app, ["run", str(model), "-o", str(tmp_path / "count.h5"), "--no-progress"]).exit_code == 0
    return len(calls)


def test_enospc_at_every_write_of_a_result_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The disk fills up at the k-th write, for every k, with an older file to be replaced:
    exit 2 "cannot write the file", the older file untouched, no temporary file left."""
    from pounding_cli import atomic

    n = _count_writes(tmp_path)
    assert n >= 5
    model = tmp_path / "m.json"
    out = tmp_path / "out.h5"
    out.write_bytes(b"older")
    real = os.pwrite
    for k in range(n):
        calls = []

        def failing(fd, data, offset, k=k):
            calls.append(1)
            if len(calls) > k:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return real(fd, data, offset)

        monkeypatch.setattr(atomic.os, "pwrite", failing)
        result = runner.invoke(app, ["run", str(model), "-o", str(out), "--no-progress", "--force"])
        assert result.exit_code == 2, (k, result.stderr, result.exception)
        assert f"{out}: cannot write the file (No space left on device)" in result.stderr, (k, result.stderr)
        assert out.read_bytes() == b"older" and leftovers(tmp_path) == [], k


@pytest.mark.parametrize("where", ["fsync", "replace"])
def test_enospc_when_the_file_is_flushed_or_renamed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, where: str) -> None:
    from pounding_cli import atomic

    model = model_file(tmp_path)
    out = tmp_path / "out.h5"
    real = getattr(atomic.os, where)

    def failing(*args, **kwargs):
        if where == "replace" or (args and isinstance(args[0], int) and not os.path.isdir(f"/proc/self/fd/{args[0]}")):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(*args, **kwargs)

    monkeypatch.setattr(atomic.os, where, failing)
    result = runner.invoke(app, ["run", str(model), "-o", str(out), "--no-progress"])
    assert result.exit_code == 2 and "cannot write the file (No space left on device)" in result.stderr, result.stderr
    assert not out.exists() and leftovers(tmp_path) == []


def test_enospc_in_a_sweep_worker_stops_the_sweep(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from pounding_cli import atomic
    from test_fuzz import InProcess

    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    model_file(tmp_path)
    sweep = tmp_path / "s.sweep.toml"
    sweep.write_text('base = "m.json"\nparameters = { "excitation.angle" = [0.0, 90.0] }\n')
    real = os.pwrite

    def failing(fd, data, offset):
        if os.readlink(f"/proc/self/fd/{fd}").endswith(".h5.%d.tmp" % os.getpid()) and "/cases/" in os.readlink(f"/proc/self/fd/{fd}"):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(fd, data, offset)

    monkeypatch.setattr(atomic.os, "pwrite", failing)
    result = runner.invoke(app, ["sweep", str(sweep), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, (result.stderr, result.exception)
    assert "cannot write the file (No space left on device)" in result.stderr.splitlines()[-1]
    assert leftovers(tmp_path / "out") == [] and list((tmp_path / "out" / "cases").iterdir()) == []


# --- SIGTERM at every instant ---------------------------------------------------------------

GATED_RUN = """
import atexit, os, sys, time
from pathlib import Path
gate = Path(sys.argv.pop(1))
os.environ["POUND_TEST_STARTED"] = str(gate / "main")
def wait_for_release():
    (gate / "exiting").touch()
    deadline = time.time() + 60
    while not (gate / "release").exists() and time.time() < deadline:
        time.sleep(0.005)
atexit.register(wait_for_release)
from pounding_cli.__main__ import main
main()
"""
"""`pound run` (its entry point) that cannot exit unseen: at exit it touches "exiting" and
waits for "release", so a test that sees no "exiting" before it signals knows the process
was alive then (a signal sent to a process that has already exited would be lost, not
swallowed); pound touches "main" once it has taken SIGTERM over (POUND_TEST_STARTED)."""


def _trial(folder: Path, model: Path, anchor: str, delay: float) -> tuple[int, str, str | None, bool, bool]:
    """Run; once `anchor` is reached ("start": the process started, "tmp": its result file
    is being written, "final": it has its final name), wait `delay` s and send SIGTERM;
    release. (exit code, stderr, final file status, whether pound had taken SIGTERM over,
    whether the file was being written at the signal); status "skip" if the run ended first."""
    name = f"{anchor}{delay:.3f}"
    gate = folder / f"gate-{name}"
    gate.mkdir()
    out = folder / f"out-{name}.h5"
    env = {**os.environ, "POUND_TEST_SLOW_WRITES": "0.02"}
    proc = subprocess.Popen([sys.executable, "-c", GATED_RUN, str(gate), "run", str(model), "-o", str(out),
                             "--no-progress"], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, env=env, text=True)  # fmt: skip
    reached = {"start": lambda: True, "final": out.exists,
               "tmp": lambda: any(p.name.startswith(f".{out.name}.") and p.name.endswith(".tmp") for p in folder.iterdir())}
    deadline = time.time() + 300
    while not reached[anchor]() and not (gate / "exiting").exists() and time.time() < deadline:
        time.sleep(0.002)
    time.sleep(delay)
    if (gate / "exiting").exists():  # finished before the signal: nothing to learn
        (gate / "release").touch()
        proc.communicate(timeout=60)
        return 0, "", "skip", True, False
    started = (gate / "main").exists()
    writing = reached["tmp"]()
    proc.send_signal(signal.SIGTERM)
    (gate / "release").touch()
    _, stderr = proc.communicate(timeout=120)
    status = None
    if out.exists():
        with h5py.File(out) as f:
            status = str(f.attrs["status"])
            assert f["energy"].shape[0] == f["time"].shape[0]
    return proc.returncode, stderr, status, started, writing


def _timeline(folder: Path, model: Path) -> tuple[float, tuple[float, float]]:
    """A run never signalled: (seconds to its exit, (start, end) of the file's writing)."""
    gate = folder / "reference"
    gate.mkdir()
    out = folder / "reference.h5"
    env = {**os.environ, "POUND_TEST_SLOW_WRITES": "0.02"}
    t0 = time.time()
    proc = subprocess.Popen([sys.executable, "-c", GATED_RUN, str(gate), "run", str(model), "-o", str(out),
                             "--no-progress"], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, env=env, text=True)  # fmt: skip
    start = end = None
    while not (gate / "exiting").exists() and time.time() - t0 < 300:
        now = time.time() - t0
        if start is None and any(p.name.startswith(".reference.h5.") for p in folder.iterdir()):
            start = now
        if end is None and out.exists():
            end = now
        time.sleep(0.005)
    total = time.time() - t0
    (gate / "release").touch()
    proc.communicate(timeout=60)
    assert proc.returncode == 0 and start is not None and end is not None, (proc.returncode, start, end)
    out.unlink()
    return total, (start, end)


@pytest.mark.slow
def test_sigterm_at_every_instant(tmp_path: Path) -> None:
    """Instants spread over a whole run (imports, checks, time loop, writing, printing) and
    dense while the file is written (each write slowed by 20 ms, so that it spans ~1 s)."""
    model = model_file(tmp_path, duration=3.0)
    total, writing = _timeline(tmp_path, model)
    start, end = writing
    instants = ([("start", total * k / 16) for k in range(1, 13)] + [("tmp", (end - start) * k / 8) for k in range(9)]
                + [("final", delay) for delay in (0.0, 0.002, 0.01, 0.05, 0.2)])  # fmt: skip
    outcomes = []
    for anchor, delay in instants:
        code, stderr, status, started, writing = _trial(tmp_path, model, anchor, delay)
        if status == "skip":
            continue
        outcomes.append((f"{anchor}+{delay:.2f}", code, status, writing))
        assert "Traceback" not in stderr, stderr
        if code == 1:
            assert status in (None, "failed: interrupted"), (delay, status, stderr)
            assert "interrupted" in stderr, stderr
        elif code == -signal.SIGTERM:
            assert status == "complete" or (status is None and not started), (delay, status, stderr)
        else:
            pytest.fail(f"exit {code} after SIGTERM at {delay:.2f} s (status {status}): {stderr}")
    print("SIGTERM outcomes (delay s, exit code, file status, while writing):", outcomes)
    assert leftovers(tmp_path) == []
    assert len(outcomes) >= 15, outcomes
    assert any(w for *_, w in outcomes), f"no instant fell while the file was written: {outcomes}"
    assert any(status == "complete" for _, _, status, _ in outcomes), f"no instant fell after the rename: {outcomes}"
