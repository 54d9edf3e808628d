"""The `pound` command and `python -m pounding_cli`: SIGTERM is taken over before anything
heavy is imported, so that from here on a SIGTERM stops pound as Ctrl-C does (exit 1,
"interrupted", nothing written) instead of killing it unannounced; the commands then take
finer care of it (interrupts.terminate_as_interrupt, atomic writes).

Once a command has ended with its exit code, the process ends at once (end_now): the
interpreter's own shutdown would then take numba's, pydantic's and typer's object graphs apart
one by one, a third of a second of a run that takes a second (docs/bench.md, "Cold start"),
with nothing left to do by then: every file pound writes is closed and renamed before its
command returns, and the streams are flushed here."""

from __future__ import annotations

import os
import sys


def main() -> None:
    """Console-script entry point."""
    from .interrupts import stop_from_the_start, stop_if_requested

    stop_from_the_start()
    try:
        from .cli import main as cli_main

        stop_if_requested()  # one that a callback swallowed while loading
    except KeyboardInterrupt:  # SIGTERM or Ctrl-C while the command line is being loaded
        print("interrupted", file=sys.stderr)
        end_now(1)
    try:
        cli_main()
    except SystemExit as done:
        end_now(done.code)
    end_now(0)


def end_now(code: int | str | None) -> None:
    """End the process with `code` as SystemExit would (None: 0; a message: printed to stderr,
    1), without the interpreter's shutdown: the exit handlers run (atexit: logging's flush,
    numba's, h5py's and any a caller registered) and the output streams are flushed, but the
    modules are not torn down. An exception other than SystemExit (a traceback, the signal's
    own end after a complete write, interrupts.die_by) never gets here."""
    import atexit

    if code is None:
        code = 0
    elif not isinstance(code, int):
        print(code, file=sys.stderr)
        code = 1
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe, a closed stream: nothing more can be said
            pass
    os._exit(code)


if __name__ == "__main__":
    main()
