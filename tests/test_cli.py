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
    """Per building: floor masses, periods, Rayleigh, its own Δt limit; then which limit sets Δt
    and what the default (hybrid) integrator will take. Plain lines are never wrapped, even at
    80 columns (a pipe); the numbers are the JSON's."""
    r = runner.invoke(app, ["validate", str(EXAMPLE)], env={"COLUMNS": "80"})
    assert r.exit_code == 0
    info = json.loads(runner.invoke(app, ["validate", str(EXAMPLE), "--json"]).stdout)
    left, right = info["buildings"]
    a = info["analysis"]
    assert left["dt_limit_s"] == pytest.approx(2 / left["omega_max_rad_s"], rel=1e-15)
    assert a["stability_limit_s"] == min(left["dt_limit_s"], right["dt_limit_s"]) == right["dt_limit_s"]
    assert a["dt_limited_by"] == "contact" and a["contact_limit_s"] < a["stability_limit_s"]
    assert a["dt_s"] <= a["dt_auto_fraction"] * a["contact_limit_s"]
    lines = r.stdout.splitlines()
    for line in ("  floors 1-4: m = 64 t, J = 6.827e+05 kg·m²", "  floors 1-3: m = 128 t, J = 3.413e+06 kg·m²",
                 f"  Δt limit (CDM): 2/ω_max = {left['dt_limit_s']:.4g} s (ω_max = {left['omega_max_rad_s']:.4g} rad/s)",
                 f"  Δt limit (CDM): 2/ω_max = {right['dt_limit_s']:.4g} s (ω_max = {right['omega_max_rad_s']:.4g} rad/s)",
                 "  Rayleigh: ζ = 0.05, 0.05 at modes 1, 3 → a0 = 0.8242 1/s, a1 = 0.0029439 s"):  # fmt: skip
        assert line in lines, r.stdout
    (dt_line,) = [ln for ln in lines if ln.startswith("  Δt = ")]
    assert dt_line == ("  Δt = 2.604e-06 s: auto, 0.00625 × 2/ω_contact — the contact limit governs (0.0004275 s; "
                       "the structure's: 0.01219 s, building right), shortened to divide the substep")  # fmt: skip
    (hybrid,) = [ln for ln in lines if ln.startswith("  integrator: ")]
    # 3,400 substeps of the whole 0.01 s record (and output) interval (ω_max·h = 1.64 ≤ 4), one
    # exact step each where nothing can touch: no two fit between samples
    assert a["substeps"] == a["steps"] == 3400
    assert f"hybrid — {a['steps']:,} exact steps while no contact is possible (3,400 substeps of 0.01 s);" in hybrid
    assert f"{a['steps_of_dt']:,} steps of Δt would span the whole 34 s" in hybrid
    assert any(ln.startswith("excitation: ") and ln.endswith("PGA X 0.526 g, Y 0.471 g") for ln in lines)
    assert max(map(len, lines)) > 80  # long lines kept whole


def test_validate_names_the_structure_limit_without_contact(tmp_path):
    doc = tomllib.loads(EXAMPLE.read_text())
    doc["contact"] = {"enabled": False}
    doc["analysis"]["integrator"] = "cdm"
    model = tmp_path / "m.json"
    model.write_text(json.dumps(doc))
    (tmp_path / "records").symlink_to(INPUTS / "records")
    r = runner.invoke(app, ["validate", str(model)])
    assert r.exit_code == 0, r.output
    assert ("  Δt = 0.0005882 s: auto, 0.05 × 2/ω_max — the structure's limit governs (0.01219 s, building right; "
            "no contact candidates), shortened to fit the output interval") in r.stdout.splitlines()  # fmt: skip
    assert "  integrator: cdm — the central difference method, 57,800 steps of Δt" in r.stdout.splitlines()


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


def test_progress_on_a_pipe_when_asked(tmp_path):
    """--progress with stderr a pipe (a log file, a batch job): plain lines on stderr, one per
    tenth done, ending at 100 %, and no terminal codes; without it a pipe gets none."""
    r = pound_cmd("run", EXAMPLE, "-o", tmp_path / "a.h5", "--progress")
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("integrating:")]
    percents = [int(ln.split()[1]) for ln in lines]
    assert percents == sorted(set(percents)) and len(percents) >= 5, r.stderr
    assert percents[-1] == 100 and all(p % 10 == 0 for p in percents)
    assert "\x1b" not in r.stderr
    quiet = pound_cmd("run", EXAMPLE, "-o", tmp_path / "b.h5")
    assert quiet.returncode == 0, quiet.stderr
    assert "integrating" not in quiet.stderr


def test_progress_in_process_when_asked(tmp_path):
    r = runner.invoke(app, ["run", str(EXAMPLE), "-o", str(tmp_path / "a.h5"), "--progress"])
    assert r.exit_code == 0, r.output
    assert "integrating: 100 %" in r.stderr.splitlines()
    assert "integrating" not in r.stdout


def test_run_summary_of_yielding_members_matches_the_hdf5(tmp_path):
    """`pound run --json` and the printed summary give, per kind of yielding member, how many
    yielded, the one of largest ductility and the one of largest residual deflection, as the
    file's /buildings/<b>/yielding says; peaks/ductility and peaks/residual_deflection are
    the yielding datasets under a second name (HDF5 hard links, no copy)."""
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
            # the largest residual deflection: the resultant over both local axes, the largest member
            residual = np.hypot(*g["residual_deflection"][()].T)
            r = group["largest_residual"]
            assert r["member"] == g["members"]["name"][int(np.argmax(residual))].decode()
            assert r["storey"] == g["members"]["storey"][int(np.argmax(residual))]
            assert r["residual_deflection_m"] == residual.max() > np.abs(g["residual_deflection"][()]).max()
            # per-member ductility and residual deflection are also under peaks/: the same datasets
            peaks = f[f"buildings/{name}/peaks"]
            for key in ("ductility", "residual_deflection"):
                assert peaks[key] == g[key], f"peaks/{key} is not a hard link to yielding/{key}"
    printed = runner.invoke(app, ["run", str(model), "-o", str(out), "--force"], env={"COLUMNS": "200"})
    group = summary["left"]["yielding"][0]
    line = (f"left: {group['yielded']} of {group['members']} columns yielded; largest ductility "
            f"{group['largest_ductility']['ductility']:.3g} ({group['largest_ductility']['member']}, storey")
    assert line in printed.stdout, printed.stdout
    r = group["largest_residual"]
    line = (f"largest residual |δ| {1e3 * r['residual_deflection_m']:.3g} mm ({r['member']}, storey {r['storey']})")
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

    def unstable(analysis, omega_max, duration, *args, **kwargs):
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
    """`pound validate` takes every shipped input, whatever it is: a record definition gives
    what `pound record` gives, a sweep file the cases `pound sweep --dry-run` lists."""
    text = path.read_text()
    sweep = path.name.endswith((".sweep.toml", ".sweep.json"))
    if sweep:  # the record is named by the sweep's base model
        text += (path.parent / tomllib.loads(text)["base"]).read_text()
    if "shared/records" in text and not SHARED.exists():
        pytest.skip("the model reads a record kept in ../shared, which is absent")
    r = runner.invoke(app, ["validate", str(path), "--json"])
    assert r.exit_code == 0, r.output
    if path.name.endswith((".record.toml", ".record.json")):
        same = runner.invoke(app, ["record", str(path), "--json"])
        assert json.loads(r.stdout) == json.loads(same.stdout)
    elif sweep:
        same = runner.invoke(app, ["sweep", str(path), "--dry-run", "--json", "--jobs", "1"])
        assert json.loads(r.stdout) == [json.loads(line) for line in same.stdout.splitlines()]
    else:
        assert json.loads(r.stdout)["file"] == str(path)


@pytest.mark.parametrize(("name", "text", "expected"), [
    ("bad.record.toml", 'name = "x"\n[L]\nfile = "{inputs}/records/ridgecrest2019_ccc.mseed"\nunits = "furlongs"\n',
     r"bad\.record\.toml: L\.units: "),
    ("bad.sweep.toml", 'base = "{inputs}/paper_pounding.toml"\nparameters = {{ "excitation.angel" = [0, 90] }}\n',
     r"excitation\.angel"),
])  # fmt: skip
def test_validate_names_the_file_and_field_of_a_bad_record_or_sweep(tmp_path, name, text, expected):
    """A record definition or sweep file in error: exit 2, the file and the field named, no
    model's complaints about missing buildings."""
    path = tmp_path / name
    path.write_text(text.format(inputs=INPUTS.as_posix()))
    r = runner.invoke(app, ["validate", str(path)])
    assert r.exit_code == 2, r.output
    assert re.search(expected, r.stderr), r.stderr
    assert "buildings" not in r.stderr, r.stderr


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
