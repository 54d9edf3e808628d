"""Sweep summary columns of yielding members: ``max_ductility[B]`` and
``max_residual_deflection_m[B]`` (buildings with inelastic columns) and
``peak_isolator_displacement_m[B]`` (base-isolated buildings), only for the
buildings that have them, equal to the case files' datasets, in the row schema, and usable as
``pound report DIR/ --y`` columns.

The sweep is tiny: the isolated building of inputs/isolated_moat.toml, its columns made
inelastic too, beside its linear neighbour; 3 s of the record; two moat gaps."""

from __future__ import annotations

import json
import re

import h5py
import jsonschema
import numpy as np
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.model import read_document
from pounding_cli.report.sweep_data import match_columns, open_sweep
from pounding_cli.report.sweep_document import sweep_summary, sweep_tables
from pounding_cli.report.sweep_lines import parameter_figure
from pounding_cli.schema import sweep_summary_schema
from pounding_cli.sweep import read_summary, run_sweep
from pounding_cli.sweep.columns import building_columns, storey_columns, yielding_columns

from conftest import INPUTS

runner = CliRunner()
GAPS = [0.05, 0.4]
SWEEP = """
title = "Isolated, inelastic superstructure: moat gap"
set = { "analysis.duration" = 3.0 }

[summary]
columns = { isolated = ["C5"] }

[parameters]
"buildings.isolated.isolation.moat.gap" = [0.05, 0.4]
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("yielding-sweep")
    doc = read_document(INPUTS / "isolated_moat.toml")
    for component in doc["excitation"]["record"].values():
        if isinstance(component, dict) and "file" in component:
            component["file"] = (INPUTS / component["file"]).as_posix()
    # columns that yield at 0.2 mm, so that they do within 3 s
    doc["hysteresis"] = {"rc": {"yield_deflection": [2e-4, 2e-4], "post_yield_ratio": 0.05}}
    for floor in doc["buildings"][0]["floors"]:
        floor["column_grid"]["hysteresis"] = "rc"
    (tmp / "model.json").write_text(json.dumps(doc), encoding="utf-8")
    path = tmp / "y.sweep.toml"
    path.write_text('base = "model.json"\n' + SWEEP, encoding="utf-8")
    outcome = run_sweep(path, tmp / "out", jobs=2)
    assert outcome.ok
    return tmp / "out"


@pytest.mark.slow
def test_columns_only_for_buildings_that_have_them(folder):
    sweep = open_sweep(folder)
    names = sweep.names("result")
    assert "max_ductility[isolated]" in names and "peak_isolator_displacement_m[isolated]" in names
    # every building has its deflection and force columns; the yielding ones only where members yield
    every = ("peak_isd_", "peak_base_shear_", "peak_base_torque_", "max_column_shear_")
    assert not [n for n in names if n.endswith("[neighbour]") and not n.startswith(every)]
    assert "max_ductility[neighbour]" not in names and "max_column_shear_N[neighbour]" in names
    # after the building's largest deflections and forces, before the per-storey columns
    i = names.index("peak_isd_theta_rad[isolated]")
    assert names[i + 1:i + 8] == ["peak_base_shear_x_N[isolated]", "peak_base_shear_y_N[isolated]",
                                  "peak_base_torque_Nm[isolated]", "max_column_shear_N[isolated]",
                                  "max_ductility[isolated]", "max_residual_deflection_m[isolated]",
                                  "peak_isolator_displacement_m[isolated]"]  # fmt: skip
    assert sweep.column("peak_isolator_displacement_m[isolated]")["units"] == "m"
    assert sweep.column("max_residual_deflection_m[isolated]")["units"] == "m"
    # the isolation storey counts: storey 1 below the base slab, then the four of the model
    assert "peak_isd_x_m[isolated/C5/5]" in names and "peak_isd_x_m[isolated/C5/6]" not in names


@pytest.mark.slow
def test_values_equal_the_case_files(folder):
    rows = read_summary(folder)
    assert [r["buildings.isolated.isolation.moat.gap"] for r in rows] == GAPS
    schema = sweep_summary_schema()
    for row in rows:
        jsonschema.validate(row, schema)
        with h5py.File(folder / row["file"]) as f:
            g = f["buildings/isolated/yielding"]
            kinds = np.array([k.decode() for k in g["members"]["kind"]])
            assert row["max_ductility[isolated]"] == g["ductility"][()][kinds == "column"].max()
            assert row["peak_isolator_displacement_m[isolated]"] == g["peak"][()][kinds == "isolator", 2].max()
            assert row["max_ductility[isolated]"] > 1  # the columns did yield
            # the resultant over both local axes of the most bent column, not the largest single axis
            residual = g["residual_deflection"][()][kinds == "column"]
            assert row["max_residual_deflection_m[isolated]"] == np.hypot(residual[:, 0], residual[:, 1]).max() > 0
            isd = f["buildings/isolated/peaks/interstorey_deflection"][()]
            assert row["peak_isd_x_m[isolated/C5/5]"] == isd[4, 4, 0]
    with h5py.File(folder / "summary.h5") as f:
        table = f["cases"][()]
        np.testing.assert_array_equal(table["max_ductility[isolated]"], [r["max_ductility[isolated]"] for r in rows])
    header = (folder / "summary.csv").read_text(encoding="utf-8").splitlines()[0].split(",")
    assert "max_ductility[isolated]" in header and "peak_isolator_displacement_m[isolated]" in header


@pytest.mark.slow
def test_report_shows_and_plots_them(folder, tmp_path):
    sweep = open_sweep(folder)
    assert match_columns(sweep, ["max_ductility[*]", "peak_isolator_displacement_m[*]"]) == [
        "max_ductility[isolated]", "peak_isolator_displacement_m[isolated]"]  # fmt: skip
    fig = parameter_figure(sweep, ys=["peak_isolator_displacement_m[isolated]", "max_ductility[isolated]"])
    by_label = {ax.get_ylabel(): ax for ax in fig.axes}
    disp = by_label["peak_isolator_displacement_m[isolated] (mm)"]
    np.testing.assert_allclose(disp.get_lines()[0].get_ydata(),
                               [1e3 * r["peak_isolator_displacement_m[isolated]"] for r in sweep.rows])  # fmt: skip
    np.testing.assert_array_equal(disp.get_lines()[0].get_xdata(), GAPS)
    assert "max_ductility[isolated]" in by_label
    _, cases = sweep_tables(sweep_summary(sweep))
    k = cases.headers.index("isolated μ max")
    assert [row[k] for row in cases.rows] == [f"{r['max_ductility[isolated]']:.4g}" for r in sweep.rows]
    assert "isolated isolator |δ| (mm)" in cases.headers
    out = tmp_path / "plots"
    r = runner.invoke(app, ["report", str(folder), "--y", "max_ductility[*]", "--plots", str(out)])
    assert r.exit_code == 0, r.output
    assert any(p.name.endswith("-columns.png") for p in out.iterdir())


def test_row_schema_knows_the_yielding_columns():
    schema = sweep_summary_schema()
    patterns = schema["patternProperties"]
    columns = yielding_columns("tower-2", True, True)
    assert [c.name for c in columns] == ["max_ductility[tower-2]", "max_residual_deflection_m[tower-2]",
                                         "peak_isolator_displacement_m[tower-2]"]  # fmt: skip
    assert yielding_columns("b", False, True)[0].name == "peak_isolator_displacement_m[b]"
    assert yielding_columns("b", False, False) == []
    for column in columns + building_columns("b") + storey_columns("b", "C1", 2):
        assert sum(bool(re.match(p, column.name)) for p in patterns) == 1, column.name
    row = {"max_ductility[b]": 2.5, "max_residual_deflection_m[b]": 0.01, "peak_isolator_displacement_m[b]": None}
    jsonschema.validate(row, {**schema, "required": []})
    for wrong in ({"max_ductility[b]": -1.0}, {"max_residual_deflection_m[b]": -1e-3}):
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(wrong, {**schema, "required": []})
