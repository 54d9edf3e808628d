"""Convert the 2019 Ridgecrest CI.CCC record (CSMIP/COSMOS V1 text) to a processed MiniSEED file.

Standalone: ``python inputs/records/make_ridgecrest_mseed.py [--source RAW] [--output MSEED]``.
Reads the horizontal channels 1 (90 deg, East -> HNE) and 2 (360 deg, North -> HNN)
of ``CICCC.RAW``, corrects and band-passes them, trims them to the strong-motion
window and writes them in m/s² as FLOAT64 MiniSEED. See README.md beside this
script for every step and its parameters. Output is deterministic.
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import NamedTuple

import numpy as np
from obspy import Stream, Trace, UTCDateTime

HERE = Path(__file__).resolve().parent
DEFAULT_SOURCE = HERE / "../../../shared/records/ridgecrest2019_ccc/CICCC.RAW"
DEFAULT_OUTPUT = HERE / "ridgecrest2019_ccc.mseed"

G = 9.80665  # standard gravity, m/s² per g
CHANNELS = {1: ("90", "HNE"), 2: ("360", "HNN")}  # COSMOS channel -> (azimuth, deg; SEED code)
TAPER_FRACTION = 0.05  # cosine taper before filtering, fraction of the length at each end
FREQMIN, FREQMAX, CORNERS = 0.1, 25.0, 4  # band-pass, Hz; poles (zero-phase)
ARIAS_START, ARIAS_END = 0.05, 0.95  # fractions of Arias intensity bounding significant duration
PRE_EVENT, POST_EVENT = 5.0, 15.0  # s kept before the 5 % time and after the 95 % time
END_TAPER = 1.0  # s of cosine taper at each end of the trimmed window

_POINTS_LINE = re.compile(
    r"^\s*(\d+)\s+Accelerogram points at\s+(\d+)\s+pts/sec in units of\s+(\S+?)\.\s+"
    r"Format:\s*\((\d+)f(\d+)\.\d+\)"
)
_START_LINE = re.compile(r"Start time:\s*(\d+)/(\d+)/(\d+),\s*(\d+):(\d+):([\d.]+)\s*UTC")
_CHANNEL_LINE = re.compile(r"^Chan\s+(\d+):\s*(\S+)")


class RawChannel(NamedTuple):
    """One channel of a COSMOS V1 file: uncorrected acceleration in the file's units."""

    number: int
    orientation: str  # azimuth in degrees as written ("90", "360") or "Up"
    start: UTCDateTime
    sampling_rate: float  # Hz
    units: str
    data: np.ndarray


def parse_cosmos_v1(path: Path) -> dict[int, RawChannel]:
    """Parse every channel of a CSMIP/COSMOS V1 text file, keyed by channel number."""
    lines = path.read_text(encoding="ascii").splitlines()
    channels: dict[int, RawChannel] = {}
    start = number = orientation = None
    for index, line in enumerate(lines):
        if found := _START_LINE.search(line):
            start = _utc(found)
        elif found := _CHANNEL_LINE.match(line):
            number, orientation = int(found.group(1)), found.group(2)
        elif found := _POINTS_LINE.match(line):
            count, rate, units = int(found.group(1)), float(found.group(2)), found.group(3)
            per_line, width = int(found.group(4)), int(found.group(5))
            data = _fixed_width(lines[index + 1 :], per_line, width)
            if data.size != count:
                raise ValueError(
                    f"{path}: channel {number}: read {data.size} points, header says {count}"
                )
            channels[number] = RawChannel(number, orientation, start, rate, units, data)
    return channels


def _utc(found: re.Match[str]) -> UTCDateTime:
    """UTC time from a ``Start time:  M/DD/YY, HH:MM:SS.S UTC`` match (two-digit years are 20YY)."""
    month, day, year, hour, minute = (int(found.group(i)) for i in range(1, 6))
    return UTCDateTime(2000 + year, month, day, hour, minute) + float(found.group(6))


def _fixed_width(lines: list[str], per_line: int, width: int) -> np.ndarray:
    """Read Fortran ``(per_line f width.d)`` values up to the ``/&`` end-of-data line.

    Fields are cut by column, not by whitespace: neighbouring values may touch.
    """
    values: list[float] = []
    for line in lines:
        if line.startswith("/&"):
            break
        for k in range(per_line):
            field = line[k * width : (k + 1) * width]
            if field.strip():
                values.append(float(field))
    return np.array(values, dtype=np.float64)


def to_trace(channel: RawChannel, code: str) -> Trace:
    """A CI.CCC trace in m/s² from a raw channel in g."""
    if channel.units != "g":
        raise ValueError(f"channel {channel.number}: expected units of g, found {channel.units!r}")
    header = {"network": "CI", "station": "CCC", "location": "", "channel": code,
              "sampling_rate": channel.sampling_rate, "starttime": channel.start}
    return Trace(data=channel.data * G, header=header)


def correct(trace: Trace) -> None:
    """Demean, remove a linear trend, taper 5 % at each end and band-pass 0.1-25 Hz (zero phase)."""
    trace.detrend("demean")
    trace.detrend("linear")
    trace.taper(max_percentage=TAPER_FRACTION, type="cosine")
    trace.filter("bandpass", freqmin=FREQMIN, freqmax=FREQMAX, corners=CORNERS, zerophase=True)


def arias_build_up(trace: Trace) -> np.ndarray:
    """Arias intensity I(t) = pi / (2 g) * integral_0^t a² dt at each sample, m/s (trapezoids)."""
    squared = trace.data**2
    steps = 0.5 * (squared[1:] + squared[:-1]) * trace.stats.delta
    return math.pi / (2.0 * G) * np.concatenate(([0.0], np.cumsum(steps)))


def arias_times(trace: Trace) -> tuple[float, float]:
    """Times (s after the first sample) at which 5 % and 95 % of the Arias intensity is reached."""
    build_up = arias_build_up(trace)
    build_up /= build_up[-1]
    t5 = np.searchsorted(build_up, ARIAS_START) * trace.stats.delta
    t95 = np.searchsorted(build_up, ARIAS_END) * trace.stats.delta
    return float(t5), float(t95)


def strong_motion_window(stream: Stream) -> tuple[UTCDateTime, UTCDateTime]:
    """Window from 5 s before the earliest 5 % Arias time to 15 s after the latest 95 % time.

    Both ends are rounded outward to whole seconds after the first sample and kept in the record.
    """
    start = stream[0].stats.starttime
    t5 = min(arias_times(tr)[0] for tr in stream)
    t95 = max(arias_times(tr)[1] for tr in stream)
    end_limit = min(tr.stats.endtime for tr in stream) - start
    first = max(0.0, math.floor(t5 - PRE_EVENT))
    last = min(float(math.floor(end_limit)), math.ceil(t95 + POST_EVENT))
    return start + first, start + last


def corrected(channels: dict[int, RawChannel]) -> Stream:
    """Corrected, band-passed HNE/HNN stream in m/s², cut to the span both channels cover."""
    stream = Stream([to_trace(channels[n], code) for n, (_, code) in CHANNELS.items()])
    for trace in stream:
        correct(trace)
    stream.trim(max(tr.stats.starttime for tr in stream), min(tr.stats.endtime for tr in stream))
    return stream


def windowed(stream: Stream) -> Stream:
    """The strong-motion window of a corrected stream, with a 1 s cosine taper at each end."""
    out = stream.copy().trim(*strong_motion_window(stream))
    for trace in out:
        trace.taper(max_percentage=None, max_length=END_TAPER, type="cosine")
    return out


def check_orientations(channels: dict[int, RawChannel]) -> None:
    """Refuse a file whose channels 1 and 2 are not the expected East and North azimuths."""
    for number, (azimuth, code) in CHANNELS.items():
        if number not in channels or channels[number].orientation != azimuth:
            raise ValueError(f"channel {number} should have azimuth {azimuth} deg for {code}")


def report(full: Stream, shipped: Stream) -> None:
    """Print the window, the shipped PGA (g) and the D5-95 (s) of the full corrected record."""
    origin, first = full[0].stats.starttime, shipped[0].stats
    print(f"window: {first.starttime} to {first.endtime} "
          f"({first.starttime - origin:g}-{first.endtime - origin:g} s after the first raw sample; "
          f"{first.npts} points at {first.sampling_rate:g} Hz)")
    for whole, trace in zip(full, shipped):
        peak = int(np.argmax(np.abs(trace.data)))
        t5, t95 = arias_times(whole)
        pga, at = abs(trace.data[peak]) / G, peak * trace.stats.delta
        print(f"{trace.id}: PGA {pga:.4f} g at {at:.2f} s into the window; "
              f"D5-95 {t95 - t5:.2f} s ({t5:.2f}-{t95:.2f} s after the first raw sample), "
              f"Arias intensity {arias_build_up(whole)[-1]:.3f} m/s")


def main(argv: list[str] | None = None) -> None:
    """Parse the arguments, convert the record and write the MiniSEED file."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, default=DEFAULT_SOURCE, help="CICCC.RAW, COSMOS V1")
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT, help="MiniSEED to write")
    args = parser.parse_args(argv)
    if not args.source.is_file():
        parser.error(f"no such file: {args.source.resolve()}")
    channels = parse_cosmos_v1(args.source.resolve())
    check_orientations(channels)
    full = corrected(channels)
    shipped = windowed(full)
    shipped.write(str(args.output), format="MSEED", encoding="FLOAT64")
    report(full, shipped)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
