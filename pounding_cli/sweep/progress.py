"""What `pound sweep` prints: the progress bar on stderr, the list of a dry run, the end.

The bar counts distinct runs (cases sharing inputs run once): done, failed and the time
left, estimated from the rate so far. Without a terminal (or with --no-progress) there is
no bar; the log lines and the final counts still go to stderr.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from rich.console import Console
from rich.table import Table

if TYPE_CHECKING:
    from .run import SweepOutcome

FAILED_SHOWN = 20
"""Failed cases listed with their messages at the end (the rest are in the summary)."""


class SweepProgress:
    """A rich progress bar for the two stages of a sweep, "check" and "run"."""

    def __init__(self, console: Console, show: bool):
        self.console = console
        self.show = show
        self.bar: Any = None
        self.tasks: dict[str, Any] = {}

    def __enter__(self) -> "SweepProgress":
        if self.show:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
            from rich.progress import TimeRemainingColumn

            self.bar = Progress(
                TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                TextColumn("{task.fields[failed]} failed"), TimeElapsedColumn(), TextColumn("ETA"),
                TimeRemainingColumn(), console=self.console, transient=False,
            )  # fmt: skip
            self.bar.__enter__()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.__exit__(*exc)

    def update(self, stage: str, done: int, failed: int, total: int) -> None:
        """on_progress of run_sweep."""
        if self.bar is None:
            return
        if stage not in self.tasks:
            label = "checking cases" if stage == "check" else "running cases "
            self.tasks[stage] = self.bar.add_task(label, total=total, failed=0)
        self.bar.update(self.tasks[stage], completed=done, total=total, failed=failed)

    def log(self, text: str) -> None:
        """log of run_sweep: one line on stderr (above the bar while it shows)."""
        self.console.print(text, markup=False, highlight=False, soft_wrap=True)


def print_cases(console: Console, outcome: SweepOutcome) -> None:
    """A dry run's list: one line per case with its hash, status and values."""
    rows = [outcome.rows[i] for i in outcome.selected]
    table = Table(title=f"{len(rows)} cases ({len({r['hash'] for r in rows})} distinct runs) → {outcome.folder}")
    for name in ("study", "case", "hash", "status"):
        table.add_column(name)
    for row in rows:
        table.add_row(row["study"], row["case"], row["hash"], row["status"])
    console.print(table)


def print_outcome(console: Console, outcome: SweepOutcome) -> None:
    """The end of a sweep on stderr: counts, where the summary is, the failed cases."""
    rows = [outcome.rows[i] for i in outcome.selected]
    complete = sum(r["status"] == "complete" for r in rows)
    failed = [r for r in rows if r["status"].startswith("failed")]
    pending = len(rows) - complete - len(failed)
    text = (f"{len(rows)} cases: {complete} complete ({outcome.reused} already were), {len(failed)} failed"
            + (f", {pending} not run" if pending else "") + f"; {outcome.ran} runs in {outcome.wall_time_s:.1f} s")  # fmt: skip
    if outcome.interrupted:
        text = "interrupted; rerun the same command to go on. " + text
    console.print(text, markup=False, highlight=False, soft_wrap=True)
    if outcome.summary is not None:
        console.print(f"summary: {outcome.summary[1]} and {outcome.summary[0].name}", markup=False, highlight=False)
    for row in failed[:FAILED_SHOWN]:
        label = f"{row['study']}/{row['case']}" if row["study"] else row["case"]
        console.print(f"{label} ({row['hash']}): {row['status']}", markup=False, highlight=False, soft_wrap=True)
    if len(failed) > FAILED_SHOWN:
        console.print(f"… and {len(failed) - FAILED_SHOWN} more failed cases (see the summary)", markup=False)
