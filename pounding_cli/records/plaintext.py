"""Plain-text accelerograms: one value per line, or two columns ``time value``.

Format accepted by :func:`parse_plaintext`:

- one column: one acceleration value per line; the sample interval ``dt`` (s)
  must be given by the caller, since the file does not hold it;
- two columns: ``time value`` per line (time in s), separated by whitespace, a
  comma or a semicolon. Times must increase strictly and be uniformly spaced to
  within :data:`REL_TOL` of the step, plus the rounding of the times themselves
  (epoch times of 1.7e9 s are resolved to 2.4e-7 s; non-uniform records must be
  resampled first); ``dt`` is the mean step, (last time − first time)/(samples − 1), which
  averages the rounding out;
- blank lines and lines starting with ``#`` or ``%`` are ignored, and so is a
  first non-numeric line (a column header such as ``time, acc``).

Values are returned in the file's units; the caller applies the unit factor.
Every problem is a :class:`~pounding_cli.errors.RecordReadError` naming the
file and, where there is one, the line number (1-based, counting every line).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from pounding_cli.errors import RecordReadError
from pounding_cli.files import MAX_RECORD_BYTES, FileRefused, read_regular

REL_TOL = 1e-6
"""Relative tolerance on the time step: uniform spacing, and agreement with a given ``dt``."""

_SEPARATORS = re.compile(r"[\s,;]+")
_COMMENT_PREFIXES = ("#", "%")
_BINARY = re.compile(r"[\x00-\x08\x0e-\x1f\x7f]")  # control characters other than \t \n \v \f \r


class NotPlainText(RecordReadError):
    """The file is binary data, not text; ``reason`` says why."""

    def __init__(self, path: Path, reason: str):
        self.reason = reason
        super().__init__(f"{path}: not plain text ({reason})")


def decode_text(path: Path) -> str:
    """Return the file's content as text, or raise :class:`NotPlainText` for binary data."""
    try:
        raw = read_regular(path, MAX_RECORD_BYTES)
    except FileRefused as exc:
        raise RecordReadError(f"{path}: {exc.reason}") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise NotPlainText(path, f"byte {err.start} is not UTF-8") from err
    binary = _BINARY.search(text)
    if binary:
        where = f"control character {binary.group()!r} at character {binary.start()}"
        raise NotPlainText(path, where)
    return text


def parse_plaintext(text: str, name: str, dt: float | None = None) -> tuple[float, np.ndarray]:
    """Parse a plain-text record; return ``(dt, values)``, dt in s, values in the file's units.

    ``name`` is used in error messages. ``dt`` (s) is required for one column;
    for two columns it is optional and, if given, must agree with the time
    column to within :data:`REL_TOL` (the given value is then used).
    """
    line_numbers, rows = _numeric_rows(text, name)
    if not rows:
        raise RecordReadError(f"{name}: no data values (zero samples)")
    table = np.array(rows, dtype=np.float64)
    _check_finite(table, line_numbers, name)
    if table.shape[1] == 1:
        if dt is None:
            raise RecordReadError(f"{name}: plain text with one value per line: give 'dt'", field="dt")
        return dt, table[:, 0]
    return _dt_from_times(table[:, 0], line_numbers, name, dt), table[:, 1]


def _numeric_rows(text: str, name: str) -> tuple[list[int], list[list[float]]]:
    """Return the line numbers and values of the numeric rows (one or two fields each)."""
    line_numbers: list[int] = []
    rows: list[list[float]] = []
    first_content = True
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip(" \t\r\f\v,;")
        if not stripped or stripped.startswith(_COMMENT_PREFIXES):
            continue
        fields = _SEPARATORS.split(stripped)
        if first_content and not _is_number(fields[0]):
            first_content = False
            continue  # a column header
        first_content = False
        values = [_to_float(field, number, name) for field in fields]
        _check_column_count(fields, number, rows, line_numbers, name)
        rows.append(values)
        line_numbers.append(number)
    return line_numbers, rows


def _check_column_count(
    fields: list[str], number: int, rows: list[list[float]], line_numbers: list[int], name: str
) -> None:
    """Raise unless the line has 1 or 2 fields, as many as the first data line."""
    if len(fields) > 2:
        raise RecordReadError(
            f"{name}: line {number} has {len(fields)} columns; "
            "expected 1 (value) or 2 (time value)"
        )
    if rows and len(fields) != len(rows[0]):
        raise RecordReadError(
            f"{name}: line {number} has {len(fields)} column(s) but line {line_numbers[0]} "
            f"has {len(rows[0])}; mixed column counts"
        )


def _is_number(field: str) -> bool:
    """True if ``field`` parses as a floating-point number."""
    try:
        float(field)
    except ValueError:
        return False
    return True


def _to_float(field: str, number: int, name: str) -> float:
    """Parse one field, naming the line and the text if it is not a number."""
    try:
        return float(field)
    except ValueError:
        raise RecordReadError(f"{name}: line {number}: {field!r} is not a number") from None


def _check_finite(table: np.ndarray, line_numbers: list[int], name: str) -> None:
    """Raise at the first NaN or infinity, naming its line and sample index."""
    bad = np.flatnonzero(~np.isfinite(table).all(axis=1))
    if bad.size:
        index = int(bad[0])
        raise RecordReadError(
            f"{name}: line {line_numbers[index]}: non-finite value at sample index {index}"
        )


def _dt_from_times(
    times: np.ndarray, line_numbers: list[int], name: str, dt: float | None
) -> float:
    """Return the sample interval (s) of a strictly increasing, uniformly spaced time column."""
    if times.size < 2:
        raise RecordReadError(f"{name}: only one sample; a record needs at least two")
    steps = np.diff(times)
    not_increasing = np.flatnonzero(steps <= 0.0)
    if not_increasing.size:
        i = int(not_increasing[0]) + 1
        raise RecordReadError(
            f"{name}: line {line_numbers[i]}: time {times[i]:g} s does not follow "
            f"{times[i - 1]:g} s (line {line_numbers[i - 1]}); times must increase strictly"
        )
    # each time is the file's decimal rounded to the nearest float: its spacing at the largest
    # time (2.4e-7 s at an epoch time of 1.7e9 s) is allowed on every step, as REL_TOL is
    resolution = 2.0 * float(np.spacing(np.max(np.abs(times))))
    median = float(np.median(steps))
    uneven = np.flatnonzero(np.abs(steps - median) > REL_TOL * median + resolution)
    if uneven.size:
        i = int(uneven[0]) + 1
        raise RecordReadError(
            f"{name}: line {line_numbers[i]}: time step {steps[i - 1]:.9g} s differs from the "
            f"median step {median:.9g} s; the record is not uniformly sampled "
            "(non-uniform records must be resampled to a constant step first)"
        )
    step = float((times[-1] - times[0]) / (times.size - 1))  # the rounding of each time averaged out
    if dt is None:
        return step
    if abs(dt - step) > REL_TOL * step:
        raise RecordReadError(
            f"{name}: given dt = {dt:.9g} s disagrees with the time column's step {step:.9g} s",
            field="dt",
        )
    return dt
