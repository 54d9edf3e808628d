"""Stopping a run or a sweep on request: SIGTERM (a batch system's stop) and SIGINT (Ctrl-C).

Python delivers a signal by running its handler between bytecodes of the main thread; a
KeyboardInterrupt raised there can land inside a finaliser or weakref callback, where the
interpreter would print "Exception ignored … Traceback" and carry on. So the handler also
records the request, the loops that must stop (the time loop's chunks, a sweep's cases) call
:func:`stop_if_requested` where stopping is safe, and within the block such a swallowed
interrupt is not printed (sys.unraisablehook): the request it carried is kept.

While a file is written (:func:`deferred`, which pounding_cli.atomic holds around every
write) the signals are only recorded: an exception raised inside h5py's C callbacks would be
swallowed, and the run would go on to exit 0 as if nothing had happened. The writer calls
:func:`checkpoint` between its parts and once more just before the rename: a recorded
signal then aborts the write (the temporary file removed, nothing written, exit 1). A signal
that arrives after that last checkpoint finds the file renamed, and is acted on as the block
ends. Once a run's result file has its final name (:func:`results_written`), SIGTERM ends
the process by the signal itself, and SIGINT raises :class:`InterruptedAfterWriting`, which
the command line also turns into death by the signal: exit 1 promises that nothing (or
partial results) was written, and a complete file was.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from contextlib import contextmanager
from typing import Iterator

_requested = False
_depth = 0
_pending: int | None = None  # a signal recorded while deferred, not yet acted on
_written = False  # the run's result file has its final name (set within terminate_as_interrupt)


class Interrupted(KeyboardInterrupt):
    """What the handler raises: caught by every ``except KeyboardInterrupt``. A subclass
    because CPython remembers a plain KeyboardInterrupt that passes through an ``exec`` of
    source text (numba and dataclasses generate code that way) and then ends the process by
    SIGINT (exit −2) even after pound has handled it and chosen exit 1; it compares the
    exception's type with KeyboardInterrupt exactly, so a subclass is not remembered."""


class InterruptedAfterWriting(KeyboardInterrupt):
    """SIGINT (Ctrl-C) after the run's result file was renamed into place: the results are
    complete. `signum` is the signal; the command line dies by it (die_by)."""

    def __init__(self, signum: int):
        self.signum = signum
        super().__init__(signum)


class terminate_as_interrupt:
    """Within the block, SIGTERM interrupts like Ctrl-C: the time loop stops between chunks,
    the partial results are written marked "failed: interrupted", and the run exits 1.
    (Only in the main thread, where Python delivers signals.)"""

    def __enter__(self) -> "terminate_as_interrupt":
        global _requested, _depth, _written
        self.previous: dict[int, object] = {}
        if threading.current_thread() is threading.main_thread():
            if _depth == 0 and _requested:  # a stop swallowed while pound loaded (stop_from_the_start)
                _requested = False
                raise Interrupted
            if _depth == 0:
                _requested = _written = False
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
            if _depth == 0:  # _written stays: the command line's handler (stop_from_the_start)
                _requested = False  # sees it until the command sets the signals' default action


def _quiet_about_interrupts(hook):  # type: ignore[no-untyped-def]
    """An unraisable-exception hook that passes over our Interrupted (recorded in _requested,
    raised again by stop_if_requested) and hands anything else to `hook`."""

    def quiet(unraisable) -> None:  # type: ignore[no-untyped-def]
        if not isinstance(unraisable.exc_value, Interrupted):
            hook(unraisable)

    return quiet


def _interrupt(signum: int, frame: object) -> None:
    global _requested
    if _written:
        after_writing(signum)
    _requested = True
    raise Interrupted


def after_writing(signum: int) -> None:
    """Act on a signal that arrived once the run's result file has its final name: SIGTERM
    ends the process by the signal; SIGINT raises InterruptedAfterWriting."""
    if signum == signal.SIGINT:
        raise InterruptedAfterWriting(signum)
    die_by(signum)


_at_death: list = []
"""Cleanups die_by runs before the process ends by a signal (outputs.claim removes its claim
file): the files a process holds only while it runs."""


def at_death(cleanup) -> None:  # type: ignore[no-untyped-def]
    """Run `cleanup()` if the process ends by die_by (until forget_at_death(cleanup))."""
    _at_death.append(cleanup)


def forget_at_death(cleanup) -> None:  # type: ignore[no-untyped-def]
    if cleanup in _at_death:
        _at_death.remove(cleanup)


def die_by(signum: int) -> None:
    """End the process by the signal `signum` (its default action), as a shell expects of a
    process it signalled: exit status 128 + signum, no cleanup to mistake for success (only
    the at_death ones: files held only while the process runs)."""
    for cleanup in reversed(_at_death):
        try:
            cleanup()
        except Exception:  # noqa: BLE001 - dying regardless
            pass
    sys.stdout.flush()
    sys.stderr.flush()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)
    time.sleep(1.0)  # the signal is delivered at once; this is never reached in practice
    os._exit(128 + signum)


def stop_from_the_start() -> None:
    """For the command line, first thing: SIGTERM raises KeyboardInterrupt (Interrupted), as
    Ctrl-C does, so that it ends pound with exit 1 and nothing written, not by the signal's
    default action, which would look the same as a kill after the results were written.
    (Only the main thread, where Python delivers signals.) POUND_TEST_STARTED names a file to
    touch once this is in place, for tests/test_write_faults.py."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _interrupt)
        # an Interrupted raised inside a callback while pound loads (numba's object cache
        # notifies LLVM through ctypes) is swallowed there: not printed, and recorded, so that
        # the command line stops once loaded (__main__: stop_if_requested)
        sys.unraisablehook = _quiet_about_interrupts(sys.unraisablehook)
    marker = os.environ.get("POUND_TEST_STARTED")
    if marker:
        from pathlib import Path

        Path(marker).touch()


def results_written() -> None:
    """The run's result file has its final name: within terminate_as_interrupt, and after it
    until the next one begins, a signal from now on means death by the signal
    (after_writing), not 'interrupted, nothing written' (a SIGTERM in the moment between the
    block's end and the command line's setting the signals' default action was "interrupted",
    exit 1, with a complete file)."""
    global _written
    if _depth:
        _written = True


def _record(signum: int, frame: object) -> None:
    """The handler while a file is written: note the signal, raise nothing."""
    global _pending, _requested
    if _pending is None:
        _pending = signum
    if _depth:
        _requested = True


@contextmanager
def deferred() -> Iterator[None]:
    """Within the block (a file being written), SIGTERM and SIGINT are recorded, not raised;
    checkpoint() raises for a recorded one. A signal still recorded when the block ends
    (it arrived after the last checkpoint: the file was renamed) is handed to the handler
    in place outside the block. Only in the main thread; elsewhere a no-op."""
    global _pending
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    outer = _pending
    _pending = None
    # a signal the process ignores (a sweep's workers ignore Ctrl-C: their parent stops them)
    # stays ignored
    previous = {sig: signal.signal(sig, _record) for sig in (signal.SIGTERM, signal.SIGINT)
                if signal.getsignal(sig) is not signal.SIG_IGN}
    try:
        yield
    finally:
        left, _pending = _pending, outer
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    if left is not None and outer is None:
        signal.raise_signal(left)  # as if it arrived now, to the handler of the enclosing code


def checkpoint() -> None:
    """Within deferred(): raise Interrupted if a signal was recorded meanwhile (the writer
    then removes what it wrote); a no-op elsewhere."""
    global _pending
    if _pending is not None:
        _pending = None
        raise Interrupted


def settle(status: str) -> None:
    """After a run's time loop, before its results are written: a stop request the loop
    acted on (its status "failed: interrupted") is done with; one it did not see (a
    KeyboardInterrupt swallowed in a finaliser once the loop had ended) stops the run now,
    with nothing written, rather than let it end in exit 0 as if nothing had happened."""
    global _requested
    if status.startswith("failed: interrupted"):
        _requested = False
    elif _requested:
        raise Interrupted


def stop_if_requested() -> None:
    """Raise KeyboardInterrupt if a stop was requested in the current block, even one whose
    first KeyboardInterrupt the interpreter swallowed."""
    if _requested:
        raise Interrupted
