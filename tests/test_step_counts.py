"""What `pound validate` says a run will take and what `pound run` says it took agree: the
integrator's name (the model's own, `cdm` or `hybrid`, everywhere) and the step counts.

A run over a duration T at step Δt takes T/Δt steps and passes T/Δt + 1 time points; the
counts are steps. They are integers compared exactly; the spans they cover are compared with
T to 1e-9 relative (Δt is a rounded division of the output interval).
"""

from __future__ import annotations

import copy
import json

import h5py
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.model import read_document, validate_model

from conftest import INPUTS, load_doc, model_doc, square_building

runner = CliRunner()


def one_building(integrator: str, duration: float = 2.0):
    return load_doc(model_doc(square_building(storeys=2), duration=duration, integrator=integrator))


def test_cdm_reports_steps_not_time_points(tmp_path):
    model = one_building("cdm")
    plan = pound.describe(model)["analysis"]
    assert plan["integrator"] == "cdm" and plan["substep_s"] is None
    n = plan["steps"]
    assert n == plan["steps_of_dt"] and n * plan["dt_s"] == pytest.approx(2.0, rel=1e-9)
    result = pound.run_model(model, output=tmp_path / "out.h5")
    d = result.diagnostics
    assert (d["integrator"], d["steps"], d["cdm_steps"], d["exact_substeps"]) == ("cdm", n, n, 0)
    assert result.time.size == n // round(plan["output_interval_s"] / plan["dt_s"]) + 1  # time points
    with h5py.File(tmp_path / "out.h5") as f:
        assert f["diagnostics"].attrs["integrator"] == "cdm" and f["diagnostics"].attrs["steps"] == n


def test_hybrid_without_contact_takes_the_substeps_validate_announces():
    model = one_building("auto")
    plan = pound.describe(model)["analysis"]
    assert plan["integrator"] == "hybrid"
    assert plan["substeps"] * plan["substep_s"] == pytest.approx(2.0, rel=1e-9)
    assert plan["substeps"] * plan["cdm_steps_per_substep"] == plan["steps_of_dt"]
    # one exact step per substep: the substep is the whole output interval here, so no two
    # fit between samples (doubles: test_time_history, test_approach)
    assert plan["steps"] == plan["substeps"] and plan["substep_s"] == pytest.approx(plan["output_interval_s"])
    d = pound.run_model(model).diagnostics
    assert (d["integrator"], d["steps"], d["exact_substeps"], d["cdm_steps"]) == ("hybrid", plan["steps"], plan["steps"], 0)
    assert d["exact_steps_of_dt"] == plan["steps_of_dt"]


@pytest.mark.parametrize("duration", [14.583, 16.0], ids=["ends-in-contact", "ends-exact"])
def test_hybrid_with_contact_steps_span_the_duration(duration):
    """The paper's pounding example, cut while the one impact (t = 14.582-14.584 s) still
    holds the CDM, and after it: the time propagated exactly (substeps, and the approach's
    shorter steps) and the CDM steps together span the duration."""
    doc = copy.deepcopy(read_document(INPUTS / "paper_pounding.toml"))
    doc["analysis"]["duration"] = duration
    doc["analysis"]["output_interval"] = 0.001  # (the analysis ends at a whole output interval)
    model = validate_model(doc, INPUTS / "paper_pounding.toml")
    plan = pound.describe(model)["analysis"]
    d = pound.run_model(model).diagnostics
    assert d["impacts"] == 1 and d["cdm_steps"] > 0
    assert d["switches"] % 2 == (1 if duration < 14.584 else 0)  # ended in the CDM / exact
    assert d["exact_steps_of_dt"] + d["cdm_steps"] == plan["steps_of_dt"]
    assert d["exact_substeps"] * plan["cdm_steps_per_substep"] > d["exact_steps_of_dt"]  # some were shorter
    assert d["steps"] == d["exact_substeps"] + d["cdm_steps"]
    assert plan["steps_of_dt"] * plan["dt_s"] == pytest.approx(duration, rel=1e-9)


def test_run_json_names_the_integrator_as_the_model_does(tmp_path):
    doc = model_doc(square_building(), duration=1.0, integrator="cdm")
    model = tmp_path / "m.json"
    model.write_text(json.dumps(doc))
    (tmp_path / "records").symlink_to(INPUTS / "records")
    r = runner.invoke(app, ["run", str(model), "-o", str(tmp_path / "out.h5"), "--json"])
    assert r.exit_code == 0, r.output
    summary = json.loads(r.stdout)
    assert summary["integrator"] == "cdm" and summary["substep_s"] is None
    v = runner.invoke(app, ["validate", str(model), "--json"])
    assert json.loads(v.stdout)["analysis"]["steps"] == summary["steps"]
