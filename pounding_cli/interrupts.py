"""Stopping a run or a sweep on request: SIGTERM (a batch system's stop) and SIGINT (Ctrl-C).

Python delivers a signal by running its handler between bytecodes of the main thread; a
KeyboardInterrupt raised there can land inside a finaliser or weakref callback, where the
interpreter prints "Exception ignored" and carries on. So the handler also records the
request, and the loops that must stop (the time loop's chunks, a sweep's cases) call
:func:`stop_if_requested` where stopping is safe.
"""

from __future__ import annotations

import signal
import threading

_requested = False
_depth = 0


class Interrupted(KeyboardInterrupt):
    """What the handler raises: caught by every ``except KeyboardInterrupt``. A subclass
    because CPython remembers a plain KeyboardInterrupt that passes through an ``exec`` of
    source text (numba and dataclasses generate code that way) and then ends the process by
    SIGINT (exit −2) even after pound has handled it and chosen exit 1; it compares the
    exception's type with KeyboardInterrupt exactly, so a subclass is not remembered."""


class terminate_as_interrupt:
    """Within the block, SIGTERM interrupts like Ctrl-C: the time loop stops between chunks,
    the partial results are written marked "failed: interrupted", and the run exits 1.
    (Only in the main thread, where Python delivers signals.)"""

    def __enter__(self) -> "terminate_as_interrupt":
        global _requested, _depth
        self.previous: dict[int, object] = {}
        if threading.current_thread() is threading.main_thread():
            if _depth == 0:
                _requested = False
            _depth += 1
            for sig in (signal.SIGTERM, signal.SIGINT):
                self.previous[sig] = signal.signal(sig, _interrupt)
        return self

    def __exit__(self, *exc: object) -> None:
        global _depth, _requested
        if self.previous:
            for sig, handler in self.previous.items():
                signal.signal(sig, handler)
            _depth -= 1
            if _depth == 0:
                _requested = False


def _interrupt(signum: int, frame: object) -> None:
    global _requested
    _requested = True
    raise Interrupted


def stop_if_requested() -> None:
    """Raise KeyboardInterrupt if a stop was requested in the current block, even one whose
    first KeyboardInterrupt the interpreter swallowed."""
    if _requested:
        raise Interrupted
