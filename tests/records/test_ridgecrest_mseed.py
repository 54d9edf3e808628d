"""The shipped Ridgecrest CI.CCC MiniSEED record: contents, and provenance from its script."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from pounding_cli.records import UNIT_FACTORS, read_accelerogram
from pounding_cli.records.metrics import metrics

REPO = Path(__file__).resolve().parents[2]
SHIPPED = REPO / "inputs" / "records" / "ridgecrest2019_ccc.mseed"
SCRIPT = REPO / "inputs" / "records" / "make_ridgecrest_mseed.py"
RAW = Path(__file__).resolve().parents[2] / "inputs" / "records" / "CICCC.RAW"  # shipped (USGS, CC0)
needs_raw = pytest.mark.skipif(not RAW.is_file(), reason=f"raw COSMOS record absent: {RAW}")

# PGA of the processed record, measured from the shipped file (printed by the script). Not the
# raw file's 0.567 g (E) / 0.471 g (N): the 0.1-25 Hz band-pass lowers the East peak.
PGA_G = {"HNE": 0.5256, "HNN": 0.4714}


def load_script() -> ModuleType:
    """Import make_ridgecrest_mseed.py (a standalone script, not part of the package)."""
    spec = importlib.util.spec_from_file_location("make_ridgecrest_mseed", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("channel", ["HNE", "HNN"])
def test_shipped_record(channel):
    rec = read_accelerogram(SHIPPED, trace=channel)
    assert rec.dt == 0.01
    assert rec.source.endswith(f"[CI.CCC..{channel}]")
    assert rec.start_time == "2019-07-06T03:20:03.000000Z"
    pga = np.abs(rec.acceleration).max() / UNIT_FACTORS["g"]
    assert pga == pytest.approx(PGA_G[channel], rel=0.02)
    assert abs(rec.acceleration[0]) < 1e-3 and abs(rec.acceleration[-1]) < 1e-3


def test_shipped_channels_have_the_same_length():
    east = read_accelerogram(SHIPPED, trace="HNE")
    north = read_accelerogram(SHIPPED, trace="HNN")
    assert east.acceleration.size == north.acceleration.size == 3401


def test_shipped_file_is_small():
    assert SHIPPED.stat().st_size < 1_000_000


def test_shipped_files_are_the_ones_the_readme_names():
    """inputs/records/README.md gives each shipped file's sha256: CICCC.RAW byte for byte as
    USGS publishes it, and the MiniSEED made from it."""
    import hashlib

    readme = (REPO / "inputs" / "records" / "README.md").read_text(encoding="utf-8")
    for path in (SHIPPED, RAW):
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
        assert f"| `{path.name}` |" in readme and f"`{digest}`" in readme, path.name
    assert hashlib.sha256(RAW.read_bytes()).hexdigest() == (
        "36f3e1828cc6753d74713b141a453ea361b4c31cfe813a248f18711ae4ac98e0"  # the shared README's
    )


@pytest.mark.parametrize("channel, arias, d5_95", [("HNE", "2.251", "10.12"), ("HNN", "3.230", "11.03")])
def test_readmes_quote_what_pound_record_gives(channel, arias, d5_95):
    """The Arias intensity (m/s) and D5-95 (s) of the shipped file in both READMEs are pound's
    own measures (pounding_cli.records.metrics), at the precision quoted."""
    m = metrics(read_accelerogram(SHIPPED, trace=channel).acceleration, 0.01)
    assert (f"{m.arias_intensity:.3f}", f"{m.significant_duration:.2f}") == (arias, d5_95)
    inputs_readme = " ".join((REPO / "inputs" / "records" / "README.md").read_text(encoding="utf-8").split())
    assert f"{channel} {arias} m/s, {d5_95} s" in inputs_readme
    table = (REPO / "docs" / "records" / "README.md").read_text(encoding="utf-8")
    assert f"| {arias} | {d5_95} |" in table


@needs_raw
def test_script_reproduces_shipped_file(tmp_path):
    """Rerun, the script writes the shipped file sample for sample, and prints the figures its
    README quotes (window, Arias intensity and D5-95 before and after windowing)."""
    import obspy

    output = tmp_path / "rerun.mseed"
    run = subprocess.run([sys.executable, str(SCRIPT), "--source", str(RAW), "--output", str(output)],
                         check=True, capture_output=True, text=True)
    rerun, shipped = obspy.read(str(output)), obspy.read(str(SHIPPED))
    assert len(rerun) == len(shipped) == 2
    for new, old in zip(rerun, shipped, strict=True):
        assert new.stats == old.stats
        assert np.array_equal(new.data, old.data)
    readme = " ".join((REPO / "inputs" / "records" / "README.md").read_text(encoding="utf-8").split())
    printed = re.findall(r"D5-95 (\d+\.\d\d) s \((\d+\.\d\d-\d+\.\d\d) s[^)]*\), Arias intensity (\d\.\d{3}) m/s", run.stdout)
    assert len(printed) == 4, run.stdout  # two channels, full record and shipped window
    for channel, ((d_full, span_full, ia_full), (d_win, span_win, ia_win)) in zip(
        ("HNE", "HNN"), zip(printed[0::2], printed[1::2], strict=True), strict=True
    ):
        assert f"{channel} {ia_full} m/s, {d_full} s ({span_full} s after the first raw sample)" in readme
        assert f"{channel} {ia_win} m/s, {d_win} s ({span_win} s into the file)" in readme


@needs_raw
def test_script_reads_the_raw_file_through_the_obspy_plugin():
    """The script reads CICCC.RAW with obspy.read (pound's COSMOS plugin): the horizontal
    channels with their own lengths, in m/s², and the header's raw peak."""
    stream = load_script().read_channels(RAW)
    assert [tr.stats.channel for tr in stream] == ["HNE", "HNN"]
    assert [tr.stats.npts for tr in stream] == [35430, 35402]
    east = stream[0]
    assert east.stats.sampling_rate == 100.0
    assert str(east.stats.starttime) == "2019-07-06T03:19:37.000000Z"
    peak = int(np.argmax(np.abs(east.data)))
    assert abs(east.data[peak]) / UNIT_FACTORS["g"] == pytest.approx(0.567, abs=0.0005)  # header: Max = -.567 g
    assert peak / east.stats.sampling_rate == pytest.approx(39.41, abs=0.01)  # at 39.410 sec
