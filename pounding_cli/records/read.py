"""Read one ground-acceleration time history from a file into an :class:`Accelerogram`.

Files obspy reads (MiniSEED, SAC, ...) go through ``obspy.read``; obspy is
imported only when a file is read, because importing it is slow. Other files
are tried as plain text (:mod:`pounding_cli.records.plaintext`). Every problem
with a file or with the arguments raises :class:`~pounding_cli.errors.RecordReadError`
naming the path; nothing is printed.

Trace selection in a multi-trace file (``trace``):

- ``None``: the file must hold a single trace id;
- ``"NET.STA.LOC.CHA"`` (has a dot): that SEED id exactly;
- ``"0"``, ``"1"``, ... (all digits): the trace at that position in the file;
- anything else: a channel code such as ``"HNE"``, matched against ``stats.channel``.

A plain-text record is a single trace: ``trace`` must be None or ``"0"``.

Pickled obspy streams are refused: unpickling a file can run arbitrary code.

Units: pound's own readers (AT2, COSMOS) convert to m/s² and say what the file held; K-NET
and KiK-net files (obspy's KNET reader) hold counts and a calibration, which is applied
(counts × ``stats.calib`` = m/s²). Other formats carry raw values in the unit the caller
names. ``units=None`` accepts only files that declare their units.

Traces sharing the selected id (a channel split into segments) are merged when
they join up exactly (no gap, identical overlap); a record with a gap or with
conflicting overlap is refused rather than filled with invented data.
"""

from __future__ import annotations

import glob
import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pounding_cli.errors import RecordReadError
from pounding_cli.files import MAX_RECORD_BYTES, FileRefused, check_regular, read_start
from pounding_cli.model.base import MAX_SAMPLE_INTERVAL, MIN_SAMPLE_INTERVAL
from pounding_cli.records.plaintext import REL_TOL, NotPlainText, decode_text, parse_plaintext

if TYPE_CHECKING:
    from obspy import Stream, Trace

UNIT_FACTORS: dict[str, float] = {"g": 9.80665, "m/s2": 1.0, "cm/s2": 0.01, "gal": 0.01}
"""Factor converting each accepted acceleration unit to m/s² (standard gravity for ``g``)."""


@dataclass(frozen=True, eq=False)
class Accelerogram:
    """A uniformly sampled ground-acceleration time history.

    ``acceleration[i]`` is the ground acceleration (m/s²) at time ``i * dt``
    after the first sample; ``dt`` is the sample interval (s). ``source`` says
    where it came from; ``start_time`` is the ISO UTC time of the first sample
    when the file records it. ``trace_id`` is the obspy trace id (None for plain
    text), ``units_in_file`` the unit of the file's values (as the file or the
    caller names it) and ``header`` what the file says about the record (station,
    event, azimuth, ...: JSON-ready, see :func:`file_header`). The array is stored
    as a read-only C-contiguous float64 copy. Compared by identity (``eq=False``:
    arrays have no single truth value).
    """

    dt: float
    acceleration: np.ndarray
    source: str
    start_time: str | None = None
    trace_id: str | None = None
    units_in_file: str | None = None
    header: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and self.dt > 0.0):
            raise ValueError(f"dt must be a finite positive number of seconds, got {self.dt!r}")
        values = np.array(self.acceleration, dtype=np.float64, order="C")
        if values.ndim != 1:
            raise ValueError(f"acceleration must be one-dimensional, got shape {values.shape}")
        values.setflags(write=False)
        object.__setattr__(self, "dt", float(self.dt))
        object.__setattr__(self, "acceleration", values)

    @property
    def duration(self) -> float:
        """Time from the first to the last sample, s."""
        return (self.acceleration.size - 1) * self.dt


def read_accelerogram(
    path: str | Path,
    *,
    trace: str | None = None,
    units: str | None = "m/s2",
    format: str = "auto",
    dt: float | None = None,
) -> Accelerogram:
    """Read a ground-acceleration record and return it in m/s².

    ``units`` is the unit of the values in the file (a key of :data:`UNIT_FACTORS`), or
    None to accept only a file that declares its units. ``format`` is ``"auto"`` (obspy,
    then plain text), ``"text"`` (plain text only) or an obspy format name such as
    ``"MSEED"`` or ``"SAC"``. ``dt`` (s) is required for one-column plain text; elsewhere
    it is optional and must agree with the file's own sample interval to within 1e-6 relative.
    """
    return _read(path, units, format, dt, trace, every=False)[0]


def read_accelerograms(
    path: str | Path, *, units: str | None = "m/s2", format: str = "auto", dt: float | None = None
) -> list[Accelerogram]:
    """Every trace of a file, one :class:`Accelerogram` per trace id in file order (segments
    of one id joined); the arguments are those of :func:`read_accelerogram`."""
    return _read(path, units, format, dt, None, every=True)


def _read(
    path: str | Path, units: str | None, format: str, dt: float | None, trace: str | None, every: bool
) -> list[Accelerogram]:
    """Check the arguments and the file, then read it with obspy or as plain text."""
    factor = None if units is None else _unit_factor(units)
    _check_dt_argument(dt)
    path = Path(path)
    _check_file(path)
    stream = None if format.lower() == "text" else _obspy_read(path, format)
    if stream is None:
        return [_text_record(_text_of(path, format), path, trace, dt, units, factor)]
    if every:
        ids = list(dict.fromkeys(tr.id for tr in stream))
        if not ids:
            raise RecordReadError(f"{path}: holds no traces")
        chosen = [_merge_segments(stream.select(id=i), i, path) for i in ids]
    else:
        chosen = [_select_trace(stream, trace, path)]
    return [_trace_record(tr, path, dt, units, factor) for tr in chosen]


def _text_of(path: Path, format: str) -> str:
    """The file as text; for ``format='auto'`` a binary file is one obspy did not know."""
    if format.lower() == "text":
        return _decode(path)
    try:
        return _decode(path)
    except NotPlainText as err:
        raise RecordReadError(f"{path}: neither a format obspy reads nor plain text ({err.reason})") from err


def _text_record(
    text: str, path: Path, trace: str | None, dt: float | None, units: str | None, factor: float | None
) -> Accelerogram:
    """A plain-text record in m/s²: its values times the unit factor the caller gave."""
    step, values = _read_text(text, path, trace, dt)
    if factor is None:
        raise RecordReadError(
            f"{path}: plain text does not say in which units its values are; "
            f"give units ({', '.join(UNIT_FACTORS)})",
            field="units",
        )
    _check_samples(step, values, path, factor)
    return Accelerogram(step, values * factor, str(path), None, None, units)


def _trace_record(trace: Trace, path: Path, dt: float | None, units: str | None, factor: float | None) -> Accelerogram:
    """An obspy trace as an Accelerogram in m/s², with the file's header."""
    from pounding_cli.records.header import file_header

    step = float(trace.stats.delta)
    _check_dt_agrees(dt, step, path)
    try:
        values = np.asarray(trace.data, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise RecordReadError(f"{path}: {trace.id} does not hold real numbers ({err})") from err
    declared = _declared_units(trace)
    if declared is not None:  # the file says its units: converted (or calibrated) to m/s²
        in_file, file_factor, calibration = declared
        if factor not in (None, 1.0) and not (file_factor and abs(factor - file_factor) <= 1e-12 * file_factor):
            same = [name for name, f in UNIT_FACTORS.items() if file_factor and abs(f - file_factor) <= 1e-12 * f]
            write = " or ".join(repr(name) for name in dict.fromkeys([*same[:1], "m/s2"]))
            raise RecordReadError(
                f"{path}: the file declares its values in {in_file} (pound converts them to m/s²); "
                f"'units' = {units!r} contradicts it: write {write}",
                field="units",
            )
        values, units, factor = values * calibration if calibration != 1.0 else values, in_file, 1.0
    elif factor is None:
        raise RecordReadError(
            f"{path}: {trace.id} does not say in which units its values are "
            f"({trace.stats.get('_format', 'this format')} holds raw numbers); "
            f"give units ({', '.join(UNIT_FACTORS)})",
            field="units",
        )
    _check_samples(step, values, path, factor)
    return Accelerogram(step, values * factor, f"{path} [{trace.id}]", str(trace.stats.starttime),
                        trace.id, units, file_header(trace))


def _unit_factor(units: str) -> float:
    """Return the factor from ``units`` to m/s², or raise listing the accepted units."""
    try:
        return UNIT_FACTORS[units.strip().lower()]
    except (KeyError, AttributeError):
        accepted = ", ".join(UNIT_FACTORS)
        raise RecordReadError(f"unknown units {units!r}; accepted: {accepted}", field="units") from None


def _check_dt_argument(dt: float | None) -> None:
    """Raise unless ``dt`` is None or a plausible sample interval, s."""
    if dt is None:
        return
    try:
        ok = MIN_SAMPLE_INTERVAL <= dt <= MAX_SAMPLE_INTERVAL
    except TypeError:
        ok = False
    if not ok:
        raise RecordReadError(f"dt must be a sample interval of {MIN_SAMPLE_INTERVAL:g} to {MAX_SAMPLE_INTERVAL:g} s, "
                              f"got {dt!r}", field="dt")


def _check_file(path: Path) -> None:
    """Raise unless ``path`` is an existing, non-empty regular file of at most
    MAX_RECORD_BYTES (a FIFO or a device is refused before anything reads it)."""
    if path.is_dir():
        raise RecordReadError(f"{path}: is a directory, not a record file")
    try:
        size = check_regular(path, MAX_RECORD_BYTES)
    except FileRefused as err:
        raise RecordReadError(f"{path}: {err.reason}") from None
    if size == 0:
        raise RecordReadError(f"{path}: empty file")


def _decode(path: Path) -> str:
    """Read the file as text, wrapping operating-system errors."""
    try:
        return decode_text(path)
    except OSError as err:
        raise RecordReadError(f"{path}: cannot read the file ({err.strerror or err})") from err


def _declared_units(trace: Trace) -> tuple[str, float | None, float] | None:
    """(units as the file names them, their factor to m/s², factor still to apply) when the
    file says what its values are; None for raw values (MiniSEED, SAC, ...).

    pound's own readers (AT2, COSMOS) have already converted to m/s² and record the factor
    they applied, so a file's "cm/sec2" matches the setting "cm/s2" (or "gal"); K-NET/KiK-net
    files read by obspy hold counts whose ``stats.calib`` is m/s² per count.
    """
    for key in ("at2", "cosmos"):
        info = trace.stats.get(key)
        if info is not None and info.get("units") == "m/s2":
            in_file = str(info.get("units_in_file"))
            try:
                file_factor = float(info.get("factor"))
            except (TypeError, ValueError):
                file_factor = UNIT_FACTORS.get(in_file.strip().lower().replace(" ", ""))
            return in_file, file_factor, 1.0
    if trace.stats.get("knet") is not None:
        return "counts × calib (K-NET scale factor, to m/s²)", 1.0, float(trace.stats.calib)
    return None


def _read_text(
    text: str, path: Path, trace: str | None, dt: float | None
) -> tuple[float, np.ndarray]:
    """Parse a plain-text record, which holds a single trace (``trace`` None or ``"0"``)."""
    if trace is not None and str(trace).strip() != "0":
        raise RecordReadError(
            f"{path}: plain text holds a single trace; 'trace' = {trace!r} does not apply",
            field="trace",
        )
    return parse_plaintext(text, str(path), dt)


def _obspy_read(path: Path, format: str) -> Stream | None:
    """Return ``obspy.read(path)``; None if ``format='auto'`` and obspy does not know the format."""
    import obspy  # slow import: only when a file is read

    _refuse_pickle(path, format)
    name = glob.escape(str(path))  # obspy.read expands wildcards; the path is literal
    auto = format.lower() == "auto"
    if auto:
        format = _cheap_guess(path) or "auto"  # skips obspy's scan of every plugin (~0.2 s)
    options = {} if format.lower() == "auto" else {"format": format}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            stream = obspy.read(name, **options)
        except TypeError as err:
            if auto and "unknown format" in str(err).lower():
                return None
            raise RecordReadError(f"{path}: obspy cannot read it as {format!r} ({err})", field="format") from err
        except Exception as err:  # obspy raises many exception types for corrupt files
            reason = "; ".join([f"{type(err).__name__}: {err}"] + [str(w.message) for w in caught])
            raise RecordReadError(f"{path}: obspy failed to read it ({reason})") from err
    for caught_warning in caught:  # a successful read keeps obspy's warnings
        warnings.warn(caught_warning.message, stacklevel=3)
    return stream


def _cheap_guess(path: Path) -> str | None:
    """The format of pound's own text formats, or of MiniSEED by its fixed header, without
    loading obspy's plugins; None when unsure (obspy then detects it)."""
    from .at2.core import _is_at2
    from .cosmos.core import _is_cosmos

    if _is_at2(str(path)):
        return "AT2"
    if _is_cosmos(str(path)):
        return "COSMOS"
    try:
        head = read_start(path, 8)
    except FileRefused:
        return None
    # a MiniSEED record starts with a 6-digit sequence number and a quality code
    if len(head) == 8 and head[:6].strip(b" 0123456789") == b"" and head[6:7] in b"DRQM" and head[7:8] in b" \x00":
        return "MSEED"
    return None


def _refuse_pickle(path: Path, format: str) -> None:
    """Refuse pickled obspy streams: unpickling a file can run arbitrary code.

    obspy's format detection unpickles any file whose first 100 bytes name
    ``obspy.core.stream``, so such files are stopped before ``obspy.read``.
    """
    try:
        looks_pickled = b"obspy.core.stream" in read_start(path, 100)
    except FileRefused as err:
        raise RecordReadError(f"{path}: {err.reason}") from None
    if format.upper() == "PICKLE" or looks_pickled:
        raise RecordReadError(
            f"{path}: pickled obspy streams are not read (unpickling a file can run "
            "arbitrary code); save the record as MiniSEED or SAC instead"
        )


def _select_trace(stream: Stream, trace: str | None, path: Path) -> Trace:
    """Return the one trace chosen by ``trace`` (see the module docstring), segments merged."""
    ids = list(dict.fromkeys(tr.id for tr in stream))
    if not ids:
        raise RecordReadError(f"{path}: holds no traces")
    if trace is None:
        if len(ids) > 1:
            raise RecordReadError(
                f"{path}: holds {len(ids)} traces ({', '.join(ids)}); choose one with 'trace'",
                field="trace",
            )
        chosen = ids[0]
    else:
        chosen = _match_trace_id(stream, ids, str(trace).strip(), path)
    return _merge_segments(stream.select(id=chosen), chosen, path)


def _match_trace_id(stream: Stream, ids: list[str], trace: str, path: Path) -> str:
    """Return the trace id that ``trace`` names: a SEED id, an index or a channel code."""
    if "." in trace:
        matches = [trace] if trace in ids else []
    elif trace.isascii() and trace.isdecimal():
        index = int(trace)
        matches = [stream[index].id] if index < len(stream) else []
    else:
        matches = list(dict.fromkeys(tr.id for tr in stream if tr.stats.channel == trace))
    if len(matches) == 1:
        return matches[0]
    if matches:
        raise RecordReadError(
            f"{path}: channel {trace!r} is ambiguous: {', '.join(matches)}; give the full SEED id",
            field="trace",
        )
    raise RecordReadError(
        f"{path}: no trace matches {trace!r}; available: {', '.join(ids)} "
        f"(give a SEED id NET.STA.LOC.CHA, a channel code or an index 0..{len(stream) - 1})",
        field="trace",
    )


def _merge_segments(segments: Stream, trace_id: str, path: Path) -> Trace:
    """Join the segments of one trace id; refuse gaps or conflicting overlaps."""
    if len(segments) == 1:
        return segments[0]
    try:
        merged = segments.copy().merge(method=0)
    except Exception as err:  # e.g. differing sampling rates
        raise RecordReadError(f"{path}: cannot merge the segments of {trace_id} ({err})") from err
    if len(merged) != 1 or np.ma.is_masked(merged[0].data):
        raise RecordReadError(
            f"{path}: {trace_id} is split into {len(segments)} segments with gaps or "
            "conflicting overlaps; fill or cut the gaps before using it as a record"
        )
    merged[0].data = np.ma.getdata(merged[0].data)
    return merged[0]


def _check_dt_agrees(dt: float | None, step: float, path: Path) -> None:
    """Raise if a given ``dt`` disagrees with the file's own sample interval."""
    if dt is not None and math.isfinite(step) and abs(dt - step) > REL_TOL * abs(step):
        raise RecordReadError(
            f"{path}: given dt = {dt:.9g} s disagrees with the file's sample interval {step:.9g} s",
            field="dt",
        )


def with_values(record: Accelerogram, values: np.ndarray, dt: float | None = None, note: str = "") -> Accelerogram:
    """A copy of `record` holding other samples (processed), optionally at another interval."""
    source = f"{record.source} ({note})" if note else record.source
    return replace(record, acceleration=values, dt=record.dt if dt is None else dt, source=source)


MAX_ACCELERATION = 1000.0 * UNIT_FACTORS["g"]
"""Largest ground acceleration a file may hold, m/s² (1000 g). The largest ever recorded
are a few g; a value far beyond is a unit mistake (counts, mm/s²) or a damaged file, and
refusing it here keeps overflow (an Arias intensity of inf) out of everything downstream."""


def _check_samples(dt: float, values: np.ndarray, path: Path, factor: float = 1.0) -> None:
    """Raise unless there are at least two finite samples, no larger than MAX_ACCELERATION
    once multiplied by `factor` (to m/s²), and dt is a plausible sample interval."""
    if not MIN_SAMPLE_INTERVAL <= dt <= MAX_SAMPLE_INTERVAL:
        raise RecordReadError(f"{path}: sample interval dt = {dt!r} s is outside {MIN_SAMPLE_INTERVAL:g} to "
                              f"{MAX_SAMPLE_INTERVAL:g} s (a damaged header?)")
    if values.size < 2:
        count = "zero samples" if values.size == 0 else "only one sample"
        raise RecordReadError(f"{path}: {count}; a record needs at least two")
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise RecordReadError(f"{path}: non-finite value (NaN, inf, or beyond float range in m/s²) at "
                              f"sample index {int(bad[0])}")
    huge = np.flatnonzero(np.abs(values) * factor > MAX_ACCELERATION)
    if huge.size:
        i = int(huge[0])
        raise RecordReadError(
            f"{path}: sample index {i} is {float(values[i]) * factor:.6g} m/s², more than "
            f"{MAX_ACCELERATION / UNIT_FACTORS['g']:g} g, which no ground motion reaches; check the units "
            "of the file (counts? mm/s²?) or the value"
        )
