"""Convert the 2019 Ridgecrest CI.CCC record (CSMIP/COSMOS V1 text) to a processed MiniSEED file.

Standalone: ``python inputs/records/make_ridgecrest_mseed.py [--source RAW] [--output MSEED]``,
with pound installed (``obspy.read`` reads the COSMOS file through pound's reader plugin, and
the Arias intensity and significant duration are pound's own, ``pounding_cli.records.metrics``).
Reads the horizontal channels 1 (90 deg, East -> HNE) and 2 (360 deg, North -> HNN)
of ``CICCC.RAW``, corrects and band-passes them, trims them to the strong-motion
window and writes them in m/s² as FLOAT64 MiniSEED. See README.md beside this
script for every step and its parameters. Output is deterministic.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import obspy
from obspy import Stream, Trace, UTCDateTime

from pounding_cli.records.metrics import Metrics, metrics

HERE = Path(__file__).resolve().parent
DEFAULT_SOURCE = HERE / "CICCC.RAW"
DEFAULT_OUTPUT = HERE / "ridgecrest2019_ccc.mseed"

CHANNELS = {1: ("90", "HNE"), 2: ("360", "HNN")}  # COSMOS channel -> (azimuth, deg; SEED code)
TAPER_FRACTION = 0.05  # cosine taper before filtering, fraction of the length at each end
FREQMIN, FREQMAX, CORNERS = 0.1, 25.0, 4  # band-pass, Hz; poles (zero-phase)
PRE_EVENT, POST_EVENT = 5.0, 15.0  # s kept before the 5 % time and after the 95 % time
END_TAPER = 1.0  # s of cosine taper at each end of the trimmed window


def read_channels(path: Path) -> Stream:
    """The horizontal channels 1 (HNE) and 2 (HNN) of the COSMOS V1 file, in m/s².

    ``obspy.read`` finds pound's COSMOS reader through its entry points (pound must be
    installed): it parses the fixed-width data blocks, checks each channel's point count and
    converts g to m/s² (x 9.80665). Only the standard header is kept.
    """
    stream = obspy.read(str(path), format="COSMOS")
    out = Stream()
    for number, (azimuth, code) in CHANNELS.items():
        found = [tr for tr in stream if tr.stats.cosmos.channel_number == number]
        if len(found) != 1 or found[0].stats.cosmos.orientation != azimuth or found[0].stats.channel != code:
            raise ValueError(f"{path}: channel {number} should have azimuth {azimuth} deg ({code})")
        tr = found[0]
        if tr.stats.cosmos.units_in_file != "g":
            raise ValueError(f"channel {number}: expected units of g, found {tr.stats.cosmos.units_in_file!r}")
        header = {"network": "CI", "station": "CCC", "location": "", "channel": code,
                  "sampling_rate": tr.stats.sampling_rate, "starttime": tr.stats.starttime}
        out.append(Trace(data=tr.data, header=header))
    return out


def correct(trace: Trace) -> None:
    """Demean, remove a linear trend, taper 5 % at each end and band-pass 0.1-25 Hz (zero phase)."""
    trace.detrend("demean")
    trace.detrend("linear")
    trace.taper(max_percentage=TAPER_FRACTION, type="cosine")
    trace.filter("bandpass", freqmin=FREQMIN, freqmax=FREQMAX, corners=CORNERS, zerophase=True)


def trace_metrics(trace: Trace) -> Metrics:
    """pound's intensity measures of a trace in m/s² (`pound record` prints the same): Arias
    intensity of the acceleration taken as linear between samples, integrated exactly, and
    the 5 % and 95 % Arias times, interpolated; times in s after the trace's first sample."""
    return metrics(trace.data, trace.stats.delta)


def strong_motion_window(stream: Stream) -> tuple[UTCDateTime, UTCDateTime]:
    """Window from 5 s before the earliest 5 % Arias time to 15 s after the latest 95 % time.

    Both ends are rounded outward to whole seconds after the first sample and kept in the record.
    """
    start = stream[0].stats.starttime
    t5 = min(trace_metrics(tr).t5 for tr in stream)
    t95 = max(trace_metrics(tr).t95 for tr in stream)
    end_limit = min(tr.stats.endtime for tr in stream) - start
    first = max(0.0, math.floor(t5 - PRE_EVENT))
    last = min(float(math.floor(end_limit)), math.ceil(t95 + POST_EVENT))
    return start + first, start + last


def corrected(stream: Stream) -> Stream:
    """Corrected, band-passed HNE/HNN stream in m/s², cut to the span both channels cover."""
    stream = stream.copy()
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


def report(full: Stream, shipped: Stream) -> None:
    """Print the window, then per channel pound's measures of the full corrected record (they
    choose the window) and of the shipped one (what `pound record` prints for the file)."""
    origin, first = full[0].stats.starttime, shipped[0].stats
    print(f"window: {first.starttime} to {first.endtime} "
          f"({first.starttime - origin:g}-{first.endtime - origin:g} s after the first raw sample; "
          f"{first.npts} points at {first.sampling_rate:g} Hz)")
    for whole, trace in zip(full, shipped, strict=True):
        w, m = trace_metrics(whole), trace_metrics(trace)
        print(f"{trace.id}: full corrected record: D5-95 {w.significant_duration:.2f} s ({w.t5:.2f}-{w.t95:.2f} s "
              f"after the first raw sample), Arias intensity {w.arias_intensity:.3f} m/s; shipped window: "
              f"PGA {m.pga_g:.4f} g at {m.pga_time:.2f} s, D5-95 {m.significant_duration:.2f} s "
              f"({m.t5:.2f}-{m.t95:.2f} s), Arias intensity {m.arias_intensity:.3f} m/s")


def main(argv: list[str] | None = None) -> None:
    """Parse the arguments, convert the record and write the MiniSEED file."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, default=DEFAULT_SOURCE, help="CICCC.RAW, COSMOS V1")
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT, help="MiniSEED to write")
    args = parser.parse_args(argv)
    if not args.source.is_file():
        parser.error(f"no such file: {args.source.resolve()}")
    full = corrected(read_channels(args.source.resolve()))
    shipped = windowed(full)
    shipped.write(str(args.output), format="MSEED", encoding="FLOAT64")
    report(full, shipped)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
