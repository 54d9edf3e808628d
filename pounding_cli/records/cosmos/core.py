"""CSMIP / COSMOS V1 and V2 text: format detection and reading (see the package docstring)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core.util import AttribDict
from ..seed import band_code
from ..textfile import BINARY, read_all, read_head, source_name

G = 9.80665
"""Standard gravity, m/s² per g."""

DETECT_BYTES = 8192
"""How much of a file :func:`_is_cosmos` reads (a V2 channel header is about 3.7 KB)."""

QUANTITIES = ("acceleration", "velocity", "displacement")
_SHORT = {"accel": "acceleration", "veloc": "velocity", "displ": "displacement"}
_INSTRUMENT = {"acceleration": "N", "velocity": "V", "displacement": "D"}
_SI_UNITS = {"acceleration": "m/s2", "velocity": "m/s", "displacement": "m"}
# Factor from the units written in the data-count line (lower case, no spaces) to SI.
_UNIT_FACTORS = {
    "acceleration": {"g": G, "cm/sec2": 0.01, "cm/sec/sec": 0.01, "cm/s2": 0.01, "cm/s/s": 0.01,
                     "cm/sec**2": 0.01, "gal": 0.01, "mm/sec2": 0.001, "mm/s2": 0.001,
                     "m/sec2": 1.0, "m/s2": 1.0, "m/s/s": 1.0},
    "velocity": {"cm/sec": 0.01, "cm/s": 0.01, "mm/sec": 0.001, "mm/s": 0.001, "m/sec": 1.0,
                 "m/s": 1.0},
    "displacement": {"cm": 0.01, "mm": 0.001, "m": 1.0},
}

_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_KIND_LINE = re.compile(r"^\s*(Uncorrected|Corrected)\s+accelerogram\b", re.IGNORECASE)
_END_LINE = re.compile(r"^\s*/&")
# Any line that starts a data block, well formed or not (the strict forms follow).
_COUNT_LIKE = re.compile(
    r"^\s*\d+\s+(?:Accelerogram\s+points\b|points\s+of\s+(?:accel|veloc|displ))", re.IGNORECASE
)
_FORMAT = r"\(\s*(\d*)\s*[FfEe](\d+)\.(\d+)\s*\)"
# V1: " 35430 Accelerogram points at 100 pts/sec in units of g.       Format: (8f9.6)"
_V1_COUNT = re.compile(
    rf"^\s*(\d+)\s+Accelerogram\s+points\s+at\s+(\d+(?:\.\d*)?|\.\d+)\s+pts/sec\s+"
    rf"in\s+units\s+of\s+(\S+?)\.?\s+Format\s*:?\s*{_FORMAT}", re.IGNORECASE)
# V2: " 12000 points of accel data equally spaced at  .005 sec, in cm/sec2. (8f10.6)"
_V2_COUNT = re.compile(
    rf"^\s*(\d+)\s+points\s+of\s+(accel|veloc|displ)\w*\s+data\s+equally\s+spaced\s+at\s+"
    rf"(\d+(?:\.\d*)?|\.\d+)\s+secs?\s*,?\s*in\s+(\S+?)\.?\s+{_FORMAT}", re.IGNORECASE)
_EXPECTED = {
    1: "'<n> Accelerogram points at <rate> pts/sec in units of <units>. Format: (<k>f<w>.<d>)'",
    2: "'<n> points of accel|veloc|displ data equally spaced at <dt> sec, in <units>. "
       "(<k>f<w>.<d>)'",
}
_START_TIME = re.compile(
    r"Start\s+time:\s*(\d{1,2})/(\d{1,2})/(\d{2,4}),?\s+(\d{1,2}):(\d{1,2}):(\d{1,2}(?:\.\d*)?)"
    r"\s*([A-Za-z]{1,4})?\s*(?:\(([^)]*)\))?", re.IGNORECASE)
_CHANNEL = re.compile(r"\bChan\s+(\d+)\s*:\s*(?:(\d+(?:\.\d*)?)\s*Deg\b|(Up|Down|Dwn|Vert\w*)\b)?",
                      re.IGNORECASE)
# A record id such as "38457511.CI.CCC.--.HN": event.network.station.location.band+instrument.
_SEED_ID = re.compile(
    r"(?:^|\s)[\w-]*\.([A-Z0-9]{1,2})\.([A-Z0-9]{1,5})\.([A-Z0-9-]{0,2})\.([A-Z0-9]{2})\b"
)
_STATION = re.compile(r"\bStation\s+(?:Id\.?|No\.?)\s*([A-Za-z0-9]+)")
_COORDS = re.compile(r"(\d+(?:\.\d*)?)\s*([NS])\s*,\s*(\d+(?:\.\d*)?)\s*([EW])\b")


def _is_cosmos(filename: Any) -> bool:
    """True if ``filename`` (path or file object) looks like a CSMIP / COSMOS V1 or V2 text file.

    Reads at most :data:`DETECT_BYTES` bytes, restores the position of a file object and
    returns False rather than raising. The first non-blank line must start with
    ``Uncorrected Accelerogram`` or ``Corrected accelerogram``, and the first 8 KB must hold
    a data-count line (``... Accelerogram points at ...`` or ``... points of accel data ...``)
    or the word ``CSMIP``; the reader then checks the file strictly.
    """
    try:
        head = read_head(filename, DETECT_BYTES)
    except Exception:  # noqa: BLE001 - detection must never raise
        return False
    if head is None or BINARY.search(head):
        return False
    lines = _LINE_BREAK.split(head)
    first = next((line for line in lines if line.strip()), "")
    if not _KIND_LINE.match(first):
        return False
    return "CSMIP" in head.upper() or any(_COUNT_LIKE.match(line) for line in lines)


def _read_cosmos(filename: Any, headonly: bool = False, quantities: Any = ("acceleration",),
                 **kwargs: Any) -> Stream:
    """Read every channel of a CSMIP / COSMOS V1 or V2 text file into a Stream (see the package).

    ``filename`` is a path or an open file object (binary or text, e.g. ``BytesIO``).
    ``quantities`` chooses the traces read from V2 files: ``"acceleration"`` (the default),
    ``"velocity"``, ``"displacement"``, an iterable of them, or ``"all"``; V1 files hold
    acceleration only. With ``headonly=True`` the traces hold their headers but no data.
    Other keyword arguments passed by :func:`obspy.read` are ignored. Raises ValueError
    naming the file and the line for anything that is not a valid file.
    """
    name = source_name(filename)
    wanted = _wanted_quantities(quantities, name)
    lines = _LINE_BREAK.split(read_all(filename, name, "a CSMIP/COSMOS text file"))
    channels: list[_Channel] = []
    index = _skip_blank(lines, 0)
    if index == len(lines):
        raise ValueError(f"{name}: empty file; expected a CSMIP/COSMOS channel header")
    while index < len(lines):
        channel, index = _parse_channel(lines, index, name, headonly, len(channels) + 1)
        channels.append(channel)
        index = _skip_blank(lines, index)
    traces = [_trace(channel, block, headonly) for channel in channels
              for block in channel.blocks if block.quantity in wanted]
    _make_ids_unique(traces)
    return Stream(traces)


# --- parsing ---------------------------------------------------------------------------------


@dataclass
class _Block:
    """One data block of a channel: a quantity, its count line and its values (file units)."""

    quantity: str
    count: int
    delta: float
    units: str
    factor: float
    line: int  # 1-based number of the data-count line
    values: np.ndarray | None = None


@dataclass
class _Channel:
    """One channel: what its header says, and its data blocks."""

    volume: int
    number: int
    orientation: str  # as written: "90", "360", "Up", or "" if the header does not say
    azimuth: float | str | None
    dip: float | None
    start: UTCDateTime | None
    start_text: str
    time_quality: str
    network: str
    station: str
    location: str
    seed_id: str
    station_name: str
    latitude: float | None
    longitude: float | None
    line: int  # 1-based number of the channel's first line
    blocks: list[_Block] = field(default_factory=list)


def _parse_channel(lines: list[str], start: int, name: str, headonly: bool,
                   ordinal: int) -> tuple[_Channel, int]:
    """Parse the channel whose first line is ``lines[start]``; return it and the next line index."""
    kind = _KIND_LINE.match(lines[start])
    if not kind:
        raise ValueError(
            f"{name}: line {start + 1}: expected a channel header starting 'Uncorrected "
            f"Accelerogram' (V1) or 'Corrected accelerogram' (V2), got {_show(lines[start])}"
        )
    volume = 1 if kind.group(1).lower() == "uncorrected" else 2
    index = _find_count_line(lines, start, name, volume)
    channel = _parse_header(lines[start:index], start, volume, ordinal)
    while index < len(lines) and _COUNT_LIKE.match(lines[index]):
        block, index = _parse_block(lines, index, name, channel, headonly)
        channel.blocks.append(block)
    return channel, _end_of_channel(lines, index, name, channel)


def _find_count_line(lines: list[str], start: int, name: str, volume: int) -> int:
    """Index of the first data-count line after the channel header starting at ``start``."""
    for index in range(start + 1, len(lines)):
        if _COUNT_LIKE.match(lines[index]):
            return index
        if _END_LINE.match(lines[index]):
            raise ValueError(f"{name}: line {index + 1}: end-of-channel line before the data-count "
                             f"line of the channel starting on line {start + 1}")
    raise ValueError(f"{name}: line {start + 1}: the channel starting here has no data-count line "
                     f"({_EXPECTED[volume]}) before the end of the file")


def _parse_header(header: list[str], start: int, volume: int, ordinal: int) -> _Channel:
    """What the header lines of a channel say (missing items are left empty, never an error)."""
    text = "\n".join(header)
    number, orientation, azimuth, dip = _channel_orientation(text, ordinal)
    start_time, start_text, quality = _start_time(text)
    network = station = location = seed_id = ""
    if found := _SEED_ID.search(text):
        network, station = found.group(1), found.group(2)
        location, seed_id = found.group(3).replace("-", ""), found.group(0).strip()
    code, station_name, latitude, longitude = _station(header)
    return _Channel(volume, number, orientation, azimuth, dip, start_time, start_text, quality,
                    network, station or code, location, seed_id, station_name, latitude,
                    longitude, start + 1)


def _channel_orientation(text: str,
                         ordinal: int) -> tuple[int, str, float | str | None, float | None]:
    """Channel number, orientation as written, azimuth and dip from ``Chan  1:  90 Deg``/``Up``."""
    found = _CHANNEL.search(text)
    if not found:
        return ordinal, "", None, None
    number = int(found.group(1))
    if found.group(2) is not None:
        return number, found.group(2), float(found.group(2)), 0.0
    if found.group(3) is not None:
        word = found.group(3).capitalize()
        down = word in ("Down", "Dwn")
        return number, word, "Down" if down else "Up", 90.0 if down else -90.0
    return number, "", None, None


def _start_time(text: str) -> tuple[UTCDateTime | None, str, str]:
    """Start time (None unless given in UTC/GMT), the text as written, and the clock quality."""
    found = _START_TIME.search(text)
    if not found:
        return None, "", ""
    quality = (found.group(8) or "").strip()
    in_utc = (found.group(7) or "").upper() in ("UTC", "GMT", "UT", "Z")
    return (_utc(found) if in_utc else None), found.group(0).strip(), quality


def _utc(found: re.Match[str]) -> UTCDateTime:
    """UTC time from a start-time match; two-digit years 70-99 are 19yy, 00-69 are 20yy."""
    month, day, year, hour, minute = (int(found.group(i)) for i in range(1, 6))
    if year < 100:
        year += 1900 if year >= 70 else 2000
    return UTCDateTime(year, month, day, hour, minute) + float(found.group(6))


def _station(header: list[str]) -> tuple[str, str, float | None, float | None]:
    """Station code, station name (next line) and coordinates from ``Station Id./No.``."""
    for position, line in enumerate(header):
        if found := _STATION.search(line):
            name = header[position + 1][:40].strip() if position + 1 < len(header) else ""
            latitude = longitude = None
            if coords := _COORDS.search(line):
                latitude = float(coords.group(1)) * (-1.0 if coords.group(2) == "S" else 1.0)
                longitude = float(coords.group(3)) * (-1.0 if coords.group(4) == "W" else 1.0)
            return found.group(1).upper()[:5], name, latitude, longitude
    return "", "", None, None


def _parse_block(lines: list[str], index: int, name: str, channel: _Channel,
                 headonly: bool) -> tuple[_Block, int]:
    """Parse the data-count line ``lines[index]`` and its values; return block and next index."""
    quantity, count, delta, units, per_line, width = _count_line(lines[index], index, name,
                                                                 channel.volume)
    if not channel.blocks and quantity != "acceleration":
        raise ValueError(f"{name}: line {index + 1}: the first data block of channel "
                         f"{channel.number} is {quantity}, not acceleration")
    if any(block.quantity == quantity for block in channel.blocks):
        raise ValueError(f"{name}: line {index + 1}: a second {quantity} block in channel "
                         f"{channel.number}")
    factor = _unit_factor(quantity, units, name, index)
    block = _Block(quantity, count, delta, units, factor, index + 1)
    n_lines = -(-count // per_line)
    _check_block_lines(lines, index, n_lines, block, name)
    if not headonly:
        block.values = _fixed_width_values(lines, index + 1, count, per_line, width, name)
    return block, index + 1 + n_lines


def _count_line(line: str, index: int, name: str,
                volume: int) -> tuple[str, int, float, str, int, int]:
    """Quantity, count, sample interval (s), units, values per line and field width."""
    found = (_V1_COUNT if volume == 1 else _V2_COUNT).match(line)
    if not found:
        raise ValueError(f"{name}: line {index + 1}: malformed data-count line; expected "
                         f"{_EXPECTED[volume]}, got {_show(line)}")
    if volume == 1:
        (count, rate, units), fmt, quantity = found.groups()[:3], found.groups()[3:], "accel"
        if not float(rate) > 0.0:
            raise ValueError(f"{name}: line {index + 1}: sampling rate {rate} pts/sec "
                             "is not positive")
        delta = 1.0 / float(rate)
    else:
        (count, quantity, step, units), fmt = found.groups()[:4], found.groups()[4:]
        if not float(step) > 0.0:
            raise ValueError(f"{name}: line {index + 1}: sample interval {step} s is not positive")
        delta = float(step)
    per_line, width = int(fmt[0] or 1), int(fmt[1])
    if int(count) < 1 or per_line < 1 or width < 1:
        raise ValueError(f"{name}: line {index + 1}: {count} points in format "
                         f"({fmt[0]}f{fmt[1]}.{fmt[2]}); expected at least one point, one value "
                         "per line and a field width of one column")
    return _SHORT[quantity.lower()], int(count), delta, units, per_line, width


def _unit_factor(quantity: str, units: str, name: str, index: int) -> float:
    """Factor from ``units`` to SI for ``quantity``, or raise naming the line."""
    key = units.strip().lower().replace(" ", "")
    try:
        return _UNIT_FACTORS[quantity][key]
    except KeyError:
        accepted = ", ".join(_UNIT_FACTORS[quantity])
        raise ValueError(f"{name}: line {index + 1}: unknown {quantity} units {units!r} "
                         f"(accepted: {accepted})") from None


def _check_block_lines(lines: list[str], index: int, n_lines: int, block: _Block,
                       name: str) -> None:
    """Raise if the file ends, or a header/end line comes, before the block's last data line."""
    for offset in range(1, n_lines + 1):
        position = index + offset
        if position >= len(lines) or (not lines[position].strip()
                                      and not any(rest.strip() for rest in lines[position:])):
            raise ValueError(
                f"{name}: line {position + 1}: the file ends after {offset - 1} of the "
                f"{n_lines} data lines announced on line {block.line} ({block.count} points); "
                "the file is truncated"
            )
        line = lines[position]
        if _END_LINE.match(line) or _COUNT_LIKE.match(line) or _KIND_LINE.match(line):
            raise ValueError(
                f"{name}: line {position + 1}: expected data line {offset} of {n_lines} "
                f"({block.count} {block.quantity} points announced on line {block.line}), "
                f"got {_show(line)}; the header's point count is wrong or data are missing"
            )


def _fixed_width_values(lines: list[str], first: int, count: int, per_line: int, width: int,
                        name: str) -> np.ndarray:
    """Read ``count`` Fortran fixed-width values, ``per_line`` per line of ``width`` columns.

    Fields are cut by column, not by white space: neighbouring values may touch
    (``1.171726-12.626200``). A blank field inside the count, text past the last field
    or a field that is not a finite number is an error naming the line and columns.
    """
    values = np.empty(count, dtype=np.float64)
    filled = 0
    number = first
    while filled < count:
        line = lines[number]
        n = min(per_line, count - filled)
        try:
            values[filled:filled + n] = [float(line[k * width:(k + 1) * width]) for k in range(n)]
        except ValueError:
            _raise_bad_field(line, number, n, width, name)
        if line[n * width:].strip():
            where = "after the last value" if n == count - filled else f"after {n} values"
            raise ValueError(f"{name}: line {number + 1}: unexpected text "
                             f"{_show(line[n * width:])} {where} (columns {n * width + 1}-); "
                             "the point count or the format is wrong")
        filled += n
        number += 1
    if not np.isfinite(values).all():
        bad = int(np.flatnonzero(~np.isfinite(values))[0])
        raise ValueError(f"{name}: line {first + bad // per_line + 1}: non-finite value")
    return values


def _raise_bad_field(line: str, number: int, n: int, width: int, name: str) -> None:
    """Raise naming the first of ``n`` fields of ``line`` that is not a number."""
    for k in range(n):
        text = line[k * width:(k + 1) * width]
        try:
            float(text)
        except ValueError:
            what = "is missing (blank)" if not text.strip() else f"{text.strip()!r} is not a number"
            columns = f"columns {k * width + 1}-{(k + 1) * width}"
            raise ValueError(f"{name}: line {number + 1}, {columns}: value {k + 1} of {n} "
                             f"{what}") from None
    raise AssertionError("unreachable")  # pragma: no cover


def _end_of_channel(lines: list[str], index: int, name: str, channel: _Channel) -> int:
    """Index after the channel's ``/&`` end line (the line is optional at the end of the file)."""
    if index < len(lines) and _END_LINE.match(lines[index]):
        return index + 1
    if index >= len(lines) or not lines[index].strip() or _KIND_LINE.match(lines[index]):
        return index
    last = channel.blocks[-1]
    raise ValueError(
        f"{name}: line {index + 1}: expected the end of channel {channel.number} ('/&' line) "
        f"after the {last.count} {last.quantity} points announced on line {last.line}, "
        f"got {_show(lines[index])}; "
        "the file holds more values than its header says"
    )


# --- traces ----------------------------------------------------------------------------------


def _trace(channel: _Channel, block: _Block, headonly: bool) -> Trace:
    """An obspy trace in SI units for one block of a channel."""
    stats = {
        "network": channel.network,
        "station": channel.station,
        "location": channel.location,
        "channel": (band_code(1.0 / block.delta) + _INSTRUMENT[block.quantity]
                    + _orientation(channel)),
        "delta": block.delta,
        "starttime": channel.start if channel.start is not None else UTCDateTime(0),
        "npts": block.count,
        "cosmos": AttribDict({
            "volume": channel.volume,
            "processing": "uncorrected" if channel.volume == 1 else "corrected",
            "channel_number": channel.number,
            "azimuth": channel.azimuth,
            "dip": channel.dip,
            "orientation": channel.orientation,
            "quantity": block.quantity,
            "units_in_file": block.units,
            "units": _SI_UNITS[block.quantity],
            "factor": block.factor,
            "starttime_in_file": channel.start is not None,
            "start_time_text": channel.start_text,
            "time_quality": channel.time_quality,
            "seed_id": channel.seed_id,
            "station_name": channel.station_name,
            "latitude": channel.latitude,
            "longitude": channel.longitude,
            "header_line": channel.line,
            "data_line": block.line,
        }),
    }
    if headonly or block.values is None:
        return Trace(header=stats)
    with np.errstate(over="ignore"):  # a value beyond float range in SI is refused by the caller
        return Trace(data=block.values * block.factor, header=stats)


def _orientation(channel: _Channel) -> str:
    """SEED orientation code: N (0/360 deg), E (90), Z (Up/Down), else 1 or 2 by nearest axis."""
    if isinstance(channel.azimuth, str):
        return "Z"
    if channel.azimuth is None:
        return "1"
    angle = channel.azimuth % 360.0
    if angle == 0.0:
        return "N"
    if angle == 90.0:
        return "E"
    return "1" if min(angle % 180.0, 180.0 - angle % 180.0) <= 45.0 else "2"


def _make_ids_unique(traces: list[Trace]) -> None:
    """If two traces share an id (a building array), set every location to the channel number."""
    ids = [tr.id for tr in traces]
    if len(set(ids)) == len(ids):
        return
    for tr in traces:
        tr.stats.location = f"{tr.stats.cosmos.channel_number % 100:02d}"


# --- helpers ---------------------------------------------------------------------------------


def _wanted_quantities(quantities: Any, name: str) -> set[str]:
    """The set of quantities asked for (``"all"``, one name, or an iterable of names)."""
    if quantities is None:
        return {"acceleration"}
    items = [quantities] if isinstance(quantities, str) else list(quantities)
    wanted = set()
    for item in items:
        key = str(item).strip().lower()
        if key == "all":
            wanted.update(QUANTITIES)
        elif key in QUANTITIES or key in _SHORT:
            wanted.add(_SHORT.get(key, key))
        else:
            raise ValueError(f"{name}: unknown quantity {item!r}; choose from "
                             f"{', '.join(QUANTITIES)} or 'all'")
    return wanted


def _skip_blank(lines: list[str], index: int) -> int:
    """Index of the first non-blank line at or after ``index`` (len(lines) if none)."""
    while index < len(lines) and not lines[index].strip():
        index += 1
    return index


def _show(text: str, limit: int = 60) -> str:
    """``text`` stripped and shortened for a message."""
    text = text.strip()
    return repr(text if len(text) <= limit else text[:limit] + "...")


