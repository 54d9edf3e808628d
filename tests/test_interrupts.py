"""Killing a real `pound run` at random moments never leaves a final-named file that is
incomplete; SIGTERM (like Ctrl-C) leaves the partial results marked "failed: interrupted"."""

from __future__ import annotations

import random
import signal
import subprocess
import sys
import time

import h5py
import pytest

from conftest import INPUTS

MODEL = INPUTS / "paper_pounding.toml"


ANNOUNCING_RUN = """
import contextlib, sys
from pathlib import Path
import pounding_cli.cli as cli
marker = Path(sys.argv.pop(1))
@contextlib.contextmanager
def announcing_bar(show):
    def update(done, total):
        if done > 0:
            marker.touch()
    yield update
cli._progress_bar = announcing_bar
cli.main()
"""
"""`pound run` that touches a marker file once the time loop reports progress, so that a test
can signal it mid-loop however long the imports and the kernel loading take."""


def _start(tmp_path, out, marker=None):
    # the CDM at every step makes the run long enough (~2 s of solver) to be hit mid-way
    model = tmp_path / "slow.toml"
    model.write_text(MODEL.read_text().replace('dt = "auto"', 'dt = "auto"\nintegrator = "cdm"'))
    (tmp_path / "records").symlink_to(INPUTS / "records")
    command = ["-m", "pounding_cli"] if marker is None else ["-c", ANNOUNCING_RUN, str(marker)]
    return subprocess.Popen([sys.executable, *command, "run", str(model), "-o", str(out), "--no-progress"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)  # fmt: skip


def _check_final_file(out):
    """A file with the final name must be whole: it opens, and says complete or failed."""
    if not out.exists():
        return None
    with h5py.File(out, "r") as f:
        status = str(f.attrs["status"])
        n = f["time"].shape[0]
        assert f["energy"].shape[0] == n and f["buildings/left/displacement"].shape[0] == n
    return status


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_killed_run_never_leaves_an_incomplete_file(tmp_path, seed, sig):
    out = tmp_path / "out.h5"
    process = _start(tmp_path, out)
    time.sleep(random.Random(seed).uniform(0.3, 4.0))
    process.send_signal(sig)
    _, stderr = process.communicate(timeout=120)
    status = _check_final_file(out)
    code = process.returncode
    if sig == signal.SIGKILL:
        assert code in (0, -signal.SIGKILL)
        assert status in (None, "complete") if code != 0 else status == "complete"
    else:
        # before the time loop the default handler ends the process; during it, the run stops
        # and writes what it has; after it, the run completes — and a signal that arrives once
        # the complete file has its final name, as the interpreter shuts down, ends the process
        # with the default handler but leaves that file whole
        assert code in (0, 1, -signal.SIGTERM), stderr
        if code == 0:
            assert status == "complete"
        elif code == 1:
            assert status is None or status == "failed: interrupted", (status, stderr)
        else:
            assert status in (None, "complete")
    leftovers = [p.name for p in tmp_path.iterdir() if p.name not in ("out.h5", "slow.toml", "records", "looping")]
    if sig == signal.SIGTERM:
        assert leftovers == [], "no temporary file is left behind"


@pytest.mark.slow
def test_sigterm_during_the_time_loop_writes_marked_partial_results(tmp_path):
    """Once the time loop runs, SIGTERM stops it and the partial results are written."""
    out = tmp_path / "out.h5"
    marker = tmp_path / "looping"
    process = _start(tmp_path, out, marker)
    deadline = time.time() + 120
    while not marker.exists() and process.poll() is None and time.time() < deadline:
        time.sleep(0.01)
    assert marker.exists() or process.poll() is not None, "the time loop did not start within 120 s"
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=max(1, deadline - time.time()))
    if process.returncode == 0:
        pytest.skip("the run finished before the signal (a fast machine)")
    assert process.returncode == 1, stderr
    assert b"failed: interrupted" in stderr
    assert _check_final_file(out) == "failed: interrupted"
    with h5py.File(out) as f:
        assert 0 < f["time"].shape[0] < 2001



def test_a_handled_interrupt_inside_generated_code_still_exits_1(tmp_path):
    """CPython remembers a plain KeyboardInterrupt that passes through exec() of source text
    (numba and dataclasses generate code so) and, under `python -m`, ends the process by
    SIGINT after it was handled: pound's handler raises a subclass, which it does not."""
    (tmp_path / "interrupt_in_exec.py").write_text(
        "import os, signal, sys\n"
        "from pounding_cli.interrupts import terminate_as_interrupt\n"
        "with terminate_as_interrupt():\n"
        "    try:\n"
        "        exec('import os, signal\\nos.kill(os.getpid(), signal.SIGTERM)\\nfor i in range(10**6): pass')\n"
        "    except KeyboardInterrupt:\n"
        "        print('handled')\n"
        "sys.exit(1)\n"
    )
    done = subprocess.run([sys.executable, "-m", "interrupt_in_exec"], cwd=tmp_path, capture_output=True, timeout=60)
    assert done.stdout == b"handled\n", done.stderr
    assert done.returncode == 1


def test_an_interrupt_swallowed_by_a_weakref_callback_is_not_printed_but_kept(monkeypatch):
    """A signal's KeyboardInterrupt that lands in a weakref callback is 'unraisable': CPython
    hands it to sys.unraisablehook, which prints "Exception ignored … Traceback" on stderr,
    and goes on. Within terminate_as_interrupt our interrupt is not passed on to the hook,
    and the request survives for the next stop_if_requested; any other unraisable exception
    still reaches the hook, and the hook is restored on leaving."""
    import gc
    import weakref

    from pounding_cli.interrupts import Interrupted, _interrupt, stop_if_requested, terminate_as_interrupt

    seen = []
    hook = seen.append
    monkeypatch.setattr(sys, "unraisablehook", hook)

    class Thing:
        pass

    def raise_in_callback(_):
        _interrupt(signal.SIGINT, None)  # as if the signal arrived while the callback ran

    def fail_in_callback(_):
        raise ValueError("a real bug")

    with terminate_as_interrupt():
        for callback in (raise_in_callback, fail_in_callback):
            thing = Thing()
            ref = weakref.ref(thing, callback)
            del thing
            gc.collect()
            assert ref() is None
        assert [type(u.exc_value) for u in seen] == [ValueError]
        with pytest.raises(Interrupted):
            stop_if_requested()
    assert sys.unraisablehook is hook
