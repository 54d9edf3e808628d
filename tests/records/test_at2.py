"""The PEER NGA .AT2 obspy plugin (pounding_cli.records.at2): real Kobe files, inputs, detection, errors."""

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
from pounding_cli.records.at2.core import G, _is_at2, _read_at2
from pounding_cli.records.cosmos.core import _is_cosmos

DATA = Path(__file__).resolve().parent / "data"
SYNTHETIC = DATA / "synthetic.AT2"
SHARED = Path(__file__).resolve().parents[3] / "shared" / "records"
KOBE = SHARED / "kobe1995_kjma"
RAW = Path(__file__).resolve().parents[2] / "inputs" / "records" / "CICCC.RAW"  # shipped (USGS, CC0)
needs_kobe = pytest.mark.skipif(
    not KOBE.is_dir(), reason=f"PEER Kobe records absent: {KOBE} (never copied into the repo: PEER terms)"
)
OBSPY_KNET = Path(obspy.__file__).parent / "io" / "nied" / "tests" / "data" / "test.knet"

# file -> (PGA in g as the shared README gives it, time of the peak in s or None, channel, component)
KOBE_FILES = {
    "RSN1106_KOBE_KJM000.AT2": (0.8342, 8.52, "BNN", "0"),  # hand-edited "NPTS =   7500 , DT =   .020 SEC ,"
    "RSN1106_KOBE_KJM090.AT2": (0.6297, 8.44, "BNE", "90"),  # hand-edited "NPTS =  7500 , DT =   .020 SEC,"
    "RSN1106_KOBE_KJM-UP.AT2": (0.3389, None, "BNZ", "UP"),  # PEER's usual "NPTS=   7500, DT=   .0200 SEC,"
}


def load_generator() -> ModuleType:
    """Import data/make_synthetic_records.py (a script beside the data, not a package module)."""
    spec = importlib.util.spec_from_file_location("make_synthetic_records", DATA / "make_synthetic_records.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


GEN = load_generator()
EXPECTED_G = np.array([float(field) for field in GEN.at2_fields()])


def write(tmp_path: Path, text: str, name: str = "bad.AT2") -> Path:
    """Write ``text`` to tmp_path/name (bytes, as given) and return the path."""
    path = tmp_path / name
    path.write_bytes(text.encode("latin-1"))
    return path


def synthetic_lines() -> list[str]:
    """The lines of synthetic.AT2, to be edited by a test."""
    return SYNTHETIC.read_text().splitlines()


def value_error(path: Path) -> str:
    """The message of the ValueError raised by obspy.read on ``path``."""
    with pytest.raises(ValueError) as info:
        obspy.read(str(path), format="AT2")
    return str(info.value)


# --- real records: Kobe 1995, JMA Kobe (PEER NGA-West2 RSN1106) -------------------------------


@needs_kobe
@pytest.mark.parametrize("name", list(KOBE_FILES))
def test_kobe_autodetected_by_obspy(name):
    pga, t_peak, channel, component = KOBE_FILES[name]
    stream = obspy.read(str(KOBE / name))  # no format: found through the entry points
    assert len(stream) == 1
    tr = stream[0]
    assert tr.stats._format == "AT2"
    assert tr.stats.npts == 7500 and tr.data.size == 7500 and tr.data.dtype == np.float64
    assert tr.stats.delta == pytest.approx(0.02, rel=1e-12)
    assert tr.id == f".KJMA..{channel}"
    assert tr.stats.starttime == UTCDateTime(0)
    at2 = tr.stats.at2
    assert (at2.station, at2.component, at2.event, at2.date) == ("KJMA", component, "Kobe Japan", "1/16/1995")
    assert (at2.units_in_file, at2.units, at2.factor) == ("g", "m/s2", G)
    peak = int(np.argmax(np.abs(tr.data)))
    assert abs(tr.data[peak]) / G == pytest.approx(pga, abs=5e-5)
    if t_peak is not None:
        assert peak * tr.stats.delta == pytest.approx(t_peak, abs=1e-9)


@needs_kobe
@pytest.mark.parametrize("name", list(KOBE_FILES))
def test_kobe_through_read_accelerogram(name):
    pga, _, channel, _ = KOBE_FILES[name]
    rec = read_accelerogram(KOBE / name, units="m/s2")  # the reader already returns m/s²
    assert rec.dt == pytest.approx(0.02, rel=1e-12)
    assert rec.acceleration.size == 7500
    assert np.abs(rec.acceleration).max() / G == pytest.approx(pga, abs=5e-5)
    assert rec.source.endswith(f"[.KJMA..{channel}]")
    assert rec.start_time == "1970-01-01T00:00:00.000000Z"


@needs_kobe
def test_kobe_values_match_the_file_text():
    """Every value is the file's number times g (checked against an independent whitespace split)."""
    path = KOBE / "RSN1106_KOBE_KJM000.AT2"
    values = np.array(path.read_text().split("\n", 4)[4].split(), dtype=np.float64)
    np.testing.assert_array_equal(obspy.read(str(path))[0].data, values * G)


@needs_kobe
@pytest.mark.parametrize("name", list(KOBE_FILES))
def test_kobe_miniseed_round_trip(name):
    tr = obspy.read(str(KOBE / name))[0]
    buffer = io.BytesIO()
    tr.write(buffer, format="MSEED", encoding="FLOAT64")
    buffer.seek(0)
    back = obspy.read(buffer)[0]
    np.testing.assert_array_equal(back.data, tr.data)
    assert (back.id, back.stats.delta, back.stats.starttime) == (tr.id, tr.stats.delta, tr.stats.starttime)


@needs_kobe
def test_kobe_from_open_files_and_bytesio():
    path = KOBE / "RSN1106_KOBE_KJM090.AT2"
    reference = obspy.read(str(path))[0].data
    with open(path, "rb") as handle:
        np.testing.assert_array_equal(obspy.read(handle)[0].data, reference)
    np.testing.assert_array_equal(obspy.read(io.BytesIO(path.read_bytes()))[0].data, reference)


# --- the synthetic file: every field ---------------------------------------------------------


def test_synthetic_contents():
    tr = obspy.read(str(SYNTHETIC))[0]
    np.testing.assert_array_equal(tr.data, EXPECTED_G * G)
    assert tr.stats.delta == 0.01 and tr.stats.npts == 23
    assert tr.id == ".SYNTH..HNE"  # 100 Hz -> H; component 90 -> E; station cut to 5 characters
    assert tr.stats.starttime == UTCDateTime(0) and tr.stats.calib == 1.0
    assert dict(tr.stats.at2) == {
        "title": "PEER NGA STRONG MOTION DATABASE RECORD", "event": "Synthetic Test Quake",
        "date": "3/14/2015", "station": "SYNTH STATION 7", "component": "90", "units_in_file": "g",
        "units": "m/s2", "factor": G, "starttime_in_file": False,
    }


def test_synthetic_file_is_reproduced_by_its_script():
    written = GEN.write_at2().encode("ascii")
    assert SYNTHETIC.read_bytes().replace(b"\r\n", b"\n") == written  # line ends aside


def read_all_ways(path: Path) -> list[np.ndarray]:
    """The data read from a str path, a Path, an open binary file, an open text file and a BytesIO."""
    results = [obspy.read(str(path))[0].data, _read_at2(path)[0].data]
    with open(path, "rb") as handle:
        results.append(obspy.read(handle)[0].data)
    with open(path, encoding="ascii") as handle:
        results.append(_read_at2(handle)[0].data)
    results.append(obspy.read(io.BytesIO(path.read_bytes()))[0].data)
    results.append(_read_at2(io.BytesIO(path.read_bytes()))[0].data)
    results.append(_read_at2(io.StringIO(path.read_text()))[0].data)
    return results


def test_path_open_file_and_bytesio_give_the_same_data():
    for data in read_all_ways(SYNTHETIC):
        np.testing.assert_array_equal(data, EXPECTED_G * G)


def test_windows_line_endings(tmp_path):
    path = write(tmp_path, SYNTHETIC.read_text().replace("\n", "\r\n"), "crlf.AT2")
    np.testing.assert_array_equal(obspy.read(str(path))[0].data, EXPECTED_G * G)


def test_headonly_reads_the_header_only():
    tr = obspy.read(str(SYNTHETIC), headonly=True)[0]
    assert tr.stats.npts == 23 and tr.data.size == 0
    assert tr.stats.at2.component == "90"


@pytest.mark.parametrize("npts_line", [
    "NPTS=     23, DT=   .0100 SEC,",  # NGA-West2
    "NPTS =     23 , DT =   .010 SEC ,",  # hand-edited, as the Kobe 000 file
    "NPTS =  23 , DT =   .010 SEC,",  # as the Kobe 090 file
    "NPTS=23,DT=0.01SEC",
    "npts= 23, dt= 1.0E-02 sec",
    "   23    .0100    NPTS, DT",  # older NGA form
    "   23    .0100    NPTS, DT, SEC",
])
def test_header_forms(tmp_path, npts_line):
    lines = synthetic_lines()
    lines[3] = npts_line
    tr = obspy.read(str(write(tmp_path, "\n".join(lines) + "\n")))[0]
    assert tr.stats.npts == 23 and tr.stats.delta == pytest.approx(0.01, rel=1e-12)
    np.testing.assert_array_equal(tr.data, EXPECTED_G * G)


@pytest.mark.parametrize("units_line, factor", [
    ("ACCELERATION TIME HISTORY IN UNITS OF G", G),
    ("ACCELERATION TIME SERIES IN UNITS OF CM/S/S", 0.01),
    ("ACCELERATION TIME SERIES IN UNITS OF CM/S2", 0.01),
    ("Acceleration time series in units of gal", 0.01),
])
def test_other_units(tmp_path, units_line, factor):
    lines = synthetic_lines()
    lines[2] = units_line
    tr = obspy.read(str(write(tmp_path, "\n".join(lines) + "\n")))[0]
    np.testing.assert_array_equal(tr.data, EXPECTED_G * factor)
    assert tr.stats.at2.factor == factor


@pytest.mark.parametrize("title, station, channel, component", [
    ("Kobe Japan, 1/16/1995, KJMA, 0", "KJMA", "HNN", "0"),
    ("Kobe Japan, 1/16/1995, KJMA, 000", "KJMA", "HNN", "000"),
    ("Kobe Japan, 1/16/1995, KJMA, 360", "KJMA", "HNN", "360"),
    ("Kobe Japan, 1/16/1995, KJMA, 090", "KJMA", "HNE", "090"),
    ("Kobe Japan, 1/16/1995, KJMA, UP", "KJMA", "HNZ", "UP"),
    ("IMPERIAL VALLEY 10/15/79 2316, EL CENTRO ARRAY #6, 140", "ELCEN", "HN1", "140"),
    ("Northridge, 1/17/1994, Sylmar, 032", "SYLMA", "HN1", "032"),
    ("Northridge, 1/17/1994, Sylmar, 052", "SYLMA", "HN2", "052"),
    ("Northridge, 1/17/1994, Sylmar, 142", "SYLMA", "HN1", "142"),
    ("Northridge, 1/17/1994, Sylmar, 232", "SYLMA", "HN2", "232"),
    ("Chi-Chi, 9/20/1999, TCU068, N", "TCU06", "HNN", "N"),
    ("Chi-Chi, 9/20/1999, TCU068, DWN", "TCU06", "HNZ", "DWN"),
    ("Chi-Chi, 9/20/1999, TCU068, E", "TCU06", "HNE", "E"),
    ("Chi-Chi, 9/20/1999, TCU068, N45E", "TCU06", "HN1", "N45E"),
    ("just a title", "", "HN1", "just a title"),
])
def test_station_and_channel_from_the_header(tmp_path, title, station, channel, component):
    lines = synthetic_lines()
    lines[1] = title
    tr = obspy.read(str(write(tmp_path, "\n".join(lines) + "\n")))[0]
    assert (tr.stats.station, tr.stats.channel, tr.stats.at2.component) == (station, channel, component)


# --- detection -------------------------------------------------------------------------------


def other_format_files(tmp_path: Path) -> dict[str, Path]:
    """Files of other formats: MiniSEED, SAC, plain text, the COSMOS test files, K-NET, garbage."""
    tr = obspy.read()[0]  # obspy's example trace
    files = {"mseed": tmp_path / "x.mseed", "sac": tmp_path / "x.sac"}
    tr.write(str(files["mseed"]), format="MSEED")
    tr.write(str(files["sac"]), format="SAC")
    texts = {
        "two_columns": "".join(f"{0.01 * i:.2f} {np.sin(i):.6f}\n" for i in range(50)),
        "one_column": "".join(f"{np.sin(i):.6f}\n" for i in range(50)),
        "header_and_columns": "time, acc\n0.00, 1\n0.01, 2\n0.02, 3\n0.03, 4\n",
        "empty": "",
        "three_lines": "PEER NGA STRONG MOTION DATABASE RECORD\nKobe Japan\nACCELERATION TIME SERIES IN UNITS OF G",
        "at2_lines_shifted": "a\nb\nc\nd\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 3, DT= .01 SEC\n",
        "knet_like": "Origin Time       1995/01/17 05:46:00\nLat.              34.595\nLong.             135.035\n"
                     "Depth. (km)       16\n",
    }
    for key, text in texts.items():
        files[key] = write(tmp_path, text, f"{key}.txt")
    files["garbage"] = tmp_path / "garbage.bin"
    files["garbage"].write_bytes(np.random.default_rng(1).integers(0, 256, 5000, dtype=np.uint8).tobytes())
    files["nul_header"] = tmp_path / "nul.AT2"
    files["nul_header"].write_bytes(SYNTHETIC.read_bytes().replace(b"UNITS", b"UN\x00TS"))
    files["cosmos_v1"] = DATA / "synthetic_2ch.V1"
    files["cosmos_v2"] = DATA / "synthetic_2ch.V2"
    if RAW.is_file():
        files["ciccc_raw"] = RAW
    if OBSPY_KNET.is_file():
        files["knet"] = OBSPY_KNET
    return files


def test_is_at2_false_on_other_formats(tmp_path):
    for key, path in other_format_files(tmp_path).items():
        assert _is_at2(str(path)) is False, key
        with open(path, "rb") as handle:
            assert _is_at2(handle) is False, key
            assert handle.tell() == 0, key


@pytest.mark.parametrize("thing", [None, 42, b"PEER", "not/a/file.AT2", object(), io.StringIO("")])
def test_is_at2_false_on_anything_else(thing):
    assert _is_at2(thing) is False


def test_is_at2_false_on_a_directory(tmp_path):
    assert _is_at2(str(tmp_path)) is False and _is_at2(tmp_path) is False


def test_is_at2_true_and_rewinds():
    assert _is_at2(str(SYNTHETIC)) is True and _is_at2(SYNTHETIC) is True
    buffer = io.BytesIO(b"junk" + SYNTHETIC.read_bytes())
    buffer.seek(4)
    assert _is_at2(buffer) is True and buffer.tell() == 4
    with open(SYNTHETIC, encoding="ascii") as handle:
        assert _is_at2(handle) is True and handle.tell() == 0


@needs_kobe
def test_kobe_is_at2_and_not_cosmos():
    for name in KOBE_FILES:
        assert _is_at2(str(KOBE / name)) is True
        assert _is_cosmos(str(KOBE / name)) is False


def test_is_at2_reads_only_the_head(tmp_path):
    """Detection reads a few KB: a file with a huge body is detected from its first lines."""

    class CountingBytesIO(io.BytesIO):
        largest = 0

        def read(self, size=-1):
            chunk = super().read(size)
            CountingBytesIO.largest = max(CountingBytesIO.largest, len(chunk))
            return chunk

    body = SYNTHETIC.read_bytes() + b"   .1000000E+00\n" * 100_000
    assert _is_at2(CountingBytesIO(body)) is True
    assert CountingBytesIO.largest <= 8192


# --- errors ----------------------------------------------------------------------------------


def test_header_lying_about_the_point_count(tmp_path):
    lines = synthetic_lines()
    lines[3] = "NPTS=     24, DT=   .0100 SEC,"
    path = write(tmp_path, "\n".join(lines) + "\n")
    message = value_error(path)
    assert str(path) in message and "NPTS = 24" in message and "23 values" in message
    assert "lines 5-9" in message


def test_non_numeric_value_names_the_line(tmp_path):
    lines = synthetic_lines()
    lines[5] = lines[5].replace("-.1365951E+00", "-.13659X1E+00")
    path = write(tmp_path, "\n".join(lines) + "\n")
    message = value_error(path)
    assert str(path) in message and "line 6" in message and "'-.13659X1E+00' is not a number" in message


@pytest.mark.parametrize("value", ["NaN", "inf", "-Infinity"])
def test_non_finite_value_names_the_line(tmp_path, value):
    lines = synthetic_lines()
    lines[7] = lines[7].replace("-.1321005E+00", value)
    message = value_error(write(tmp_path, "\n".join(lines) + "\n"))
    assert "line 8" in message and "non-finite" in message


def test_truncated_file(tmp_path):
    text = SYNTHETIC.read_text()
    cut = text[: text.index("-.2199865E+00")]  # the file stops in the middle of line 8
    path = write(tmp_path, cut)
    message = value_error(path)
    assert str(path) in message and "NPTS = 23" in message and "16 values" in message
    assert "lines 5-8" in message and "truncated" in message


def test_truncated_in_the_middle_of_a_number(tmp_path):
    text = SYNTHETIC.read_text()
    cut = text[: text.index("-.2199865E+00") + 11]  # "-.2199865E+" : not a number
    message = value_error(write(tmp_path, cut))
    assert "line 8" in message and "'-.2199865E+' is not a number" in message


@pytest.mark.parametrize("line, replacement, expected", [
    (3, "NPTS= 23, DT=", "line 4: expected 'NPTS= <n>, DT= <dt> SEC'"),
    (3, "NPTS= 23, DT= -0.01 SEC", "line 4: DT = -0.01 s is not a positive time step"),
    (3, "NPTS= 0, DT= .01 SEC", "line 4: NPTS = 0"),
    (3, "NPTS= 23, DT= 0.0 SEC", "line 4: DT = 0.0 s is not a positive time step"),
    (2, "ACCELERATION TIME SERIES IN UNITS OF FURLONGS", "line 3: unknown units 'FURLONGS'"),
    (2, "VELOCITY TIME SERIES IN UNITS OF CM/S", "line 3: expected 'ACCELERATION TIME SERIES IN UNITS OF"),
])
def test_bad_header_lines(tmp_path, line, replacement, expected):
    lines = synthetic_lines()
    lines[line] = replacement
    path = write(tmp_path, "\n".join(lines) + "\n")
    assert _is_at2(str(path)) is True  # detected, so the reader can say what is wrong
    message = value_error(path)
    assert str(path) in message and expected in message


def test_header_only_file(tmp_path):
    message = value_error(write(tmp_path, "\n".join(synthetic_lines()[:4]) + "\n"))
    assert "line 4 says NPTS = 23 but the file holds no values after its 4 header lines" in message


def test_binary_data_in_the_body(tmp_path):
    path = tmp_path / "bin.AT2"
    path.write_bytes(SYNTHETIC.read_bytes() + b"\x00\x01\x02")
    assert "line 10: control character" in value_error(path)


def test_bytesio_error_names_the_object():
    with pytest.raises(ValueError, match=r"<BytesIO>: line 4 says NPTS = 24"):
        _read_at2(io.BytesIO(SYNTHETIC.read_bytes().replace(b"NPTS=     23", b"NPTS=     24")))


def test_bad_at2_through_read_accelerogram(tmp_path):
    lines = synthetic_lines()
    lines[5] = lines[5].replace("-.1365951E+00", "-.13659X1E+00")
    path = write(tmp_path, "\n".join(lines) + "\n")
    with pytest.raises(RecordReadError) as info:
        read_accelerogram(path, units="m/s2")
    message = str(info.value)
    assert str(path) in message and "line 6" in message and "is not a number" in message
    assert "ValueError" in message


def test_lying_at2_through_read_accelerogram(tmp_path):
    lines = synthetic_lines()
    lines[3] = "NPTS=     30, DT=   .0100 SEC,"
    with pytest.raises(RecordReadError, match=r"NPTS = 30 but the file holds 23 values"):
        read_accelerogram(write(tmp_path, "\n".join(lines) + "\n"), units="m/s2")


@pytest.mark.parametrize("format", ["auto", "AT2", "at2"])
def test_synthetic_through_read_accelerogram(format):
    rec = read_accelerogram(SYNTHETIC, units="m/s2", format=format)
    np.testing.assert_array_equal(rec.acceleration, EXPECTED_G * G)
    assert rec.dt == 0.01 and rec.source == f"{SYNTHETIC} [.SYNTH..HNE]"


def test_header_count_lower_than_the_values(tmp_path):
    lines = synthetic_lines()
    lines[3] = "NPTS=     20, DT=   .0100 SEC,"
    message = value_error(write(tmp_path, "\n".join(lines) + "\n"))
    assert "line 4 says NPTS = 20 but the file holds 23 values (lines 5-9)" in message



def test_units_of_a_self_describing_file_are_applied_once():
    """An AT2 file says its units (g): read_accelerogram must not apply them a second time.
    'g' (what the file says) and 'm/s2' (what the reader returns) give the same values;
    any other unit contradicts the file and is refused, naming the 'units' setting."""
    from pounding_cli.errors import RecordReadError
    from pounding_cli.records import read_accelerogram

    as_g = read_accelerogram(SYNTHETIC, units="g").acceleration
    as_si = read_accelerogram(SYNTHETIC, units="m/s2").acceleration
    np.testing.assert_array_equal(as_g, as_si)
    raw = obspy.read(str(SYNTHETIC))[0]
    np.testing.assert_array_equal(as_g, raw.data)
    with pytest.raises(RecordReadError, match="declares its values in g") as info:
        read_accelerogram(SYNTHETIC, units="cm/s2")
    assert info.value.field == "units"
