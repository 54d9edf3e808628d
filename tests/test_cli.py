"""The `pound` command line: exit codes, JSON output, default output name, schemas."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tomllib

import h5py
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app

from conftest import EXAMPLE, INPUTS, ROOT, SHARED

runner = CliRunner()


def pound_cmd(*args, cwd=None):
    """Run the real console entry point in a subprocess."""
    return subprocess.run(
        [sys.executable, "-m", "pounding_cli", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=300
    )


def test_version():
    r = runner.invoke(app, ["--version"])
    assert r.exit_code == 0
    assert r.output.strip() == f"pound {pound.__version__}"


def test_validate_json():
    r = runner.invoke(app, ["validate", str(EXAMPLE), "--json"])
    assert r.exit_code == 0, r.output
    info = json.loads(r.stdout)
    left = info["buildings"][0]
    assert left["name"] == "left" and left["storeys"] == 4
    assert abs(left["periods_s"][0] - 0.44656) < 1e-4
    assert info["analysis"]["dt_s"] < info["analysis"]["stability_limit_s"]


def test_validate_prints_periods_and_time_step():
    r = runner.invoke(app, ["validate", str(EXAMPLE)], env={"COLUMNS": "120"})
    assert r.exit_code == 0
    for words in ("building left", "0.4466", "Rayleigh", "a0 =", "stability limit", "PGA X"):
        assert words in r.stdout


def test_run_subprocess_writes_file_and_json(tmp_path):
    out = tmp_path / "out.h5"
    r = pound_cmd("run", EXAMPLE, "-o", out, "--json")
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)  # stdout holds the JSON document and nothing else
    assert summary["status"] == "complete"
    assert summary["output"] == str(out)
    left = {b["name"]: b for b in summary["buildings"]}["left"]
    assert left["peak_interstorey_x"]["unit"] == "m"
    with h5py.File(out) as f:
        assert f.attrs["status"] == "complete"


def test_run_summary_of_yielding_members_matches_the_hdf5(tmp_path):
    """`pound run --json` and the printed summary give, per kind of yielding member, how many
    yielded and the one of largest ductility, as the file's /buildings/<b>/yielding says."""
    import numpy as np
    from pounding_cli.model import read_document

    doc = read_document(INPUTS / "paper_inelastic.toml")
    doc["analysis"]["duration"] = 16.0
    model = tmp_path / "model.json"
    model.write_text(json.dumps(doc))
    (tmp_path / "records").symlink_to(INPUTS / "records")
    out = tmp_path / "out.h5"
    r = runner.invoke(app, ["run", str(model), "-o", str(out), "--json"])
    assert r.exit_code == 0, r.output
    summary = {b["name"]: b for b in json.loads(r.stdout)["buildings"]}
    with h5py.File(out) as f:
        for name in ("left", "right"):
            g = f[f"buildings/{name}/yielding"]
            ductility = g["ductility"][()].max(axis=1)
            worst = int(np.argmax(ductility))
            (group,) = summary[name]["yielding"]
            assert group["kind"] == "column" and group["members"] == ductility.size
            assert group["yielded"] == int((ductility >= 1).sum()) > 0
            w = group["largest_ductility"]
            assert w["member"] == g["members"]["name"][worst].decode()
            assert w["ductility"] == pytest.approx(ductility[worst], rel=1e-12)
            assert w["peak_deflection_m"] == pytest.approx(g["peak"][worst, 2], rel=1e-12)
            assert w["residual_deflection_m"] == pytest.approx(np.hypot(*g["residual_deflection"][worst]), rel=1e-12)
    printed = runner.invoke(app, ["run", str(model), "-o", str(out), "--force"], env={"COLUMNS": "200"})
    group = summary["left"]["yielding"][0]
    line = (f"left: {group['yielded']} of {group['members']} columns yielded; largest ductility "
            f"{group['largest_ductility']['ductility']:.3g} ({group['largest_ductility']['member']}, storey")
    assert line in printed.stdout, printed.stdout


def test_run_default_output_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = runner.invoke(app, ["run", str(EXAMPLE), "--no-progress"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "paper_wide_gap.h5").exists()
    assert "complete" in r.stdout


def test_failed_run_exits_1_and_keeps_marked_file(tmp_path, monkeypatch):
    from pounding_cli import api
    from pounding_cli.assembly import TimeGrid

    def unstable(analysis, omega_max, duration, *args):
        limit = 2 / omega_max
        return TimeGrid(dt=1.05 * limit, stride=1, n_steps=int(duration / limit), stability_limit=limit)

    monkeypatch.setattr(api, "time_grid", unstable)
    out = tmp_path / "x.h5"
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(out)])
    assert r.exit_code == 1
    assert re.search(r"failed: (diverged|unstable) at step \d+ \(t = ", r.stderr)
    with h5py.File(out) as f:
        assert re.match(r"failed: (diverged|unstable)", f.attrs["status"])


def test_schemas_are_in_sync():
    """schemas/ holds exactly what `pound schema` writes (run it after changing a model)."""
    r = runner.invoke(app, ["schema", "--check", "--out", str(ROOT / "schemas")])
    assert r.exit_code == 0, r.output


def test_schema_writes_files(tmp_path):
    r = runner.invoke(app, ["schema", "--out", str(tmp_path)])
    assert r.exit_code == 0
    written = (tmp_path / "model.schema.json").read_text()
    assert written == (ROOT / "schemas" / "model.schema.json").read_text()
    schema = json.loads(written)
    height = schema["$defs"]["Floor"]["properties"]["height"]
    assert ", m," in height["description"]  # the unit travels with the description


def _all_fields(schema):
    for name, node in schema["$defs"].items():
        for field, spec in node.get("properties", {}).items():
            yield f"{name}.{field}", spec


def test_every_field_has_a_description():
    schema = pound.model.PoundModel.model_json_schema()
    missing = [name for name, spec in _all_fields(schema) if not spec.get("description")]
    assert not missing, f"fields without a description: {missing}"


@pytest.mark.parametrize("path", sorted(INPUTS.glob("*.toml")) + sorted(INPUTS.glob("*.json")), ids=lambda p: p.name)
def test_every_shipped_input_validates(path, tmp_path):
    text = path.read_text()
    sweep = path.name.endswith((".sweep.toml", ".sweep.json"))
    if sweep:  # the record is named by the sweep's base model
        text += (path.parent / tomllib.loads(text)["base"]).read_text()
    if "shared/records" in text and not SHARED.exists():
        pytest.skip("the model reads a record kept in ../shared, which is absent")
    command = ["record"] if path.name.endswith((".record.toml", ".record.json")) else ["validate"]
    if sweep:  # a sweep file: every case checked, nothing run
        command = ["sweep", "--dry-run", "--jobs", "1", "-o", str(tmp_path / "out")]
    r = runner.invoke(app, [command[0], str(path), *command[1:]])  # a record definition is checked by `pound record`
    assert r.exit_code == 0, r.output


def test_output_paths(tmp_path):
    """A missing output folder is created; an existing file is refused without --force
    (exit 2, nothing changed) and overwritten with it."""
    target = tmp_path / "new" / "deeper" / "x.h5"
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(target)])
    assert r.exit_code == 0, r.output
    stamp = target.stat().st_mtime_ns
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(target)])
    assert r.exit_code == 2
    assert "exists; choose another name or pass --force" in r.stderr
    assert target.stat().st_mtime_ns == stamp
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(target), "--force"])
    assert r.exit_code == 0, r.output



def test_unwritable_output_folder_is_refused(tmp_path, monkeypatch):
    """A folder the user cannot write to is exit 2 naming it, before any work (simulated: the
    tests may run as root, who can write anywhere)."""
    from pounding_cli import api

    real = os.access
    monkeypatch.setattr(api.os, "access", lambda path, mode: False if str(path) == str(tmp_path) else real(path, mode))
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(tmp_path / "x.h5")])
    assert r.exit_code == 2
    assert f"the folder {str(tmp_path)!r} is not writable" in r.stderr
    assert list(tmp_path.iterdir()) == []


def test_trace_may_be_an_integer_index():
    from conftest import load_doc, model_doc

    doc = model_doc()
    doc["excitation"]["record"]["L"]["trace"] = 0  # HNE is the first trace of the file
    doc["excitation"]["components"] = ["L"]
    info = pound.describe(load_doc(doc))
    assert abs(info["excitation"]["pga_g"]["X"] - 0.5256) < 1e-3
