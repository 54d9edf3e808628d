"""The errors pound reports to its users, and the exit code of each.

- :class:`InputError` — bad input or usage; the CLI prints it as one paragraph
  ``file: path.to.field: what was expected`` and exits 2.
- :class:`RecordReadError` — a ground-motion file could not be read; raised by
  :mod:`pounding_cli.records` without knowing which model field named the file,
  and turned into an :class:`InputError` by whoever does.
- :class:`WriteError` — an InputError: a file could not be written (disk full); exit 2.
- :class:`AnalysisFailed` — the analysis ran but failed (instability, blow-up);
  exit 1, partial results kept and marked.
"""

from __future__ import annotations

from pathlib import Path


class PoundError(Exception):
    """Base of every error pound raises on purpose."""

    exit_code = 1


class InputError(PoundError):
    """Bad input: names the file, the field and what was expected."""

    exit_code = 2

    def __init__(self, message: str, *, file: str | Path | None = None, field: str | None = None):
        self.file = str(file) if file is not None else None
        self.field = field
        self.message = message
        super().__init__(self.__str__())

    def __str__(self) -> str:
        parts = [p for p in (self.file, self.field) if p]
        parts.append(self.message)
        return ": ".join(parts)


class WriteError(InputError):
    """A file could not be written (the disk full, no permission, a folder gone): exit 2,
    "cannot write the file (reason)", with nothing left under the file's name or a temporary
    one (pounding_cli.atomic). A sweep stops at the first case that could not be written."""


class RecordReadError(PoundError):
    """A record file could not be read or does not hold what was asked for.

    `field` names the setting of the record component at fault: "file" (the default),
    "trace", "units", "format" or "dt".
    """

    exit_code = 2

    def __init__(self, message: str, *, field: str = "file"):
        self.field = field
        super().__init__(message)


class AnalysisFailed(PoundError):
    """The analysis ran but could not finish (e.g. numerical instability)."""

    exit_code = 1
