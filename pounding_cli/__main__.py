"""The `pound` command and `python -m pounding_cli`: SIGTERM is taken over before anything
heavy is imported, so that from here on a SIGTERM stops pound as Ctrl-C does (exit 1,
"interrupted", nothing written) instead of killing it unannounced; the commands then take
finer care of it (interrupts.terminate_as_interrupt, atomic writes)."""

from __future__ import annotations

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
        sys.exit(1)
    cli_main()


if __name__ == "__main__":
    main()
