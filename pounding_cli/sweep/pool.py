"""A pool of local worker processes, one task at a time each, that knows which task a dead
worker was running.

Why not ``concurrent.futures.ProcessPoolExecutor``: when one of its workers dies (killed
for memory, a crash in compiled code), every pending task fails with ``BrokenProcessPool``
and no one can tell which case was to blame. Here each worker has its own pipe, so a death
fails exactly the task it held, and a fresh worker takes its place.

Workers are started with ``spawn`` (no copy of the parent's threads or open files) and an
environment that pins every numeric library to one thread (:data:`ONE_THREAD`), set before
the child imports anything. They ignore Ctrl-C, which is the parent's to handle (it stops
them), and on Linux they die with the parent, so that a sweep killed with ``kill -9`` does
not leave workers computing.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
from collections import deque
from contextlib import contextmanager
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from multiprocessing.reduction import ForkingPickler
from typing import Any, Callable, Iterable, Iterator

ONE_THREAD = {
    "NUMBA_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
}
"""Environment of a worker process: one thread for numba, OpenMP and the BLAS libraries."""

Task = tuple[Any, Callable[..., Any], tuple[Any, ...]]
"""(key, function, arguments)."""

Outcome = tuple[Any, bool, Any]
"""(key, True, returned value) or (key, False, message)."""


def _worker(conn: Connection, parent: int) -> None:
    """A worker's loop: run each (key, function, arguments) received, send back the outcome."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent(parent)
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            return
        if message is None:
            return
        key, function, args = message
        try:
            outcome = (key, True, function(*args))
        except BaseException as exc:  # noqa: BLE001 - reported as the task's failure
            outcome = (key, False, f"{type(exc).__name__}: {exc}")
        try:
            conn.send(outcome)
        except (BrokenPipeError, OSError):
            return


def _die_with_parent(parent: int) -> None:
    """Linux: have the kernel kill this process when its parent dies (prctl PR_SET_PDEATHSIG)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1 = PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)


@dataclass
class _Worker:
    process: multiprocessing.process.BaseProcess
    conn: Connection
    task: Any = None  # key of the task it holds, or None when idle
    busy: bool = False


class LocalPool:
    """`jobs` worker processes, started when first needed and reused for every task."""

    def __init__(self, jobs: int):
        self.jobs = max(1, int(jobs))
        self._context = multiprocessing.get_context("spawn")
        self._workers: list[_Worker] = []

    @property
    def description(self) -> str:
        return f"{self.jobs} local process{'es' if self.jobs > 1 else ''}"

    def run(self, tasks: Iterable[Task]) -> Iterator[Outcome]:
        """Run the tasks, yielding each outcome as it arrives (not in order)."""
        queue = deque(tasks)
        while queue or any(w.busy for w in self._workers):
            while queue and (worker := self._idle_worker()) is not None:
                key, function, args = queue.popleft()
                try:
                    message = ForkingPickler.dumps((key, function, args))
                except Exception as exc:  # noqa: BLE001 - this task's failure only
                    yield key, False, f"the task cannot be sent to a worker: {type(exc).__name__}: {exc}"
                    continue
                worker.task, worker.busy = key, True
                try:
                    worker.conn.send_bytes(message)
                except (BrokenPipeError, OSError):
                    pass  # the worker died: its sentinel reports it below
            busy = [w for w in self._workers if w.busy]
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for worker in busy:
                if worker.conn in ready and worker.conn.poll():
                    try:
                        outcome = worker.conn.recv()
                    except (EOFError, OSError):
                        outcome = None
                    if outcome is not None:
                        worker.task, worker.busy = None, False
                        yield outcome
                        continue
                if worker.process.sentinel in ready or not worker.process.is_alive():
                    key = worker.task
                    self._retire(worker)
                    yield key, False, _death(worker.process)

    def close(self) -> None:
        """Stop every worker: ask the idle ones to leave, terminate those still working."""
        for worker in self._workers:
            try:
                if not worker.busy:
                    worker.conn.send(None)
            except (BrokenPipeError, OSError):
                pass
        for worker in self._workers:
            worker.process.join(timeout=0.5 if not worker.busy else 0)
            if worker.process.is_alive():
                worker.process.terminate()
                worker.process.join(timeout=5)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            worker.conn.close()
        self._workers.clear()

    def __enter__(self) -> "LocalPool":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _idle_worker(self) -> _Worker | None:
        for worker in self._workers:
            if not worker.busy:
                return worker
        if len(self._workers) < self.jobs:
            return self._start()
        return None

    def _start(self) -> _Worker:
        parent_end, child_end = self._context.Pipe()
        process = self._context.Process(target=_worker, args=(child_end, os.getpid()), daemon=True)
        saved = {k: os.environ.get(k) for k in ONE_THREAD}
        os.environ.update(ONE_THREAD)  # inherited by the child as it starts: before any import
        try:
            with _main_module_not_rerun():
                process.start()
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        child_end.close()
        worker = _Worker(process, parent_end)
        self._workers.append(worker)
        return worker

    def _retire(self, worker: _Worker) -> None:
        worker.process.join(timeout=1)
        worker.conn.close()
        self._workers.remove(worker)


@contextmanager
def _main_module_not_rerun() -> Iterator[None]:
    """Start a worker without it running the main module again.

    A spawned process normally re-runs the parent's main script (as ``__mp_main__``) so that
    the parent's functions can be found; a script that calls ``run_sweep`` at its top level,
    without ``if __name__ == "__main__":``, would then start a sweep inside every worker as it
    starts, and the worker dies. pound's workers need nothing of the main module (their tasks
    are pound's own functions, found by their module), so the main module's ``__file__`` and
    ``__spec__``, by which multiprocessing finds it, are hidden while the process starts: a
    plain script works as it is, with or without the guard."""
    main = sys.modules.get("__main__")
    saved = {k: main.__dict__[k] for k in ("__file__", "__spec__") if main is not None and k in main.__dict__}
    if main is not None:
        main.__dict__.pop("__file__", None)
        main.__dict__["__spec__"] = None
    try:
        yield
    finally:
        if main is not None:
            main.__dict__.pop("__spec__", None)
            main.__dict__.update(saved)


def _death(process: multiprocessing.process.BaseProcess) -> str:
    code = process.exitcode
    if code is not None and code < 0:
        try:
            how = f"killed by signal {signal.Signals(-code).name}"
        except ValueError:
            how = f"killed by signal {-code}"
        if -code == signal.SIGKILL:
            how += " (out of memory?)"
    else:
        how = f"exit code {code}"
    return f"the worker process running this case died ({how})"
