"""The CSMIP / COSMOS V1 and V2 obspy plugin (pounding_cli.records.cosmos): real V1, synthetic V1/V2, errors."""

from __future__ import annotations

import importlib.util
import io
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import obspy
import pytest
from obspy import UTCDateTime

from pounding_cli.errors import RecordReadError
from pounding_cli.records import read_accelerogram
from pounding_cli.records.at2.core import _is_at2
from pounding_cli.records.cosmos.core import G, _is_cosmos, _read_cosmos

REPO = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"
V1 = DATA / "synthetic_2ch.V1"
V2 = DATA / "synthetic_2ch.V2"
RAW = Path(__file__).resolve().parents[2] / "inputs" / "records" / "CICCC.RAW"  # shipped (USGS, CC0)
needs_raw = pytest.mark.skipif(not RAW.is_file(), reason=f"USGS Ridgecrest CICCC.RAW absent: {RAW}")

# Ridgecrest CI.CCC: channel -> (points, azimuth, SEED channel, peak g, time of the peak in s)
RIDGECREST = [(35430, 90.0, "HNE", 0.567, 39.41), (35402, 360.0, "HNN", 0.471, 40.52),
              (35406, "Up", "HNZ", 0.361, 38.93)]


def load_script(path: Path, name: str) -> ModuleType:
    """Import a standalone script by path."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


GEN = load_script(DATA / "make_synthetic_records.py", "make_synthetic_records")


def expected_v1(channel: int) -> np.ndarray:
    """Values of a synthetic V1 channel in m/s² (file values in g, times g)."""
    return np.array([float(field) for field in GEN.v1_fields(channel)]) * G


def expected_v2(channel: int, quantity: str) -> np.ndarray:
    """Values of a synthetic V2 block in SI units (file values in cm/s², cm/s or cm, times 0.01)."""
    return np.array([float(field) for field in GEN.v2_fields(channel, quantity)]) * 0.01


def write(tmp_path: Path, text: str, name: str = "bad.V1") -> Path:
    """Write ``text`` (as given, no newline translation) to tmp_path/name and return the path."""
    path = tmp_path / name
    path.write_bytes(text.encode("latin-1"))
    return path


def lines_of(path: Path) -> list[str]:
    """The lines of a synthetic file without their line ends, to be edited by a test."""
    return path.read_bytes().decode("ascii").replace("\r\n", "\n").split("\n")


def line_index(lines: list[str], start: str, occurrence: int = 1) -> int:
    """Index of the ``occurrence``-th line starting (after spaces) with ``start``."""
    hits = [i for i, line in enumerate(lines) if line.lstrip().startswith(start)]
    return hits[occurrence - 1]


def value_error(path: Path, **kwargs) -> str:
    """The message of the ValueError raised by obspy.read on ``path`` as COSMOS."""
    with pytest.raises(ValueError) as info:
        obspy.read(str(path), format="COSMOS", **kwargs)
    return str(info.value)


# --- the real V1 record: Ridgecrest 2019, CI.CCC (USGS, public domain) ------------------------


@needs_raw
def test_ridgecrest_autodetected_by_obspy():
    stream = obspy.read(str(RAW))  # no format: found through the entry points
    assert len(stream) == 3
    for tr, (npts, azimuth, channel, peak_g, t_peak) in zip(stream, RIDGECREST):
        assert tr.stats._format == "COSMOS"
        assert tr.id == f"CI.CCC..{channel}"
        assert tr.stats.npts == npts and tr.data.size == npts and tr.data.dtype == np.float64
        assert tr.stats.sampling_rate == 100.0
        assert tr.stats.starttime == UTCDateTime("2019-07-06T03:19:37.0Z")
        cosmos = tr.stats.cosmos
        assert cosmos.azimuth == azimuth and cosmos.dip == (-90.0 if azimuth == "Up" else 0.0)
        assert (cosmos.volume, cosmos.processing, cosmos.quantity) == (1, "uncorrected", "acceleration")
        assert (cosmos.units_in_file, cosmos.units, cosmos.factor) == ("g", "m/s2", G)
        assert (cosmos.time_quality, cosmos.seed_id) == ("GPS", "38457511.CI.CCC.--.HN")
        assert cosmos.station_name == "China Lake NWC, Christmas Canyon Rd."
        assert (cosmos.latitude, cosmos.longitude) == (35.525, -117.365)
        peak = int(np.argmax(np.abs(tr.data)))
        assert abs(tr.data[peak]) / G == pytest.approx(peak_g, abs=5e-4)
        assert peak * tr.stats.delta == pytest.approx(t_peak, abs=1e-9)  # the header's "at 39.410 sec"
    assert [tr.stats.cosmos.channel_number for tr in stream] == [1, 2, 3]


def _independent_v1_parse(path: Path) -> list[np.ndarray]:
    """A second, minimal reading of a CSMIP V1 file's data blocks, in g: after each
    "<n> Accelerogram points ... Format: (<k>f<w>.<d>)" line, n values of w columns each."""
    import re

    lines = path.read_text(encoding="ascii").splitlines()
    count_line = re.compile(r"^\s*(\d+)\s+Accelerogram points.*\((\d+)f(\d+)\.\d+\)")
    blocks = []
    for index, line in enumerate(lines):
        found = count_line.match(line)
        if found:
            n, per_line, width = (int(g) for g in found.groups())
            fields = [row[k * width:(k + 1) * width] for row in lines[index + 1:index + 1 + -(-n // per_line)]
                      for k in range(per_line)]
            blocks.append(np.array([float(f) for f in fields if f.strip()][:n]))
    return blocks


@needs_raw
def test_ridgecrest_matches_an_independent_parse():
    """The plugin's values are those of a separate fixed-width parse of the file, times g."""
    for tr, values in zip(obspy.read(str(RAW)), _independent_v1_parse(RAW), strict=True):
        np.testing.assert_array_equal(tr.data, values * G)


@needs_raw
@pytest.mark.parametrize("index", [0, 1, 2])
def test_ridgecrest_through_read_accelerogram(index):
    npts, _, channel, peak_g, _ = RIDGECREST[index]
    rec = read_accelerogram(RAW, trace=channel, units="m/s2")
    assert rec.dt == 0.01 and rec.acceleration.size == npts
    assert np.abs(rec.acceleration).max() / G == pytest.approx(peak_g, abs=5e-4)
    assert rec.source.endswith(f"[CI.CCC..{channel}]") and rec.start_time == "2019-07-06T03:19:37.000000Z"


@needs_raw
def test_ridgecrest_needs_a_trace_choice():
    with pytest.raises(RecordReadError, match=r"holds 3 traces .*CI.CCC..HNE, CI.CCC..HNN, CI.CCC..HNZ"):
        read_accelerogram(RAW, units="m/s2")


@needs_raw
def test_ridgecrest_miniseed_round_trip():
    stream = obspy.read(str(RAW))
    buffer = io.BytesIO()
    stream.write(buffer, format="MSEED", encoding="FLOAT64")
    buffer.seek(0)
    back = obspy.read(buffer)
    assert [tr.id for tr in back] == [tr.id for tr in stream]
    for tr, tr_back in zip(stream, back):
        np.testing.assert_array_equal(tr_back.data, tr.data)
        assert (tr_back.stats.starttime, tr_back.stats.delta) == (tr.stats.starttime, tr.stats.delta)


@needs_raw
def test_ridgecrest_from_open_file_and_bytesio():
    reference = obspy.read(str(RAW))
    with open(RAW, "rb") as handle:
        from_file = obspy.read(handle)
    from_bytes = obspy.read(io.BytesIO(RAW.read_bytes()))
    assert len(reference) == len(from_file) == len(from_bytes) == 3  # the three channels, each way
    for a, b, c in zip(reference, from_file, from_bytes, strict=True):
        assert b.stats == a.stats and c.stats == a.stats
        np.testing.assert_array_equal(b.data, a.data)
        np.testing.assert_array_equal(c.data, a.data)


@needs_raw
def test_ridgecrest_headonly():
    stream = obspy.read(str(RAW), headonly=True)
    assert [tr.stats.npts for tr in stream] == [35430, 35402, 35406]
    assert all(tr.data.size == 0 for tr in stream)


# --- synthetic V1 and V2 ---------------------------------------------------------------------


def same_text(path: Path, text: str) -> bool:
    """True if the file holds ``text``, line ends aside (a checkout may convert them)."""
    return path.read_bytes().replace(b"\r\n", b"\n") == text.encode("ascii").replace(b"\r\n", b"\n")


def test_synthetic_files_are_reproduced_by_their_script():
    assert same_text(V1, GEN.write_v1()) and same_text(V2, GEN.write_v2())
    assert V1.read_bytes().count(b"\r\n") == 64  # the V1 file tests CRLF line ends


def test_synthetic_v1():
    stream = obspy.read(str(V1))
    assert [tr.id for tr in stream] == ["XX.SYN..HNN", "XX.SYN..HNZ"]  # 200 Hz, 360 Deg and Up
    for tr, channel in zip(stream, (1, 2)):
        np.testing.assert_array_equal(tr.data, expected_v1(channel))
        assert tr.stats.delta == 0.005
        assert tr.stats.starttime == UTCDateTime("2015-03-14T11:05:06.5Z")
    assert stream[0].data[5] == -1.234567 * G  # 9 columns wide: touches its neighbours
    assert (stream[1].data[4], stream[1].data[5]) == (-2.5 * G, 1.234567 * G)
    assert [tr.stats.cosmos.azimuth for tr in stream] == [360.0, "Up"]
    assert [tr.stats.cosmos.orientation for tr in stream] == ["360", "Up"]
    assert stream[0].stats.cosmos.station_name == "Synthetic Station, Test Road"
    assert (stream[0].stats.cosmos.header_line, stream[0].stats.cosmos.data_line) == (1, 28)


def test_synthetic_v2_acceleration_by_default():
    stream = obspy.read(str(V2))
    assert [tr.id for tr in stream] == [".99999..HNE", ".99999..HNZ"]  # no record id: station number
    for tr, channel in zip(stream, (1, 2)):
        np.testing.assert_array_equal(tr.data, expected_v2(channel, "accel"))
        assert tr.stats.delta == 0.005 and tr.stats.npts == 20
        assert tr.stats.starttime == UTCDateTime("2015-03-14T11:05:06.0Z")
        cosmos = tr.stats.cosmos
        assert (cosmos.volume, cosmos.processing, cosmos.quantity) == (2, "corrected", "acceleration")
        assert (cosmos.units_in_file, cosmos.units, cosmos.factor) == ("cm/sec2", "m/s2", 0.01)
        assert (cosmos.latitude, cosmos.longitude) == (37.5, -122.25)
    # values that touch in the file: "  1.171726-12.626200 -7.202959"
    np.testing.assert_array_equal(stream[0].data[9:12], np.array([1.171726, -12.6262, -7.202959]) * 0.01)
    assert [tr.stats.cosmos.azimuth for tr in stream] == [90.0, "Up"]


def test_synthetic_v2_all_quantities():
    stream = obspy.read(str(V2), quantities="all")
    assert [tr.stats.channel for tr in stream] == ["HNE", "HVE", "HDE", "HNZ", "HVZ", "HDZ"]
    assert [tr.stats.cosmos.units for tr in stream] == ["m/s2", "m/s", "m"] * 2
    assert [tr.stats.cosmos.units_in_file for tr in stream] == ["cm/sec2", "cm/sec", "cm"] * 2
    for tr in stream:
        channel = tr.stats.cosmos.channel_number
        quantity = tr.stats.cosmos.quantity[:5]
        np.testing.assert_array_equal(tr.data, expected_v2(channel, quantity))


@pytest.mark.parametrize("quantities, channels", [
    ("velocity", ["HVE", "HVZ"]),
    (["accel", "displ"], ["HNE", "HDE", "HNZ", "HDZ"]),
    (("displacement",), ["HDE", "HDZ"]),
    (None, ["HNE", "HNZ"]),
])
def test_synthetic_v2_chosen_quantities(quantities, channels):
    assert [tr.stats.channel for tr in obspy.read(str(V2), quantities=quantities)] == channels


def test_v1_has_acceleration_only():
    assert [tr.stats.channel for tr in obspy.read(str(V1), quantities="all")] == ["HNN", "HNZ"]


def test_unknown_quantity():
    assert "unknown quantity 'jerk'" in value_error(V2, quantities=["accel", "jerk"])


@pytest.mark.parametrize("path", [V1, V2], ids=["V1", "V2"])
def test_path_open_file_and_bytesio_give_the_same_data(path):
    reference = obspy.read(str(path))
    streams = [obspy.read(path), _read_cosmos(path), _read_cosmos(str(path))]
    with open(path, "rb") as handle:
        streams.append(obspy.read(handle))
    with open(path, encoding="ascii", newline="") as handle:
        streams.append(_read_cosmos(handle))
    streams.append(obspy.read(io.BytesIO(path.read_bytes())))
    streams.append(_read_cosmos(io.StringIO(path.read_text())))
    for stream in streams:
        assert [tr.id for tr in stream] == [tr.id for tr in reference]
        for tr, ref in zip(stream, reference):
            np.testing.assert_array_equal(tr.data, ref.data)


@pytest.mark.parametrize("path", [V1, V2], ids=["V1", "V2"])
def test_synthetic_miniseed_round_trip(path):
    stream = obspy.read(str(path), quantities="all")
    buffer = io.BytesIO()
    stream.write(buffer, format="MSEED", encoding="FLOAT64")
    buffer.seek(0)
    for tr, back in zip(stream, obspy.read(buffer)):
        np.testing.assert_array_equal(back.data, tr.data)
        assert back.id == tr.id


def test_headonly():
    stream = obspy.read(str(V2), headonly=True, quantities="all")
    assert [tr.stats.npts for tr in stream] == [20] * 6 and all(tr.data.size == 0 for tr in stream)


def test_same_ids_get_the_channel_number_as_location(tmp_path):
    """A building array: two sensors along the same axis would share an id."""
    text = V1.read_bytes().decode("ascii").replace("Chan  2:  Up", "Chan  2: 360 Deg")
    stream = obspy.read(str(write(tmp_path, text)))
    assert [tr.id for tr in stream] == ["XX.SYN.01.HNN", "XX.SYN.02.HNN"]


@pytest.mark.parametrize("orientation, channel, azimuth, dip", [
    ("180 Deg", "HN1", 180.0, 0.0), ("270 Deg", "HN2", 270.0, 0.0), ("  0 Deg", "HNN", 0.0, 0.0),
    ("315 Deg", "HN1", 315.0, 0.0), ("Down", "HNZ", "Down", 90.0), ("", "HN1", None, None),
])
def test_orientations(tmp_path, orientation, channel, azimuth, dip):
    text = V1.read_bytes().decode("ascii").replace("Chan  1: 360 Deg", f"Chan  1: {orientation}".ljust(16))
    tr = obspy.read(str(write(tmp_path, text)))[0]
    assert (tr.stats.channel, tr.stats.cosmos.azimuth, tr.stats.cosmos.dip) == (channel, azimuth, dip)


@pytest.mark.parametrize("start, expected, in_file", [
    ("Start time:  1/17/94, 12:30:55.0 UTC", UTCDateTime("1994-01-17T12:30:55Z"), True),
    ("Start time:  1/17/1994, 12:30:55.25 GMT", UTCDateTime("1994-01-17T12:30:55.25Z"), True),
    ("Start time:  1/17/94, 04:30:55.0 PST", UTCDateTime(0), False),
    ("Trigger:     unknown", UTCDateTime(0), False),
])
def test_start_times(tmp_path, start, expected, in_file):
    text = V1.read_bytes().decode("ascii").replace("Start time:  3/14/15, 11:05:06.5 UTC (GPS)", start)
    tr = obspy.read(str(write(tmp_path, text)))[0]
    assert tr.stats.starttime == expected and tr.stats.cosmos.starttime_in_file is in_file


# --- detection -------------------------------------------------------------------------------


def other_format_files(tmp_path: Path) -> dict[str, Path]:
    """Files of other formats: MiniSEED, SAC, plain text, AT2, K-NET, COSMOS v1.20, SMC, GeoNet, garbage."""
    tr = obspy.read()[0]
    files = {"mseed": tmp_path / "x.mseed", "sac": tmp_path / "x.sac"}
    tr.write(str(files["mseed"]), format="MSEED")
    tr.write(str(files["sac"]), format="SAC")
    texts = {
        "two_columns": "".join(f"{0.01 * i:.2f} {np.sin(i):.6f}\n" for i in range(50)),
        "one_column": "".join(f"{np.sin(i):.6f}\n" for i in range(50)),
        "empty": "",
        "blank_lines": "\n\n   \n",
        "cosmos_v120": "Corrected acceleration    (Format v01.20 with 13 text lines)\nRecord of ...\n"
                       " 100 Integer-header values follow on  10 lines, Format= (10I8)\n"
                       "   42000 acceleration pts, approx  210 secs, units=cm/sec2(04),Format=(1E15.6)\n",
        "smc": "2 CORRECTED ACCELEROGRAM\n" + "x\n" * 20,
        "geonet_v1a": "Uncorrected accelerogram 20160214_001343_NBLC_20 GNS Science\n"
                      "Site NBLC      43 30 25S  172 43 53E     Cusp file:  20160214_001345_NBLC\n",
        "knet_like": "Origin Time       1995/01/17 05:46:00\nLat.              34.595\n",
    }
    for key, text in texts.items():
        files[key] = write(tmp_path, text, f"{key}.txt")
    files["garbage"] = tmp_path / "garbage.bin"
    files["garbage"].write_bytes(np.random.default_rng(2).integers(0, 256, 20000, dtype=np.uint8).tobytes())
    files["nul_in_v1"] = tmp_path / "nul.V1"
    files["nul_in_v1"].write_bytes(V1.read_bytes().replace(b"Uncorrected Accelerogram Data  ", b"\x00" * 31, 1))
    files["at2"] = DATA / "synthetic.AT2"
    knet = Path(obspy.__file__).parent / "io" / "nied" / "tests" / "data" / "test.knet"
    if knet.is_file():
        files["knet"] = knet
    return files


def test_is_cosmos_false_on_other_formats(tmp_path):
    for key, path in other_format_files(tmp_path).items():
        assert _is_cosmos(str(path)) is False, key
        with open(path, "rb") as handle:
            assert _is_cosmos(handle) is False, key
            assert handle.tell() == 0, key


@pytest.mark.parametrize("thing", [None, 42, b"Corrected accelerogram", "no/such/file.V2", object()])
def test_is_cosmos_false_on_anything_else(thing):
    assert _is_cosmos(thing) is False


def test_is_cosmos_false_on_a_directory(tmp_path):
    assert _is_cosmos(str(tmp_path)) is False


def test_is_cosmos_true_and_rewinds():
    for path in (V1, V2):
        assert _is_cosmos(str(path)) is True and _is_at2(str(path)) is False
        buffer = io.BytesIO(path.read_bytes())
        buffer.seek(0)
        assert _is_cosmos(buffer) is True and buffer.tell() == 0
    if RAW.is_file():
        assert _is_cosmos(str(RAW)) is True and _is_at2(str(RAW)) is False


def test_is_cosmos_reads_only_the_head():
    class CountingBytesIO(io.BytesIO):
        largest = 0

        def read(self, size=-1):
            chunk = super().read(size)
            CountingBytesIO.largest = max(CountingBytesIO.largest, len(chunk))
            return chunk

    assert _is_cosmos(CountingBytesIO(V1.read_bytes() * 200)) is True
    assert CountingBytesIO.largest <= 8192


# --- errors ----------------------------------------------------------------------------------


def edited(lines: list[str], index: int, new: str | None) -> list[str]:
    """A copy of ``lines`` with line ``index`` replaced (or removed if ``new`` is None)."""
    copy = list(lines)
    if new is None:
        del copy[index]
    else:
        copy[index] = new
    return copy


def test_header_count_too_large(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points")
    lines[i] = lines[i].replace("    21 Accel", "    29 Accel")
    path = write(tmp_path, "\n".join(lines))
    message = value_error(path)
    assert str(path) in message
    assert f"line {i + 5}: expected data line 4 of 4 (29 acceleration points announced on line {i + 1})" in message
    assert "'/&" in message and "the header's point count is wrong" in message


def test_header_count_too_small_by_lines(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points")
    lines[i] = lines[i].replace("    21 Accel", "    16 Accel")  # 2 full lines of 8 instead of 3 lines
    message = value_error(write(tmp_path, "\n".join(lines)))
    assert f"line {i + 4}: expected the end of channel 1 ('/&' line) after the 16 acceleration points " \
           f"announced on line {i + 1}" in message
    assert "more values than its header says" in message


def test_header_count_too_small_by_one(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points")
    lines[i] = lines[i].replace("    21 Accel", "    20 Accel")
    message = value_error(write(tmp_path, "\n".join(lines)))
    assert f"line {i + 4}: unexpected text '.001499' after the last value (columns 37-)" in message


def test_v2_count_too_large_meets_the_next_block(tmp_path):
    lines = lines_of(V2)
    i = line_index(lines, "20 points of accel")
    lines[i] = lines[i].replace("    20 points", "    28 points")
    message = value_error(write(tmp_path, "\n".join(lines), "bad.V2"))
    assert f"line {i + 5}: expected data line 4 of 4 (28 acceleration points announced on line {i + 1})" in message
    assert "'20 points of veloc data" in message


def test_non_numeric_value_names_line_and_columns(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points") + 1
    lines[i] = lines[i][:9] + "   abc463" + lines[i][18:]
    path = write(tmp_path, "\n".join(lines))
    message = value_error(path)
    assert f"{path}: line {i + 1}, columns 10-18: value 2 of 8 'abc463' is not a number" in message


def test_blank_value_names_line_and_columns(tmp_path):
    lines = lines_of(V2)
    i = line_index(lines, "20 points of displ", 2) + 1
    lines[i] = lines[i][:20] + " " * 10 + lines[i][30:]
    message = value_error(write(tmp_path, "\n".join(lines), "bad.V2"), quantities="all")
    assert f"line {i + 1}, columns 21-30: value 3 of 8 is missing (blank)" in message


@pytest.mark.parametrize("value", ["      NaN", "      inf"])
def test_non_finite_value(tmp_path, value):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points") + 2
    lines[i] = value + lines[i][9:]
    message = value_error(write(tmp_path, "\n".join(lines)))
    assert f"line {i + 1}: non-finite value" in message


def test_truncated_in_the_data(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "19 Accelerogram points")  # channel 2: 3 data lines
    path = write(tmp_path, "\r\n".join(lines[: i + 2]) + "\r\n")
    message = value_error(path)
    assert str(path) in message
    assert f"line {i + 3}: the file ends after 1 of the 3 data lines announced on line {i + 1} (19 points)" in message
    assert "truncated" in message


def test_truncated_in_the_middle_of_a_line(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "19 Accelerogram points")
    text = "\r\n".join(lines[: i + 3]) + "\r\n" + lines[i + 3][:14]  # last line cut after 1.5 values
    message = value_error(write(tmp_path, text))
    assert f"line {i + 4}, columns 19-27: value 3 of 3 is missing (blank)" in message


def test_truncated_in_the_header(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "Uncorrected Accelerogram Data", 2)
    message = value_error(write(tmp_path, "\n".join(lines[: i + 20])))
    assert f"line {i + 1}: the channel starting here has no data-count line" in message


@pytest.mark.parametrize("path, start, new, expected", [
    (V1, "21 Accelerogram points", "    21 Accelerogram points at 200 pts/sec in units of g.   Format: 8f9.6",
     "malformed data-count line; expected '<n> Accelerogram points at <rate> pts/sec"),
    (V1, "21 Accelerogram points", "    21 Accelerogram points at 200 pts/sec in units of furlongs.  Format: (8f9.6)",
     "unknown acceleration units 'furlongs'"),
    (V1, "21 Accelerogram points", "    21 Accelerogram points at 0 pts/sec in units of g.  Format: (8f9.6)",
     "sampling rate 0 pts/sec is not positive"),
    (V2, "20 points of veloc", "    20 points of veloc data equally spaced at  .005 sec, in cm/sec2. (8f10.7)",
     "unknown velocity units 'cm/sec2'"),
    (V2, "20 points of veloc", "    20 points of accel data equally spaced at  .005 sec, in cm/sec2. (8f10.7)",
     "a second acceleration block in channel 1"),
    (V2, "20 points of accel", "    20 points of veloc data equally spaced at  .005 sec, in cm/sec. (8f10.7)",
     "the first data block of channel 1 is velocity, not acceleration"),
])
def test_bad_data_count_lines(tmp_path, path, start, new, expected):
    lines = lines_of(path)
    i = line_index(lines, start)
    bad = write(tmp_path, "\n".join(edited(lines, i, new)), "bad" + path.suffix)
    message = value_error(bad, quantities="all")
    assert f"{bad}: line {i + 1}" in message and expected in message


def test_garbage_between_channels(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "/&")
    lines.insert(i + 1, "this is not a channel header")
    message = value_error(write(tmp_path, "\n".join(lines)))
    assert f"line {i + 2}: expected a channel header starting 'Uncorrected Accelerogram'" in message


def test_end_line_inside_the_header(tmp_path):
    lines = lines_of(V1)
    message = value_error(write(tmp_path, "\n".join(edited(lines, 5, "/& oops"))))
    assert "line 6: end-of-channel line before the data-count line of the channel starting on line 1" in message


def test_bad_cosmos_through_read_accelerogram(tmp_path):
    lines = lines_of(V1)
    i = line_index(lines, "21 Accelerogram points") + 1
    lines[i] = lines[i][:9] + "   abc463" + lines[i][18:]
    path = write(tmp_path, "\n".join(lines))
    with pytest.raises(RecordReadError) as info:
        read_accelerogram(path, trace="HNN", units="m/s2")
    message = str(info.value)
    assert str(path) in message and f"line {i + 1}, columns 10-18" in message and "not a number" in message


@pytest.mark.parametrize("format", ["auto", "COSMOS", "cosmos"])
def test_synthetic_through_read_accelerogram(format):
    rec = read_accelerogram(V2, trace="HNZ", units="m/s2", format=format)
    np.testing.assert_array_equal(rec.acceleration, expected_v2(2, "accel"))
    assert rec.dt == 0.005 and rec.start_time == "2015-03-14T11:05:06.000000Z"
