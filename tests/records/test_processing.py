"""Processing and scaling of a record: units, each obspy step in its order, common Δt and span,
scale and target PGA."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pounding_cli.errors import InputError
from pounding_cli.model.record import Record
from pounding_cli.records.combine import G, RecordOrigin, record_motion

EPS = np.finfo(float).eps


def write_column(folder: Path, name: str, values) -> str:
    """A one-column text record; returns its file name."""
    (folder / name).write_text("\n".join(repr(float(v)) for v in values) + "\n")
    return name


def motion(folder: Path, components: dict, processing: dict | None = None):
    record = Record.model_validate({**components, "processing": processing or {}})
    return record_motion(record, RecordOrigin(folder / "r.record.toml"))


def wave(n: int = 2001, dt: float = 0.01, seed: int = 3) -> np.ndarray:
    """A reproducible accelerogram-like signal with an offset and a trend (values in g)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    return 0.3 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.2 * t) + 0.05 * rng.standard_normal(n) + 0.01 + 0.002 * t


# --- units and scaling: exact --------------------------------------------------------------------


@pytest.mark.parametrize(("units", "factor"), [("g", 9.80665), ("m/s2", 1.0), ("cm/s2", 0.01), ("gal", 0.01)])
def test_unit_conversion_is_exact(tmp_path, units, factor):
    """Each value is multiplied once by the unit's factor: the same float as numpy's product."""
    values = np.array([0.0, 0.125, -0.3, 1.0 / 3.0, 7.5e-4])
    name = write_column(tmp_path, "a.txt", values)
    m = motion(tmp_path, {"L": {"file": name, "units": units, "dt": 0.01}})
    assert np.array_equal(m.acceleration["L"], values * factor)


def test_scale_is_exact(tmp_path):
    values = wave()
    name = write_column(tmp_path, "a.txt", values)
    m = motion(tmp_path, {"L": {"file": name, "units": "g", "dt": 0.01}}, {"scale": 1.7})
    assert np.array_equal(m.acceleration["L"], (values * G) * 1.7)
    assert m.factor == 1.7


def test_target_pga_uses_the_larger_component(tmp_path):
    """One factor for both components; the larger PGA becomes the target. Exact to one
    rounding of the factor and one of the product: |PGA − target| ≤ 2 ulp."""
    east, north = wave(seed=1), 0.5 * wave(seed=2)
    comps = {"L": {"file": write_column(tmp_path, "e.txt", east), "units": "g", "dt": 0.01},
             "T": {"file": write_column(tmp_path, "n.txt", north), "units": "g", "dt": 0.01}}
    m = motion(tmp_path, comps, {"target_pga": 0.4})
    pga = {k: np.abs(v).max() for k, v in m.acceleration.items()}
    target = 0.4 * G
    assert abs(pga["L"] - target) <= 2 * EPS * target
    factor = target / (np.abs(east).max() * G)
    assert m.factor == factor
    assert np.array_equal(m.acceleration["T"], (north * G) * factor)  # the same factor on T
    assert any("becomes 0.4 g" in note for note in m.notes)


def test_target_pga_of_a_zero_record_is_refused(tmp_path):
    name = write_column(tmp_path, "z.txt", np.zeros(10))
    with pytest.raises(InputError, match=r"processing.target_pga: .*zero throughout"):
        motion(tmp_path, {"L": {"file": name, "units": "g", "dt": 0.01}}, {"target_pga": 0.3})


# --- each obspy step, in order ---------------------------------------------------------------


def obspy_reference(values_si: np.ndarray, dt: float, steps) -> np.ndarray:
    from obspy import Trace

    tr = Trace(data=values_si.copy(), header={"delta": dt})
    for step in steps:
        step(tr)
    return tr.data


PIPELINE = {
    "demean": ({"demean": True}, [lambda t: t.detrend("demean")]),
    "detrend": ({"detrend": True}, [lambda t: t.detrend("linear")]),
    "taper": ({"taper": 0.05}, [lambda t: t.taper(max_percentage=0.05, type="cosine")]),
    "bandpass": ({"filter": {"freqmin": 0.1, "freqmax": 20.0}},
                 [lambda t: t.filter("bandpass", freqmin=0.1, freqmax=20.0, corners=4, zerophase=True)]),
    "highpass causal": ({"filter": {"freqmin": 0.2, "corners": 2, "zerophase": False}},
                        [lambda t: t.filter("highpass", freq=0.2, corners=2, zerophase=False)]),
    "lowpass": ({"filter": {"freqmax": 10.0}}, [lambda t: t.filter("lowpass", freq=10.0, corners=4, zerophase=True)]),
    "all in order": (
        {"demean": True, "detrend": True, "taper": 0.1, "filter": {"freqmin": 0.1, "freqmax": 20.0},
         "window": {"start": 2.0, "end": 12.5}},
        [lambda t: t.detrend("demean"), lambda t: t.detrend("linear"),
         lambda t: t.taper(max_percentage=0.1, type="cosine"),
         lambda t: t.filter("bandpass", freqmin=0.1, freqmax=20.0, corners=4, zerophase=True),
         lambda t: t.trim(t.stats.starttime + 2.0, t.stats.starttime + 12.5, nearest_sample=True)],
    ),
}  # fmt: skip


@pytest.mark.parametrize("case", list(PIPELINE))
def test_processing_is_obspys_in_the_documented_order(tmp_path, case):
    settings, steps = PIPELINE[case]
    values = wave()
    name = write_column(tmp_path, "a.txt", values)
    m = motion(tmp_path, {"L": {"file": name, "units": "g", "dt": 0.01}}, settings)
    assert np.array_equal(m.acceleration["L"], obspy_reference(values * G, 0.01, steps))


def test_window_keeps_the_nearest_samples_both_ends_included(tmp_path):
    values = np.arange(1001, dtype=float)
    name = write_column(tmp_path, "a.txt", values)
    m = motion(tmp_path, {"L": {"file": name, "units": "m/s2", "dt": 0.01}}, {"window": {"start": 1.004, "end": 2.006}})
    assert m.acceleration["L"][0] == 100.0 and m.acceleration["L"][-1] == 201.0
    m = motion(tmp_path, {"L": {"file": name, "units": "m/s2", "dt": 0.01}}, {"window": {"start": 9.0}})
    assert m.acceleration["L"].tolist() == values[900:].tolist()


@pytest.mark.parametrize(("window", "field"), [({"start": 10.5}, "window.start"), ({"start": 1.0, "end": 10.2}, "window.end")])
def test_window_outside_the_record(tmp_path, window, field):
    name = write_column(tmp_path, "a.txt", np.ones(1001))
    with pytest.raises(InputError, match=rf"processing.{field}: .*not inside the record, which lasts 10 s"):
        motion(tmp_path, {"L": {"file": name, "units": "m/s2", "dt": 0.01}}, {"window": window})


@pytest.mark.parametrize(("flt", "field"), [({"freqmin": 0.1, "freqmax": 50.0}, "freqmax"), ({"freqmin": 60.0}, "freqmin")])
def test_filter_corner_at_or_above_nyquist(tmp_path, flt, field):
    name = write_column(tmp_path, "a.txt", wave())
    with pytest.raises(InputError) as info:
        motion(tmp_path, {"L": {"file": name, "units": "g", "dt": 0.01}}, {"filter": flt})
    message = str(info.value)
    assert f"r.record.toml: processing.filter.{field}: " in message
    assert "is not below the Nyquist frequency 50 Hz" in message and "a.txt" in message


# --- common Δt and span ------------------------------------------------------------------------


def test_different_intervals_are_resampled_linearly_with_a_note(tmp_path):
    coarse = np.array([0.0, 1.0, 0.0, -1.0, 0.0])
    fine = np.zeros(9)
    comps = {"L": {"file": write_column(tmp_path, "c.txt", coarse), "units": "m/s2", "dt": 0.02},
             "T": {"file": write_column(tmp_path, "f.txt", fine), "units": "m/s2", "dt": 0.01}}
    m = motion(tmp_path, comps)
    assert m.dt == 0.01
    # to 1e-15: the sample times i·Δt are rounded floats, so the interpolation weights are too
    np.testing.assert_allclose(m.acceleration["L"], [0, 0.5, 1, 0.5, 0, -0.5, -1, -0.5, 0], rtol=0, atol=1e-15)
    assert any("resampled linearly to 0.01 s" in note for note in m.notes)


def test_different_intervals_refused_when_resampling_is_off(tmp_path):
    comps = {"L": {"file": write_column(tmp_path, "c.txt", np.zeros(5)), "units": "m/s2", "dt": 0.02},
             "T": {"file": write_column(tmp_path, "f.txt", np.zeros(9)), "units": "m/s2", "dt": 0.01}}
    with pytest.raises(InputError) as info:
        motion(tmp_path, comps, {"resample": False})
    assert "r.record.toml: processing.resample: the components have different sample intervals (L: 0.02 s, T: 0.01 s)" in str(info.value)


def test_unequal_lengths_are_cut_to_the_common_span_with_a_note(tmp_path):
    comps = {"L": {"file": write_column(tmp_path, "a.txt", np.arange(10.0)), "units": "m/s2", "dt": 0.01},
             "T": {"file": write_column(tmp_path, "b.txt", np.arange(7.0)), "units": "m/s2", "dt": 0.01}}
    m = motion(tmp_path, comps)
    assert m.points == 7 and m.acceleration["L"].tolist() == list(range(7))
    assert any("cut to the common 0.06 s" in note for note in m.notes)
