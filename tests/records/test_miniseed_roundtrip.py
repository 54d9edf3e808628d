"""A record written to MiniSEED by obspy and read back gives the same run, bit for bit."""

from __future__ import annotations

import numpy as np

import pounding_cli as pound
from pounding_cli.model import validate_model
from pounding_cli.records import read_accelerogram

from conftest import model_doc, square_building


def test_text_record_and_its_miniseed_copy_give_the_same_run(tmp_path):
    """A plain-text record in g, and the same samples in m/s² written by obspy as FLOAT64
    MiniSEED: the ground motion and every stored displacement are identical."""
    from obspy import Stream, Trace, UTCDateTime

    t = np.arange(301) * 0.01
    east = 0.3 * np.sin(2 * np.pi * 2.0 * t) * np.exp(-t)
    north = 0.2 * np.cos(2 * np.pi * 1.5 * t) * t * np.exp(-t)
    for name, values in (("e.txt", east), ("n.txt", north)):
        (tmp_path / name).write_text("\n".join(repr(float(v)) for v in values) + "\n")
    text_doc = model_doc(square_building(storeys=2), duration=3.0)
    text_doc["excitation"]["record"] = {
        "L": {"file": "e.txt", "units": "g", "dt": 0.01}, "T": {"file": "n.txt", "units": "g", "dt": 0.01},
    }  # fmt: skip

    traces = []
    for name, channel in (("e.txt", "HNE"), ("n.txt", "HNN")):
        record = read_accelerogram(tmp_path / name, units="g", dt=0.01)  # m/s²
        header = {"network": "XX", "station": "RT", "channel": channel, "delta": 0.01,
                  "starttime": UTCDateTime("2020-01-01T00:00:00")}
        traces.append(Trace(data=np.array(record.acceleration), header=header))
    Stream(traces).write(str(tmp_path / "copy.mseed"), format="MSEED", encoding="FLOAT64")
    mseed_doc = model_doc(square_building(storeys=2), duration=3.0)
    mseed_doc["excitation"]["record"] = {
        "L": {"file": "copy.mseed", "trace": "HNE", "units": "m/s2"},
        "T": {"file": "copy.mseed", "trace": "HNN", "units": "m/s2"},
    }

    a = pound.run_model(validate_model(text_doc, tmp_path / "text.toml"))
    b = pound.run_model(validate_model(mseed_doc, tmp_path / "mseed.toml"))
    assert a.complete and b.complete
    assert np.array_equal(a.ground_acceleration, b.ground_acceleration)
    assert np.array_equal(a.buildings["b"].displacement, b.buildings["b"].displacement)
    assert np.abs(a.buildings["b"].displacement).max() > 0
