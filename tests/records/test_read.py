"""Tests of read_accelerogram: plain text, units, obspy formats, trace selection, bad files."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding_cli.errors import RecordReadError
from pounding_cli.records import UNIT_FACTORS, Accelerogram, read_accelerogram

REPO = Path(__file__).resolve().parents[2]
T0 = "2020-01-02T03:04:05.000000Z"


def write_text(tmp_path: Path, text: str, name: str = "record.txt") -> Path:
    """Write ``text`` to a file in tmp_path and return its path."""
    path = tmp_path / name
    path.write_text(text)
    return path


def make_trace(channel: str = "HNE", station: str = "STA", data=None, start: str = T0):
    """A 100 Hz obspy trace XX.<station>..<channel> holding ``data`` (default 0, 1, ..., 9)."""
    from obspy import Trace, UTCDateTime

    values = np.arange(10.0) if data is None else np.asarray(data, dtype=np.float64)
    header = {"network": "XX", "station": station, "location": "", "channel": channel,
              "delta": 0.01, "starttime": UTCDateTime(start)}
    return Trace(data=values, header=header)


def write_stream(path: Path, *traces, format: str = "MSEED") -> Path:
    """Write the traces to ``path`` with obspy and return the path."""
    from obspy import Stream

    options = {"encoding": "FLOAT64"} if format == "MSEED" else {}
    Stream(list(traces)).write(str(path), format=format, **options)
    return path


def read_error(path: Path, **kwargs) -> str:
    """The message of the RecordReadError raised when reading ``path``."""
    with pytest.raises(RecordReadError) as info:
        read_accelerogram(path, **kwargs)
    return str(info.value)


# --- plain text -------------------------------------------------------------------------


def test_one_column_with_dt(tmp_path):
    rec = read_accelerogram(write_text(tmp_path, "0.0\n0.5\n-0.25\n1e-3\n"), dt=0.02)
    assert isinstance(rec, Accelerogram)
    assert rec.dt == 0.02
    np.testing.assert_array_equal(rec.acceleration, [0.0, 0.5, -0.25, 1e-3])
    assert rec.acceleration.dtype == np.float64 and rec.acceleration.flags.c_contiguous
    assert not rec.acceleration.flags.writeable
    assert rec.start_time is None and rec.source.endswith("record.txt")


@pytest.mark.parametrize("separator", [" ", "   ", "\t", ",", ", ", ";", " ; "])
def test_two_columns(tmp_path, separator):
    text = "".join(f"{0.005 * i:.3f}{separator}{v}\n" for i, v in enumerate([0.0, 1.0, -2.0, 3.5]))
    rec = read_accelerogram(write_text(tmp_path, text))
    assert rec.dt == pytest.approx(0.005, rel=1e-12)
    np.testing.assert_array_equal(rec.acceleration, [0.0, 1.0, -2.0, 3.5])


def test_header_comments_and_blank_lines(tmp_path):
    text = "# exported by hand\n\ntime (s), acc (m/s2)\n% units m/s2\n0.0, 1\n0.01, 2\n\n0.02, 3\n"
    rec = read_accelerogram(write_text(tmp_path, text))
    assert rec.dt == pytest.approx(0.01)
    np.testing.assert_array_equal(rec.acceleration, [1.0, 2.0, 3.0])


def test_format_text_and_windows_line_endings(tmp_path):
    path = tmp_path / "crlf.csv"
    path.write_bytes(b"t;a\r\n0;0.1\r\n0.5;0.2\r\n1.0;0.3\r\n")
    rec = read_accelerogram(path, format="text")
    assert rec.dt == 0.5
    np.testing.assert_array_equal(rec.acceleration, [0.1, 0.2, 0.3])


def test_two_columns_with_matching_dt(tmp_path):
    rec = read_accelerogram(write_text(tmp_path, "0 1\n0.01 2\n0.02 3\n"), dt=0.01)
    assert rec.dt == 0.01


def test_two_columns_with_disagreeing_dt(tmp_path):
    message = read_error(write_text(tmp_path, "0 1\n0.01 2\n0.02 3\n"), dt=0.02)
    assert "disagrees" in message and "0.02" in message


def test_non_uniform_times(tmp_path):
    message = read_error(write_text(tmp_path, "t a\n0 1\n0.01 2\n0.02 3\n0.035 4\n0.045 5\n"))
    assert "line 5" in message and "resampled" in message


def test_decreasing_times(tmp_path):
    message = read_error(write_text(tmp_path, "0 1\n0.01 2\n0.005 3\n"))
    assert "line 3" in message and "increase strictly" in message


def test_repeated_time(tmp_path):
    message = read_error(write_text(tmp_path, "# c\n0 1\n0.01 2\n0.01 3\n"))
    assert "line 4" in message and "increase strictly" in message


def test_mixed_columns(tmp_path):
    message = read_error(write_text(tmp_path, "0 1\n0.01 2\n3\n"), dt=0.01)
    assert "line 3" in message and "mixed" in message


def test_three_columns(tmp_path):
    message = read_error(write_text(tmp_path, "0 1 2\n"))
    assert "line 1" in message and "3 columns" in message


def test_bad_number(tmp_path):
    message = read_error(write_text(tmp_path, "1.0\n2.0\n3.O\n"), dt=0.01)
    assert "line 3" in message and "'3.O'" in message


def test_missing_dt(tmp_path):
    message = read_error(write_text(tmp_path, "1.0\n2.0\n"))
    assert "one value per line" in message and "give 'dt'" in message


@pytest.mark.parametrize("bad", ["nan", "NaN", "inf", "-inf"])
def test_non_finite_value(tmp_path, bad):
    message = read_error(write_text(tmp_path, f"# header\n1.0\n2.0\n{bad}\n4.0\n"), dt=0.01)
    assert "sample index 2" in message and "line 4" in message


def test_empty_file(tmp_path):
    assert "empty file" in read_error(write_text(tmp_path, ""))


def test_only_comments(tmp_path):
    assert "zero samples" in read_error(write_text(tmp_path, "# nothing\n\n"), dt=0.01)


def test_one_sample(tmp_path):
    assert "one sample" in read_error(write_text(tmp_path, "1.0\n"), dt=0.01)
    assert "one sample" in read_error(write_text(tmp_path, "0 1.0\n", "two.txt"))


def test_missing_file(tmp_path):
    message = read_error(tmp_path / "absent.txt", dt=0.01)
    assert "no such file" in message and "absent.txt" in message


def test_directory(tmp_path):
    assert "directory" in read_error(tmp_path)


@pytest.mark.parametrize("dt", [0.0, -0.01, float("nan"), float("inf")])
def test_bad_dt_argument(tmp_path, dt):
    assert "dt" in read_error(write_text(tmp_path, "1\n2\n"), dt=dt)


def test_trace_selection_in_plain_text(tmp_path):
    path = write_text(tmp_path, "1\n2\n")
    assert read_accelerogram(path, dt=0.01, trace="0").acceleration.size == 2
    assert "single trace" in read_error(path, dt=0.01, trace="HNE")


# --- units --------------------------------------------------------------------------------


@pytest.mark.parametrize(("units", "factor"), [("g", 9.80665), ("m/s2", 1.0), ("cm/s2", 0.01),
                                               ("gal", 0.01), ("G", 9.80665)])
def test_units(tmp_path, units, factor):
    rec = read_accelerogram(write_text(tmp_path, "0.5\n-2\n"), dt=0.01, units=units)
    np.testing.assert_allclose(rec.acceleration, [0.5 * factor, -2.0 * factor], rtol=1e-15)


def test_unknown_units(tmp_path):
    message = read_error(write_text(tmp_path, "1\n2\n"), dt=0.01, units="ft/s2")
    assert "'ft/s2'" in message
    assert all(unit in message for unit in UNIT_FACTORS)


# --- obspy formats ------------------------------------------------------------------------


def test_minimal_miniseed_single_trace(tmp_path):
    path = write_stream(tmp_path / "one.mseed", make_trace(data=[0.0, 0.25, -0.5, 1.0]))
    rec = read_accelerogram(path, units="g")
    assert rec.dt == 0.01
    np.testing.assert_array_equal(rec.acceleration, np.array([0.0, 0.25, -0.5, 1.0]) * 9.80665)
    assert rec.start_time == T0
    assert rec.source == f"{path} [XX.STA..HNE]"


def test_sac(tmp_path):
    data = np.sin(np.linspace(0.0, 3.0, 50))
    path = write_stream(tmp_path / "rec.sac", make_trace(data=data), format="SAC")
    rec = read_accelerogram(path, units="cm/s2")
    assert rec.dt == pytest.approx(0.01, rel=1e-6)  # SAC stores delta as float32
    np.testing.assert_allclose(rec.acceleration, data.astype(np.float32).astype(np.float64) * 0.01,
                               rtol=1e-15)
    rec = read_accelerogram(path, format="SAC")
    assert rec.acceleration.size == 50


@pytest.fixture
def two_traces(tmp_path) -> Path:
    """MiniSEED holding XX.STA..HNE (0..9) and XX.STA..HNN (-(0..9))."""
    east, north = make_trace("HNE"), make_trace("HNN", data=-np.arange(10.0))
    return write_stream(tmp_path / "two.mseed", east, north)


@pytest.mark.parametrize(("trace", "sign"), [("XX.STA..HNE", 1), ("HNE", 1), ("0", 1),
                                             ("XX.STA..HNN", -1), ("HNN", -1), ("1", -1)])
def test_trace_selection(two_traces, trace, sign):
    rec = read_accelerogram(two_traces, trace=trace)
    np.testing.assert_array_equal(rec.acceleration, sign * np.arange(10.0))


def test_trace_needed_when_several(two_traces):
    message = read_error(two_traces)
    assert "holds 2 traces (XX.STA..HNE, XX.STA..HNN)" in message and "'trace'" in message


@pytest.mark.parametrize("trace", ["HNZ", "XX.STA..HNZ", "2", "XX.STA.00.HNE"])
def test_trace_not_found(two_traces, trace):
    message = read_error(two_traces, trace=trace)
    assert f"'{trace}'" in message and "XX.STA..HNE, XX.STA..HNN" in message


def test_ambiguous_channel_code(tmp_path):
    path = write_stream(tmp_path / "stations.mseed", make_trace(station="A"), make_trace(station="B"))
    message = read_error(path, trace="HNE")
    assert "ambiguous" in message and "XX.A..HNE" in message and "XX.B..HNE" in message
    assert read_accelerogram(path, trace="XX.B..HNE").source.endswith("[XX.B..HNE]")


def test_contiguous_segments_are_merged(tmp_path):
    first = make_trace(data=np.arange(5.0))
    second = make_trace(data=np.arange(5.0, 10.0), start="2020-01-02T03:04:05.05")
    path = write_stream(tmp_path / "segments.slist", first, second, format="SLIST")
    rec = read_accelerogram(path)
    np.testing.assert_array_equal(rec.acceleration, np.arange(10.0))


def test_gap_is_refused(tmp_path):
    first = make_trace(data=np.arange(5.0))
    second = make_trace(data=np.arange(5.0), start="2020-01-02T03:04:06")
    message = read_error(write_stream(tmp_path / "gap.mseed", first, second))
    assert "XX.STA..HNE" in message and "gaps" in message


def test_dt_argument_checked_against_file(tmp_path):
    path = write_stream(tmp_path / "one.mseed", make_trace())
    assert read_accelerogram(path, dt=0.01).dt == 0.01
    assert "disagrees" in read_error(path, dt=0.02)


def test_non_finite_in_miniseed(tmp_path):
    path = write_stream(tmp_path / "nan.mseed", make_trace(data=[0.0, 1.0, 2.0, np.nan, 4.0]))
    assert "sample index 3" in read_error(path)


def test_one_sample_miniseed(tmp_path):
    path = write_stream(tmp_path / "short.mseed", make_trace(data=[1.0]))
    assert "one sample" in read_error(path)


def test_path_with_wildcard_characters(tmp_path):
    path = write_stream(tmp_path / "rec[1]*.mseed", make_trace())
    write_stream(tmp_path / "rec1x.mseed", make_trace(data=-np.arange(10.0)))
    np.testing.assert_array_equal(read_accelerogram(path).acceleration, np.arange(10.0))


# --- bad files: only RecordReadError ------------------------------------------------------


def test_garbage_binary(tmp_path):
    path = tmp_path / "garbage.bin"
    path.write_bytes(np.random.default_rng(0).bytes(4096))
    message = read_error(path)
    assert "neither a format obspy reads nor plain text" in message and "garbage.bin" in message
    assert "not plain text" in read_error(path, format="text")


def test_binary_with_nul_bytes(tmp_path):
    path = tmp_path / "zeros.dat"
    path.write_bytes(b"1.0\n\x00\x00\x002.0\n")
    assert "neither a format obspy reads nor plain text" in read_error(path, dt=0.01)


def test_truncated_miniseed(tmp_path):
    full = write_stream(tmp_path / "full.mseed", make_trace(data=np.arange(2000.0)))
    path = tmp_path / "truncated.mseed"
    path.write_bytes(full.read_bytes()[:300])
    assert "truncated.mseed" in read_error(path)


def test_wrong_explicit_format(tmp_path):
    path = write_stream(tmp_path / "one.mseed", make_trace())
    assert "one.mseed" in read_error(path, format="SAC")
    assert "'NOPE'" in read_error(path, format="NOPE")


def test_pickle_is_refused(tmp_path):
    path = write_stream(tmp_path / "stream.pkl", make_trace(), format="PICKLE")
    assert "pickled" in read_error(path)
    assert "pickled" in read_error(write_stream(tmp_path / "one.mseed", make_trace()),
                                   format="PICKLE")


def test_import_does_not_load_obspy():
    code = "import sys, pounding_cli, pounding_cli.records; print('obspy' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True,
                            text=True, check=True)
    assert result.stdout.strip() == "False"
