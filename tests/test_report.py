"""`pound report`: the summary document, its JSON Schema, the tables, --column, failed runs.

The shipped pounding example runs once per module; its --json document must validate against
schemas/report.schema.json and its numbers must equal the HDF5 datasets.
"""

from __future__ import annotations

import json
import math

import h5py
import jsonschema
import numpy as np
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.report import summary

from conftest import EXAMPLE, INPUTS, ROOT

runner = CliRunner()
WIDE = {"COLUMNS": "160"}


@pytest.fixture(scope="module")
def pounding_h5(tmp_path_factory):
    """The shipped pounding example (one impact at the third floor), run once."""
    path = tmp_path_factory.mktemp("report") / "paper_pounding.h5"
    result = pound.run_model(INPUTS / "paper_pounding.toml", output=path)
    assert result.complete
    return path


@pytest.fixture(scope="module")
def failed_h5(tmp_path_factory):
    """The same model run at a time step beyond the stability limit: it fails, partially written."""
    from pounding_cli import api
    from pounding_cli.assembly import TimeGrid

    def unstable(analysis, omega_max, duration, *args, **kwargs):
        limit = 2 / omega_max
        return TimeGrid(dt=1.05 * limit, stride=1, n_steps=int(duration / limit), stability_limit=limit)

    path = tmp_path_factory.mktemp("failed") / "failed.h5"
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(api, "time_grid", unstable)
        result = pound.run_model(EXAMPLE, output=path)
    assert not result.complete
    return path


def _json(*args):
    r = runner.invoke(app, ["report", *map(str, args), "--json"])
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def _nan_to_none(values):
    return [None if math.isnan(v) else v for v in np.asarray(values, dtype=float).ravel()]


def test_json_validates_against_the_schema(pounding_h5):
    schema = json.loads((ROOT / "schemas" / "report.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    jsonschema.validate(_json(pounding_h5), schema, cls=jsonschema.Draft202012Validator)


def test_json_numbers_equal_the_hdf5_datasets(pounding_h5):
    doc = _json(pounding_h5)
    with h5py.File(pounding_h5) as f:
        assert doc["status"] == f.attrs["status"] == "complete" and doc["complete"]
        assert doc["input_sha256"] == f.attrs["input_sha256"]
        assert doc["title"] == json.loads(f.attrs["model"])["title"]
        for b in doc["buildings"]:
            g = f[f"buildings/{b['name']}"]
            names = [n.decode() for n in g["columns"]["name"]]
            isd = g["peaks/interstorey_deflection"][()]
            assert [c["name"] for c in b["columns"]] == names
            for c in b["columns"]:
                assert sum(c["interstorey_deflection"], []) == _nan_to_none(isd[names.index(c["name"])])
            assert b["periods_s"] == g["modes/period"][()].tolist()
            assert b["peak_displacement"] == g["peaks/displacement"][()].tolist()
            assert b["peak_acceleration"] == g["peaks/acceleration"][()].tolist()
            assert b["storeys"] == g["floors"].shape[0]
            assert b["mass_kg"] == g["floors"]["mass"].sum()
            x = b["peak_interstorey"]["x"]
            assert x["value"] == np.nanmax(isd[:, :, 0])
            assert x["value"] == isd[names.index(x["column"]), x["storey"] - 1, 0]
            assert [s["theta_rad"] for s in b["storey_peaks"]] == np.nanmax(isd[:, :, 2], axis=0).tolist()
        events = f["impacts/events"][()]
        assert doc["impacts"]["count"] == events.size == 1
        for row, e in zip(events, doc["impacts"]["events"]):
            for name, value in e.items():
                stored = row[name].decode() if isinstance(row[name], bytes) else row[name].item()
                assert value == (None if isinstance(stored, float) and math.isnan(stored) else stored), name
        assert doc["impacts"]["peak_normal_force_N"] == events["peak_normal_force"].max()
        pairs = f["impacts/pairs"][()]
        assert [p["k_normal_N_per_m2"] for p in doc["impacts"]["pairs"]] == pairs["k_normal"].tolist()
        energy = f["energy"][()]
        assert list(doc["energy"]["final_J"].values()) == energy[-1].tolist()
        assert doc["energy"]["max_input_J"] == np.abs(energy[:, 0]).max()
        assert doc["analysis"]["dt_s"] == f["diagnostics"].attrs["dt"]
        assert doc["analysis"]["duration_s"] == f["time"][-1]
        assert doc["record"]["pga_X_g"] == np.abs(f["ground/acceleration"][:, 0]).max() / 9.80665
        assert doc["diagnostics"]["steps"] == f["diagnostics"].attrs["steps"]


def test_python_api_is_the_cli_document(pounding_h5):
    assert summary(pounding_h5) == _json(pounding_h5)


def test_column_narrows_to_one_column(pounding_h5):
    doc = _json(pounding_h5, "--column", "C9")
    assert doc["column"] == "C9"
    assert [[c["name"] for c in b["columns"]] for b in doc["buildings"]] == [["C9"], ["C9"]]
    doc = _json(pounding_h5, "--column", "left:C9")
    assert [[c["name"] for c in b["columns"]] for b in doc["buildings"]] == [["C9"], []]
    r = runner.invoke(app, ["report", str(pounding_h5), "--column", "left:C9"], env=WIDE)
    assert r.exit_code == 0
    assert "left, column C9" in r.stdout and "right, column" not in r.stdout
    c9 = np.array(doc["buildings"][0]["columns"][0]["interstorey_deflection"])
    assert f"{1e3 * c9[0, 0]:.4g}" in r.stdout  # storey 1, Δx in mm


def test_unknown_column_is_a_usage_error(pounding_h5):
    r = runner.invoke(app, ["report", str(pounding_h5), "--column", "C99"])
    assert r.exit_code == 2
    assert "--column: no building has a column 'C99'" in r.stderr and "left:C9" in r.stderr


def test_tables_show_the_run(pounding_h5):
    r = runner.invoke(app, ["report", str(pounding_h5)], env=WIDE)
    assert r.exit_code == 0, r.output
    doc = summary(pounding_h5)
    text = r.stdout
    assert text.lstrip().startswith("Run")  # no warning above a complete run
    for words in ("Paper example", "Ridgecrest", "hybrid", "Δt", "solver", "T1 (s)", "0.4466",
                  "energy balance error", "Impacts per contact pair", "left floor 3", "right floor 3",
                  "Largest peak interstorey deflection", "storey 1"):  # fmt: skip
        assert words in text, words
    peak = doc["impacts"]["peak"]
    assert f"{peak['peak_normal_force'] / 1e3:,.0f} kN" in text
    x = doc["buildings"][0]["peak_interstorey"]["x"]
    assert f"{1e3 * x['value']:.3g} ({x['column']}, storey {x['storey']})" in text


def test_failed_run_says_so_at_the_top(failed_h5):
    r = runner.invoke(app, ["report", str(failed_h5)], env=WIDE)
    assert r.exit_code == 0
    first = r.stdout.strip().splitlines()[0]
    assert first.startswith("FAILED RUN: ") and ("diverged" in first or "unstable" in first)
    assert "results are partial" in r.stdout and "results are partial" in r.stderr
    doc = _json(failed_h5)
    assert doc["complete"] is False and doc["status"].startswith("failed: ")
    assert doc["analysis"]["duration_s"] < 34.0


def test_several_files_give_a_list(pounding_h5, failed_h5):
    docs = _json(pounding_h5, failed_h5)
    assert [d["file"] for d in docs] == [str(pounding_h5), str(failed_h5)]
    r = runner.invoke(app, ["report", str(pounding_h5), str(failed_h5)], env=WIDE)
    assert r.stdout.count("Run") >= 2 and "FAILED RUN" in r.stdout


def test_what_is_not_a_result_file(tmp_path):
    text = tmp_path / "notes.h5"
    text.write_text("not hdf5")
    for path, words in ((tmp_path / "none.h5", "no such file"), (text, "cannot read it as HDF5"),
                        (tmp_path, "not a sweep output folder")):  # fmt: skip
        r = runner.invoke(app, ["report", str(path)])
        assert r.exit_code == 2, path
        assert words in r.stderr
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = 1
    r = runner.invoke(app, ["report", str(other)])
    assert r.exit_code == 2 and "not a pound result file" in r.stderr


def test_json_does_not_load_matplotlib(pounding_h5):
    """--json is for scripts: it answers without importing the plotting stack."""
    import subprocess
    import sys

    code = ("import sys; from typer.testing import CliRunner; from pounding_cli.cli import app; "
            f"r = CliRunner().invoke(app, ['report', {str(pounding_h5)!r}, '--json']); "
            "assert r.exit_code == 0, r.output; assert 'matplotlib' not in sys.modules")  # fmt: skip
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
