"""PEER NGA ``.AT2`` acceleration files: detection and reading (see the package docstring)."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core.util import AttribDict
from ..seed import band_code
from ..textfile import BINARY, read_all, read_head, source_name

G = 9.80665
"""Standard gravity, m/s² per g."""

UNIT_FACTORS = {"G": G, "CM/S/S": 0.01, "CM/S2": 0.01, "CM/S^2": 0.01, "CM/SEC/SEC": 0.01,
                "CM/SEC2": 0.01, "CM/SEC^2": 0.01, "GAL": 0.01, "M/S/S": 1.0, "M/S2": 1.0,
                "M/S^2": 1.0}
"""Factor from each accepted unit of the third header line to m/s² (keys upper case, no spaces)."""

DETECT_BYTES = 4096
"""How much of a file :func:`_is_at2` reads."""

_UNITS_LINE = re.compile(
    r"^\s*ACCELERATION\s+TIME\s+(?:SERIES|HISTORY)\s+IN\s+UNITS\s+OF\s+(.*?)\s*$", re.IGNORECASE
)
_NUMBER = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?)"
# NGA-West2: "NPTS=   7500, DT=   .0200 SEC,"; spaces around "=" and "," tolerated.
_NPTS_NEW = re.compile(rf"^\s*NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*{_NUMBER}\s*(?:SECS?\.?)?\s*,?\s*$",
                       re.IGNORECASE)
# Older NGA: "   7500    .0200    NPTS, DT".
_NPTS_OLD = re.compile(rf"^\s*(\d+)\s*,?\s+{_NUMBER}\s*,?\s+NPTS\s*,?\s*DT\b.*$", re.IGNORECASE)
_NPTS_WORDS = re.compile(r"\bNPTS\b.*\bDT\b", re.IGNORECASE)
_FORTRAN_EXPONENT = re.compile(r"(?<=[0-9.])[Dd](?=[-+]?[0-9])")
"""A Fortran double-precision exponent letter, 1.5D-03: read as E, in the values as in the header."""
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_VERTICAL = {"UP", "UD", "U", "V", "VER", "VERT", "VERTICAL", "Z", "DWN", "DOWN", "DN"}
_NORTH = {"N", "NS", "N-S", "NORTH"}
_EAST = {"E", "EW", "E-W", "EAST"}


def _is_at2(filename: Any) -> bool:
    """True if ``filename`` (path or file object) looks like a PEER ``.AT2`` acceleration file.

    Reads at most :data:`DETECT_BYTES` bytes, restores the position of a file object and
    returns False rather than raising. The file is taken as AT2 if it is text and its third
    line is the units line (``ACCELERATION TIME SERIES IN UNITS OF ...``) or its fourth line
    names ``NPTS`` and ``DT``; the reader then checks every header line strictly, so a
    damaged AT2 file is reported as such instead of as an unknown format.
    """
    try:
        head = read_head(filename, DETECT_BYTES)
    except Exception:  # noqa: BLE001 - detection must never raise
        return False
    if head is None or BINARY.search(head):
        return False
    lines = _LINE_BREAK.split(head)
    if len(lines) < 4:
        return False
    return bool(_UNITS_LINE.match(lines[2]) or _NPTS_WORDS.search(lines[3]))


def _read_at2(filename: Any, headonly: bool = False, **kwargs: Any) -> Stream:
    """Read a PEER ``.AT2`` file into a one-trace Stream in m/s² (see the package docstring).

    ``filename`` is a path or an open file object (binary or text, e.g. ``BytesIO``).
    With ``headonly=True`` the trace holds the header (``npts`` included) but no data.
    Other keyword arguments passed by :func:`obspy.read` are ignored. Raises ValueError
    naming the file and the line for anything that is not a valid AT2 file.
    """
    name = source_name(filename)
    lines = _LINE_BREAK.split(read_all(filename, name, "an AT2 text file"))
    if len(lines) < 4:
        raise ValueError(f"{name}: an AT2 file has 4 header lines; found only {len(lines)} line(s)")
    stats = _header_stats(lines, name)
    if headonly:
        return Stream([Trace(header=stats)])
    data = _parse_values(lines, stats["npts"], name)
    with np.errstate(over="ignore"):  # a value beyond float range in m/s² is refused by the caller
        return Stream([Trace(data=data * stats["at2"].factor, header=stats)])


def _header_stats(lines: list[str], name: str) -> dict[str, Any]:
    """The trace header (obspy stats) from the 4 header lines."""
    units, factor = _parse_units(lines[2], name)
    npts, dt = _parse_npts_dt(lines[3], name)
    header = _parse_title(lines[1])
    return {
        "network": "",
        "station": _station_code(header["station"]),
        "location": "",
        "channel": band_code(1.0 / dt) + "N" + _orientation(header["component"]),
        "delta": dt,
        "starttime": UTCDateTime(0),
        "npts": npts,
        "at2": AttribDict({
            "title": lines[0].strip(),
            "event": header["event"],
            "date": header["date"],
            "station": header["station"],
            "component": header["component"],
            "units_in_file": units,
            "units": "m/s2",
            "factor": factor,
            "starttime_in_file": False,
        }),
    }


# --- header lines --------------------------------------------------------------------------


def _parse_units(line: str, name: str) -> tuple[str, float]:
    """Units word of line 3 and its factor to m/s²."""
    found = _UNITS_LINE.match(line)
    if not found:
        raise ValueError(
            f"{name}: line 3: expected 'ACCELERATION TIME SERIES IN UNITS OF <units>', "
            f"got {line.strip()!r}"
        )
    units = found.group(1).rstrip(" .,")
    key = re.sub(r"\s+", "", units).upper()
    if key not in UNIT_FACTORS:
        accepted = ", ".join(sorted({"g", "cm/s2", "gal", "m/s2"}))
        raise ValueError(f"{name}: line 3: unknown units {units!r} (accepted: {accepted})")
    return units.lower() if key == "G" else units, UNIT_FACTORS[key]


def _parse_npts_dt(line: str, name: str) -> tuple[int, float]:
    """NPTS and DT (s) from line 4, in the NGA-West2 or the older form."""
    found = _NPTS_NEW.match(line) or _NPTS_OLD.match(line)
    if not found:
        raise ValueError(
            f"{name}: line 4: expected 'NPTS= <n>, DT= <dt> SEC' or '<n> <dt> NPTS, DT', "
            f"got {line.strip()!r}"
        )
    npts = int(found.group(1))
    dt = float(found.group(2).replace("D", "E").replace("d", "e"))
    if npts < 1:
        raise ValueError(f"{name}: line 4: NPTS = {npts}; a record needs at least one point")
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"{name}: line 4: DT = {found.group(2)} s is not a positive time step")
    return npts, dt


def _parse_title(line: str) -> dict[str, str]:
    """Event, date, station and component from line 2 (``event, date, station, component``).

    The fields are comma-separated; the component is the last, the station the one before
    it. Fewer fields leave the missing ones empty; the line is never an error.
    """
    fields = [f.strip() for f in line.split(",")]
    fields = [f for f in fields if f] or [""]
    parsed = {"event": "", "date": "", "station": "", "component": fields[-1]}
    if len(fields) >= 2:
        parsed["station"] = fields[-2]
    if len(fields) >= 3:
        parsed["event"] = fields[0]
        parsed["date"] = fields[1] if len(fields) >= 4 else ""
    return parsed


def _station_code(station: str) -> str:
    """A SEED station code (1-5 upper-case letters and digits) from the header's station name."""
    return re.sub(r"[^A-Z0-9]", "", station.upper())[:5]


def _orientation(component: str) -> str:
    """SEED orientation code from the header's component (see the package docstring).

    ``0``/``360`` -> ``N``, ``90`` -> ``E``, vertical words (``UP``, ``UD``, ``V`` ...) -> ``Z``;
    any other angle -> ``1`` if nearer the north-south axis, else ``2``; unrecognised -> ``1``.
    """
    word = component.strip().upper()
    if word in _VERTICAL:
        return "Z"
    if word in _EAST:
        return "E"
    if word in _NORTH:
        return "N"
    angle = _angle(word)
    if angle is None:
        return "1"
    angle %= 360.0
    if angle == 0.0:
        return "N"
    if angle == 90.0:
        return "E"
    return "1" if min(angle % 180.0, 180.0 - angle % 180.0) <= 45.0 else "2"


def _angle(word: str) -> float | None:
    """Azimuth in degrees from a component such as ``000``, ``90``, ``N45E`` (None otherwise)."""
    if re.fullmatch(r"\d{1,3}(?:\.\d*)?", word):
        return float(word)
    found = re.fullmatch(r"([NS])(\d{1,2}(?:\.\d*)?)([EW])", word)
    if not found:
        return None
    value = float(found.group(2))
    base = {"NE": value, "SE": 180.0 - value, "SW": 180.0 + value, "NW": 360.0 - value}
    return base[found.group(1) + found.group(3)]


# --- data ----------------------------------------------------------------------------------


def _parse_values(lines: list[str], npts: int, name: str) -> np.ndarray:
    """The values after the 4 header lines; checks they are numbers and that there are NPTS."""
    body = [_FORTRAN_EXPONENT.sub("E", line) for line in lines[4:]]
    try:
        data = np.array(" ".join(body).split(), dtype=np.float64)
    except ValueError:
        data = None
    if data is None or not np.isfinite(data).all():
        _raise_at_bad_value(body, name)
    if data.size == 0:
        raise ValueError(f"{name}: line 4 says NPTS = {npts} but the file holds no values "
                         "after its 4 header lines")
    if data.size != npts:
        last = _last_data_line(body)
        raise ValueError(
            f"{name}: line 4 says NPTS = {npts} but the file holds {data.size} values "
            f"(lines 5-{last}); the file is truncated or its header is wrong"
        )
    return data


def _raise_at_bad_value(body: list[str], name: str) -> None:
    """Raise naming the first line holding a non-numeric or non-finite value."""
    for number, line in enumerate(body, start=5):
        for field in line.split():
            try:
                value = float(field)
            except ValueError:
                raise ValueError(f"{name}: line {number}: {field!r} is not a number") from None
            if not math.isfinite(value):
                raise ValueError(f"{name}: line {number}: non-finite value {field!r}")
    raise AssertionError("unreachable: a bad value was found by numpy")  # pragma: no cover


def _last_data_line(body: list[str]) -> int:
    """1-based number of the last non-blank line (4 if there is none)."""
    for index in range(len(body) - 1, -1, -1):
        if body[index].strip():
            return index + 5
    return 4
