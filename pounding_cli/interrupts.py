"""Stopping a run or a sweep on request: SIGTERM (a batch system's stop) and SIGINT (Ctrl-C).

Python delivers a signal by running its handler between bytecodes of the main thread; a
KeyboardInterrupt raised there can land inside a finaliser or weakref callback, where the
interpreter would print "Exception ignored … Traceback" and carry on. So the handler also
records the request, the loops that must stop (the time loop's chunks, a sweep's cases) call
:func:`stop_if_requested` where stopping is safe, and within the block such a swallowed
interrupt is not printed (sys.unraisablehook): the request it carried is kept.
"""

from __future__ import annotations

import signal
import sys
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
            self.hook = sys.unraisablehook
            sys.unraisablehook = _quiet_about_interrupts(self.hook)
        return self

    def __exit__(self, *exc: object) -> None:
        global _depth, _requested
        if self.previous:
            for sig, handler in self.previous.items():
                signal.signal(sig, handler)
            sys.unraisablehook = self.hook
            _depth -= 1
            if _depth == 0:
                _requested = False


def _quiet_about_interrupts(hook):  # type: ignore[no-untyped-def]
    """An unraisable-exception hook that passes over our Interrupted (recorded in _requested,
    raised again by stop_if_requested) and hands anything else to `hook`."""

    def quiet(unraisable) -> None:  # type: ignore[no-untyped-def]
        if not isinstance(unraisable.exc_value, Interrupted):
            hook(unraisable)

    return quiet


def _interrupt(signum: int, frame: object) -> None:
    global _requested
    _requested = True
    raise Interrupted


def stop_if_requested() -> None:
    """Raise KeyboardInterrupt if a stop was requested in the current block, even one whose
    first KeyboardInterrupt the interpreter swallowed."""
    if _requested:
        raise Interrupted
