"""The `pound` command and `python -m pounding_cli`: SIGTERM is taken over before anything
heavy is imported, so that from here on a SIGTERM stops pound as Ctrl-C does (exit 1,
"interrupted", nothing written) instead of killing it unannounced; the commands then take
finer care of it (interrupts.terminate_as_interrupt, atomic writes).

While pound starts, the cyclic garbage collector runs less often (START_GC_THRESHOLDS): the
imports make some 150,000 long-lived objects and almost no garbage, and the default
thresholds (700, 10, 10) had the collector run over 300 times while they were made, twice
through all of them (0.05-0.3 s of a run).
When the command is done, its objects are frozen out of the cyclic garbage collector
(gc.freeze): the interpreter's last collection at exit would otherwise take apart the
object graphs that numba, pydantic and typer built at start-up, one by one, for nothing
(0.3-0.5 s of a 2.4 s `pound run`, docs/bench.md "Cold start"); the operating system
frees the memory at once. Files and other resources are closed by the commands themselves
and by the exit handlers, which still run."""

from __future__ import annotations

import gc
import sys

START_GC_THRESHOLDS = (20_000, 20, 20)
"""gc.set_threshold for a pound process: a young collection per 20,000 net allocations, not 700."""


def main() -> None:
    """Console-script entry point."""
    gc.set_threshold(*START_GC_THRESHOLDS)
    from .interrupts import stop_from_the_start, stop_if_requested

    stop_from_the_start()
    try:
        from .cli import main as cli_main

        stop_if_requested()  # one that a callback swallowed while loading
    except KeyboardInterrupt:  # SIGTERM or Ctrl-C while the command line is being loaded
        print("interrupted", file=sys.stderr)
        sys.exit(1)
    try:
        cli_main()
    finally:
        gc.freeze()


if __name__ == "__main__":
    main()
