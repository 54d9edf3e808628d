"""Write the small synthetic record files beside this script (run: ``python make_synthetic_records.py``).

Every value and header field is invented here; only the layouts follow the real formats
(PEER NGA ``.AT2``; CSMIP V1 as in USGS's CICCC.RAW; CSMIP V2 as in the CE89146.V2 and
CIWLT.V2 test files of USGS gmprocess). The tests import the ``*_fields`` functions to
know the exact text of every value, and check that this script reproduces the files.
"""

from __future__ import annotations

import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
AT2 = HERE / "synthetic.AT2"
V1 = HERE / "synthetic_2ch.V1"
V2 = HERE / "synthetic_2ch.V2"

AT2_NPTS = 23
V1_CHANNELS = {1: ("360 Deg", 21), 2: (" Up", 19)}  # channel -> (orientation text, points)
V2_CHANNELS = {1: (" 90 Deg", 20), 2: (" Up", 20)}
V2_QUANTITIES = (("accel", "cm/sec2.", 6), ("veloc", "cm/sec. ", 7), ("displ", "cm.     ", 7))


def fortran_f(value: float, width: int, decimals: int) -> str:
    """``value`` as Fortran ``F<width>.<decimals>`` writes it in CSMIP files (no leading zero)."""
    text = f"{value:.{decimals}f}"
    if text.startswith("0."):
        text = text[1:]
    elif text.startswith("-0."):
        text = "-" + text[2:]
    if len(text) > width:
        raise ValueError(f"{value} does not fit F{width}.{decimals}")
    return text.rjust(width)


def fortran_e(value: float) -> str:
    """``value`` as PEER's ``E15.7`` (``  -.1416764E-03``)."""
    if value == 0.0:
        return "   .0000000E+00"
    exponent = math.floor(math.log10(abs(value))) + 1
    mantissa = round(abs(value) / 10.0**exponent, 7)
    if mantissa >= 1.0:
        mantissa, exponent = mantissa / 10.0, exponent + 1
    text = ("-" if value < 0 else "") + f"{mantissa:.7f}"[1:] + f"E{exponent:+03d}"
    return text.rjust(15)


def at2_fields() -> list[str]:
    """The 23 values of synthetic.AT2 (g), as written."""
    return [fortran_e(0.5 * math.sin(0.7 * k) * math.exp(-0.05 * k) * (1 if k % 3 else -1))
            for k in range(AT2_NPTS)]


def v1_fields(channel: int) -> list[str]:
    """The values (g) of a channel of synthetic_2ch.V1, as written (F9.6).

    Sample 5 of channel 1 and samples 4 and 5 of channel 2 fill all 9 columns, so they
    touch their neighbours, as large values do in real files.
    """
    count = V1_CHANNELS[channel][1]
    values = [round(0.01 * channel * math.sin(0.9 * k + channel), 6) for k in range(count)]
    values[5] = -1.234567 * (1 if channel == 1 else -1)
    if channel == 2:
        values[4] = -2.5
    return [fortran_f(v, 9, 6) for v in values]


def v2_fields(channel: int, quantity: str) -> list[str]:
    """The values of one block of synthetic_2ch.V2 as written (accel F10.6, veloc/displ F10.7)."""
    count = V2_CHANNELS[channel][1]
    scale = {"accel": 40.0, "veloc": 2.0, "displ": 0.1}[quantity]
    decimals = 6 if quantity == "accel" else 7
    values = [round(scale * channel * math.cos(0.6 * k) * math.exp(-0.02 * k), decimals)
              for k in range(count)]
    if quantity == "accel":  # touching values, as in real V2 files: " 1.171726-12.626200 -7.202959"
        values[9:12] = [1.171726, -12.6262, -7.202959]
    return [fortran_f(v, 10, decimals) for v in values]


def _peak(fields: list[str], delta: float) -> tuple[float, float]:
    """Largest absolute value of ``fields`` (signed) and its time, s."""
    index = max(range(len(fields)), key=lambda i: abs(float(fields[i])))
    return float(fields[index]), index * delta


def data_lines(fields: list[str], per_line: int = 8) -> list[str]:
    """Fixed-width fields joined ``per_line`` to a line."""
    return ["".join(fields[i:i + per_line]) for i in range(0, len(fields), per_line)]


def write_at2() -> str:
    """Text of synthetic.AT2 (NGA-West2 header form)."""
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Synthetic Test Quake, 3/14/2015, SYNTH STATION 7, 90",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS=   {AT2_NPTS:4d}, DT=   .0100 SEC,",
    ]
    fields = at2_fields()
    lines += ["".join(fields[i:i + 5]) for i in range(0, len(fields), 5)]
    return "\n".join(lines) + "\n"


def _ints(values: list[int]) -> list[str]:
    """``values`` in ``16i5`` lines."""
    return ["".join(f"{v:5d}" for v in values[i:i + 16]) for i in range(0, len(values), 16)]


def _reals(values: list[float]) -> list[str]:
    """``values`` in ``8f10`` lines (F10.7, or F10.5 for larger numbers, as CSMIP writes them)."""
    return ["".join(fortran_f(v, 10, 7 if abs(v) < 10 else 5) for v in values[i:i + 8])
            for i in range(0, len(values), 8)]


def write_v1() -> str:
    """Text of synthetic_2ch.V1: two channels at 200 pts/sec, in g, CRLF line endings."""
    lines: list[str] = []
    for channel, (orientation, count) in V1_CHANNELS.items():
        fields = v1_fields(channel)
        peak = max(fields, key=lambda f: abs(float(f)))
        lines += [
            "Uncorrected Accelerogram Data             Processed: 03/15/15, TEST  synth1     ",
            "Rcrd of Sat Mar 14, 2015 04:05:06.0 PDT               (Synthetic, CSMIP layout)  ",
            "                                        (Origin:  Synthetic test record)        ",
            "99999999.XX.SYN.--.HN                Start time:  3/14/15, 11:05:06.5 UTC (GPS) ",
            "Station Id. SYN     37.500N, 122.250W    Synth   s/n 0001  (2 Chns of  2 at Sta)",
            "Synthetic Station, Test Road             TEST   Data: Acceleration              ",
            f"Chan  {channel}: {orientation:<71}",
            "Rcrd of Sat Mar 14, 2015 04:05:06.0 PDT    Sat Mar 14, 2015 04:05:06.0 PDT      ",
            "Hypocenter:  Synthetic.                      ML:  Synthetic.                    ",
            "Instr Period =  .0050 sec,  Damping =  .707,  Sensitivity = 1.00 v/g  (Nominal) ",
            f"No. of Points = {count:6d}  Record Length ={count / 200:7.3f} sec   at 200 Samples/sec  ",
            f"Units of uncor data are sec and g.         Max  = {float(peak):6.3f} g.               ",
            "RMS calc for complete record =        .   Chn. metadata effective date:         ",
        ]
        lines += _ints([channel, 200, channel, 2, 2] + [-999] * 95)
        lines += _reals([0.005, 0.707, count / 200.0] + [-999.0] * 47)
        lines.append(f"{count:6d} Accelerogram points at 200 pts/sec in units of g.       Format: (8f9.6)  ")
        lines += data_lines(fields)
        lines.append(f"/&  ----------  End of Data for Station Channel   {channel}  ----------")
    return "\r\n".join(lines) + "\r\n"


def write_v2() -> str:
    """Text of synthetic_2ch.V2: two channels, accel/veloc/displ at .005 s, cm units."""
    lines: list[str] = []
    for channel, (orientation, count) in V2_CHANNELS.items():
        chan = f"Chan  {channel}: {orientation}"
        peaks = {q: _peak(v2_fields(channel, q), 0.005) for q, _, _ in V2_QUANTITIES}
        lines += [
            f"Corrected accelerogram   99999-S0001-15073.01       {chan:<17}     from   ",
            "Uncorrected Accelerogram Data             Processed: 03/15/15, TEST  synth2     ",
            "Record of Sat Mar 14, 2015 04:05:06.0 PDT             (Synthetic, CSMIP layout)  ",
            "CSMIP layout, synthetic values          (Origin:  Synthetic test record)        ",
            "99999-S0001-15073.01                 Start time:  3/14/15, 11:05:06.0 UTC (GPS) ",
            "Station No. 99999   37.500N, 122.250W     Synth  s/n 0001  (2 Chns of  2 at Sta)",
            "Synthetic Free Field                      TEST                                  ",
            f"{chan:<80}",
            "Record of Sat Mar 14, 2015 04:05:06.0 PDT    Sat Mar 14, 2015 04:05:06.0 PDT    ",
            "Hypocenter:  Synthetic.                      ML:  Synthetic.                    ",
            "Instr Period =  .0100 sec,  Damping =  .700,  Sensitivity = 1.00  v/g           ",
            f"                        Record length ={count * 0.005:7.3f} sec.                             ",
            "                                     Uncor Max  =   .013 g , at    .045 sec.    ",
            "RMS accel of (uncor) record  =        .   Chn. metadata effective date: 01/01/15",
            "Accelerogram bandpass filtered with 3 dB pts at   .10 and 40.00 cyc/sec         ",
            f"{count:6d} points of instrument- and baseline-corrected accel, veloc and displ data ",
            "At equally-spaced intervals of    .005  sec.                                    ",
            "Peak acceleration = {:9.3f}    cm/sec/sec  at {:8.3f}   sec.                 ".format(*peaks["accel"]),
            "Peak   velocity   = {:9.3f}      cm/sec    at {:8.3f}   sec.                 ".format(*peaks["veloc"]),
            "Peak displacement = {:9.3f}        cm      at {:8.3f}   sec.                 ".format(*peaks["displ"]),
            "Initial velocity  =      .000   cm/sec;   Initial displacement =     .000   cm  ",
            "Record of Sat Mar 14, 2015 04:05:06.0 PDT    Sat Mar 14, 2015 04:05:06.0 PDT    ",
            " " * 80,
            f"99999-S0001-15073.01      Synthetic Free Field    {chan:<30}"[:80],
            " " * 80,
        ]
        lines += _ints([channel, 200, channel, 2, 2] + [-999] * 95)
        lines += _reals([0.01, 0.7, count * 0.005] + [-999.0] * 97)
        for quantity, units, decimals in V2_QUANTITIES:
            fmt = f"(8f10.{decimals})"
            lines.append(f"{count:6d} points of {quantity} data equally spaced at  .005 sec, in {units} {fmt}    ")
            lines += data_lines(v2_fields(channel, quantity))
        lines.append(f"/&  ----------  End of data for channel  {channel}  ----------")
    return "\n".join(lines) + "\n"


def main() -> None:
    """Write the three files (byte-identical on every run)."""
    AT2.write_bytes(write_at2().encode("ascii"))
    V1.write_bytes(write_v1().encode("ascii"))
    V2.write_bytes(write_v2().encode("ascii"))
    for path in (AT2, V1, V2):
        print(f"wrote {path.name} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
