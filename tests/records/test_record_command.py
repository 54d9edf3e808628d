"""`pound record`: text and JSON output (checked against its JSON Schema), the plot, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.records.inspect import open_record
from pounding_cli.records.metrics import metrics
from pounding_cli.records.plot import LABELS, record_figure
from pounding_cli.records.spectrum import DEFAULT_PERIODS
from pounding_cli.records.summary import describe_record

from conftest import INPUTS, ROOT, SHARED

runner = CliRunner()
SHIPPED = INPUTS / "ridgecrest2019_ccc.record.toml"
MSEED = INPUTS / "records" / "ridgecrest2019_ccc.mseed"
SCHEMA = json.loads((ROOT / "schemas" / "record-summary.schema.json").read_text(encoding="utf-8"))
KOBE = SHARED / "records" / "kobe1995_kjma"
needs_kobe = pytest.mark.skipif(not KOBE.is_dir(), reason=f"PEER Kobe records absent: {KOBE}")


def pound_record(*args: str):
    result = runner.invoke(app, ["record", *map(str, args)], env={"COLUMNS": "120"})
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result


# --- output ---------------------------------------------------------------------------------------


def test_text_output_of_the_shipped_definition():
    r = pound_record(SHIPPED)
    assert r.exit_code == 0, r.stderr
    for text in ("2019 Ridgecrest M7.1", "event: 2019 Ridgecrest, California", "processing: none",
                 "0.5256 at 13.41 s", "0.4714 at 14.52 s", "3401", "34.00", "90°", "360°", "D5-95 (s)"):  # fmt: skip
        assert text in r.stdout, text


def test_json_output_follows_its_schema_and_the_metrics():
    r = pound_record(SHIPPED, "--json")
    assert r.exit_code == 0, r.stderr
    document = json.loads(r.stdout)
    jsonschema.validate(document, SCHEMA)
    assert document["kind"] == "definition" and document["metadata"]["magnitude"] == 7.1
    east = open_record(SHIPPED).components[0]
    m = metrics(east.acceleration, east.dt)
    first = document["components"][0]
    assert (first["name"], first["trace_id"], first["azimuth_deg"]) == ("L", "CI.CCC..HNE", 90.0)
    assert (first["points"], first["dt_s"], first["pga_m_s2"], first["arias_intensity_m_s"]) == (
        3401, 0.01, m.pga, m.arias_intensity)
    assert first["pga_g"] == pytest.approx(0.5256, abs=5e-5)


def test_json_of_a_record_file_lists_every_trace():
    document = describe_record(MSEED, units="m/s2")
    jsonschema.validate(document, SCHEMA)
    assert document["kind"] == "record file"
    assert [c["name"] for c in document["components"]] == ["CI.CCC..HNE", "CI.CCC..HNN"]
    assert document["components"][0]["header"]["start_time"] == "2019-07-06T03:20:03.000000Z"
    one = describe_record(MSEED, units="m/s2", trace="HNN")
    assert [c["name"] for c in one["components"]] == ["CI.CCC..HNN"]


def test_processing_and_scale_are_reported(tmp_path):
    (tmp_path / "s.record.toml").write_text(
        f'name = "scaled"\n[L]\nfile = "{MSEED.as_posix()}"\ntrace = "HNE"\nunits = "m/s2"\n'
        '[processing]\ndemean = true\ntarget_pga = 0.3\n'
    )
    r = pound_record(tmp_path / "s.record.toml", "--json")
    document = json.loads(r.stdout)
    jsonschema.validate(document, SCHEMA)
    assert document["processing"] == ["demean", "scaled to a PGA of 0.3 g"]
    assert document["components"][0]["pga_g"] == pytest.approx(0.3, rel=1e-15)
    assert document["scale_factor"] != 1.0 and "becomes 0.3 g" in document["notes"][0]


@needs_kobe
def test_kobe_files_as_pound_record_prints_them():
    document = describe_record(KOBE / "RSN1106_KOBE_KJM000.AT2")
    (c,) = document["components"]
    assert (c["points"], c["dt_s"], round(c["pga_g"], 3)) == (7500, 0.02, 0.834)
    assert c["azimuth_deg"] == 0.0 and c["units_in_file"] == "g"
    assert document["metadata"]["event"] == "Kobe Japan"


# --- the plot --------------------------------------------------------------------------------------


def test_figure_has_four_labelled_panels_with_every_series():
    data = open_record(SHIPPED)
    figure = record_figure(data)
    axes = figure.get_axes()
    assert len(axes) == 4
    ylabels = [ax.get_ylabel() for ax in axes]
    assert ylabels == [LABELS["acceleration"], LABELS["velocity"], LABELS["displacement"], LABELS["psa"]]
    assert ylabels == ["acceleration (g)", "velocity (m/s)", "displacement (m)", "PSA, 5 % damping (g)"]
    assert [ax.get_xlabel() for ax in axes] == ["time (s)"] * 3 + ["period (s)"]
    assert axes[3].get_xscale() == "log"
    for ax in axes[:3]:
        lines = ax.get_lines()
        assert [ln.get_label() for ln in lines] == ["L", "T"]
        assert all(ln.get_xydata().shape == (3401, 2) for ln in lines)
        assert lines[0].get_xdata()[-1] == pytest.approx(34.0)
    psa = axes[3].get_lines()
    assert all(ln.get_xydata().shape == (DEFAULT_PERIODS.size, 2) for ln in psa)
    # the acceleration panel is in g: its peak is the PGA in g
    assert np.abs(axes[0].get_lines()[0].get_ydata()).max() == pytest.approx(0.5256, abs=5e-5)
    # at the shortest period the spectrum is close to the PGA (a stiff oscillator follows the ground)
    assert psa[0].get_ydata()[0] == pytest.approx(0.5256, rel=0.05)


def test_plot_option_writes_a_png(tmp_path):
    out = tmp_path / "r.png"
    r = pound_record(SHIPPED, "--plot", out)
    assert r.exit_code == 0, r.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {out}" in r.stderr


# --- bad input: exit 2, the file named, and the line or field ------------------------------------


AT2_HEADER = "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, STA, 0\nACCELERATION TIME SERIES IN UNITS OF G\n"


@pytest.mark.parametrize(("name", "text", "args", "expected"), [
    ("lying.AT2", AT2_HEADER + "NPTS=   10, DT=   .0100 SEC,\n  .1  .2  .3  .4  .5\n  .6  .7  .8\n", [],
     ["lying.AT2: line 4 says NPTS = 10 but the file holds 8 values (lines 5-6)"]),
    ("words.AT2", AT2_HEADER + "NPTS=    4, DT=   .0100 SEC,\n  .1  .2  x.3  .4\n", [],
     ["words.AT2: line 5: 'x.3' is not a number"]),
    ("nan.AT2", AT2_HEADER + "NPTS=    4, DT=   .0100 SEC,\n  .1  .2  NaN  .4\n", [],
     ["nan.AT2: line 5: non-finite value 'NaN'"]),
    ("zero_dt.AT2", AT2_HEADER + "NPTS=    2, DT=   .0000 SEC,\n  .1  .2\n", [],
     ["zero_dt.AT2: line 4: DT = .0000 s is not a positive time step"]),
    ("nan.txt", "0.1\n0.2\nnan\n", ["--units", "g", "--dt", "0.01"], ["nan.txt: line 3: non-finite value"]),
    ("column.txt", "0.1\n0.2\n", ["--units", "g", "--dt", "0"], ["--dt", "dt must be a sample interval of 1e-06 to 1 s, got 0.0"]),
    ("column2.txt", "0.1\n0.2\n", ["--units", "g", "--dt", "-0.01"], ["--dt", "got -0.01"]),
    ("column3.txt", "0.1\n0.2\n", ["--units", "g"], ["--dt", "column3.txt: plain text with one value per line: give 'dt'"]),
    ("column4.txt", "0.1\n0.2\n", ["--dt", "0.01"], ["--units", "column4.txt: plain text does not say in which units"]),
])  # fmt: skip
def test_bad_record_files(tmp_path, name, text, args, expected):
    (tmp_path / name).write_text(text)
    r = pound_record(tmp_path / name, *args)
    assert r.exit_code == 2, r.stdout + r.stderr
    assert r.stdout == "" and "Traceback" not in r.stderr
    for part in expected:
        assert part in r.stderr, r.stderr


@pytest.mark.parametrize(("definition", "expected"), [
    ('[L]\nfile = "a.mseed"\nunits = "g"\nazimuth = 400\n', "bad.record.toml: L.azimuth: Input should be less than or equal to 360"),
    ('name = "no components"\n', "bad.record.toml: (top level): a record needs at least one component"),
    ('[L]\nfile = "a.mseed"\nunits = "g"\ndt = 0\n', "bad.record.toml: L.dt: Input should be greater than or equal to 0.000001"),
    ('[L]\nfile = "a.txt"\nunits = "g"\ndt = 0.02\n[T]\nfile = "b.txt"\nunits = "g"\ndt = 0.01\n[processing]\nresample = false\n',
     "bad.record.toml: processing.resample: the components have different sample intervals (L: 0.02 s, T: 0.01 s)"),
    ('[L]\nfile = "missing.AT2"\nunits = "g"\n', "bad.record.toml: L.file: "),
    ('[L]\nfile = "a.txt"\nunits = "g"\ndt = 0.01\n[processing]\nfilter = { freqmax = 80.0 }\n',
     "bad.record.toml: processing.filter.freqmax: "),
])  # fmt: skip
def test_bad_definitions(tmp_path, definition, expected):
    (tmp_path / "a.txt").write_text("0.1\n0.2\n0.3\n")
    (tmp_path / "b.txt").write_text("0.1\n0.2\n0.3\n0.4\n0.5\n")
    (tmp_path / "bad.record.toml").write_text(definition)
    r = pound_record(tmp_path / "bad.record.toml")
    assert r.exit_code == 2, r.stdout + r.stderr
    assert expected in r.stderr, r.stderr


def test_options_of_record_files_are_refused_for_definitions():
    r = pound_record(SHIPPED, "--units", "g")
    assert r.exit_code == 2
    assert "ridgecrest2019_ccc.record.toml: --units apply to record files" in r.stderr


def test_units_needed_for_miniseed():
    r = pound_record(MSEED)
    assert r.exit_code == 2
    assert "--units: " in r.stderr and "ridgecrest2019_ccc.mseed: CI.CCC..HNE does not say in which units" in r.stderr


def test_bad_plot_name(tmp_path):
    r = pound_record(SHIPPED, "--plot", tmp_path / "r.gif")
    assert r.exit_code == 2 and "r.gif: cannot write a .gif plot" in r.stderr
    r = pound_record(SHIPPED, "--plot", tmp_path / "no" / "r.png")
    assert r.exit_code == 2 and "does not exist; create it first" in r.stderr


# --- formats obspy reads: K-NET and SAC ------------------------------------------------------------


def write_knet(path: Path, counts: np.ndarray, direction: str = "N-S") -> None:
    """A K-NET ASCII file (the layout of obspy's own test file): 17 header lines, 8 counts per line."""
    header = [
        "Origin Time       2000/01/02 03:04:00", "Lat.              35.000", "Long.             139.000",
        "Depth. (km)       10", "Mag.              6.1", "Station Code      TST001",
        "Station Lat.      35.1000", "Station Long.     139.1000", "Station Height(m) 10",
        "Record Time       2000/01/02 03:04:10", "Sampling Freq(Hz) 100Hz",
        f"Duration Time(s)  {counts.size // 100}", f"Dir.              {direction}",
        "Scale Factor      2000(gal)/8388608", "Max. Acc. (gal)   1.000", "Last Correction   2000/01/02 03:00:00",
        "Memo.             synthetic",
    ]  # fmt: skip
    rows = [" ".join(f"{int(c):8d}" for c in counts[i:i + 8]) for i in range(0, counts.size, 8)]
    path.write_text("\n".join(header + rows) + "\n")


def test_knet_counts_are_calibrated(tmp_path):
    """obspy's K-NET reader gives counts and stats.calib (m/s² per count); pound applies it."""
    counts = np.zeros(400, dtype=int)
    counts[100] = 8388608 // 2000 * 3  # 12582 counts ≈ 3 gal
    path = tmp_path / "TST0010001021304.NS"
    write_knet(path, counts)
    document = describe_record(path)
    (c,) = document["components"]
    assert c["pga_m_s2"] == pytest.approx(12582 * 0.01 * 2000 / 8388608, rel=1e-12)
    assert c["header"]["format"] == "KNET" and c["azimuth_deg"] == 0.0
    assert document["metadata"]["magnitude"] == 6.1


def test_sac_component_azimuth_is_reported(tmp_path):
    from obspy import Trace

    trace = Trace(data=np.sin(np.arange(200) / 10.0), header={"delta": 0.01, "station": "SAC1", "channel": "HN1"})
    trace.write(str(tmp_path / "x.sac"), format="SAC")
    from obspy import read

    st = read(str(tmp_path / "x.sac"))
    st[0].stats.sac.cmpaz, st[0].stats.sac.cmpinc = 30.0, 90.0
    st.write(str(tmp_path / "x.sac"), format="SAC")
    document = describe_record(tmp_path / "x.sac", units="cm/s2")
    assert document["components"][0]["azimuth_deg"] == 30.0
    # SAC stores float32 samples: 1e-6 relative covers their rounding (2^-24 ≈ 6e-8)
    assert document["components"][0]["pga_m_s2"] == pytest.approx(0.01 * np.abs(trace.data).max(), rel=1e-6)
