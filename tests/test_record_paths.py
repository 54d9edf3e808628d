"""Record paths: a model names its record files (and a record definition file) relative to
itself or absolutely, and a record definition names its component files relative to itself;
never relative to the current directory. A missing file is exit 2 naming the file and field.

Every test runs from another directory (monkeypatch.chdir) that holds decoys: files of the
same relative names, holding garbage, that would be read if a path were taken relative to
the current directory.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app

from conftest import model_doc, square_building

DATA = Path(__file__).parent / "records" / "data"
runner = CliRunner()


def invoke(*args: str):
    result = runner.invoke(app, [*map(str, args)], env={"POUND_DEBUG": "1", "COLUMNS": "200"})
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """tmp/project/models/{inline.json, named.json, defs/rec.record.toml, defs/data/quake.AT2},
    tmp/project/records/quake.AT2, and decoys in tmp/elsewhere at the same relative paths."""
    models = tmp_path / "project" / "models"
    (models / "defs" / "data").mkdir(parents=True)
    (tmp_path / "project" / "records").mkdir()
    shutil.copy(DATA / "synthetic.AT2", tmp_path / "project" / "records" / "quake.AT2")
    shutil.copy(DATA / "synthetic.AT2", models / "defs" / "data" / "quake.AT2")
    (models / "defs" / "rec.record.toml").write_text(
        'name = "paths"\n[L]\nfile = "data/quake.AT2"\nunits = "g"\n[T]\nfile = "data/quake.AT2"\nunits = "g"\n'
    )
    inline = model_doc(square_building(size=6.0), duration=0.2)
    for c in ("L", "T"):
        inline["excitation"]["record"][c] = {"file": "../records/quake.AT2", "units": "g"}
    (models / "inline.json").write_text(json.dumps(inline))
    named = model_doc(square_building(size=6.0), duration=0.2)
    named["excitation"]["record"] = "defs/rec.record.toml"
    (models / "named.json").write_text(json.dumps(named))
    elsewhere = tmp_path / "elsewhere"
    for decoy in ("../records/quake.AT2", "records/quake.AT2", "data/quake.AT2", "defs/data/quake.AT2"):
        (elsewhere / "x" / decoy).parent.mkdir(parents=True, exist_ok=True)
        (elsewhere / "x" / decoy).write_bytes(b"\x00 decoy: read relative to the current directory\n")
    (elsewhere / "x" / "defs" / "rec.record.toml").write_text("decoy = [")
    return tmp_path


def pga(result) -> float:
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)["excitation"]["pga_g"]["X"]


@pytest.mark.parametrize("model", ["inline.json", "named.json"])
def test_record_paths_are_relative_to_the_model_not_the_current_directory(project, monkeypatch, model):
    models = project / "project" / "models"
    monkeypatch.chdir(models)
    expected = pga(invoke("validate", model, "--json"))
    assert expected > 0
    for cwd, named in [(project, f"project/models/{model}"), (project / "elsewhere" / "x", models / model),
                       (project / "elsewhere", Path("..") / "project" / "models" / model)]:  # fmt: skip
        monkeypatch.chdir(cwd)
        assert pga(invoke("validate", named, "--json")) == expected, (cwd, named)


def test_component_paths_are_relative_to_the_definition(project, monkeypatch):
    definition = project / "project" / "models" / "defs" / "rec.record.toml"
    monkeypatch.chdir(project / "elsewhere" / "x")
    for named in (definition, Path("../..") / definition.relative_to(project)):
        result = invoke("record", named, "--json")
        assert result.exit_code == 0, result.stderr
        assert [c["points"] for c in json.loads(result.stdout)["components"]] == [23, 23]


def test_absolute_record_paths(project, monkeypatch):
    models = project / "project" / "models"
    doc = json.loads((models / "inline.json").read_text())
    for c in ("L", "T"):
        doc["excitation"]["record"][c]["file"] = str(project / "project" / "records" / "quake.AT2")
    (models / "absolute.json").write_text(json.dumps(doc))
    monkeypatch.chdir(project / "elsewhere" / "x")
    assert pga(invoke("validate", models / "absolute.json", "--json")) > 0


def test_a_loaded_model_keeps_its_folder_when_the_directory_changes(project, monkeypatch):
    """The API: a model loaded by a relative path still finds its record definition after chdir."""
    monkeypatch.chdir(project / "project")
    loaded = pound.load_model("models/named.json")
    monkeypatch.chdir(project / "elsewhere" / "x")
    assert pound.prepare(loaded).ground.acceleration.shape[0] == 23


def test_a_loaded_model_with_an_inline_record_keeps_its_folder(project, monkeypatch):
    monkeypatch.chdir(project / "project")
    loaded = pound.load_model("models/inline.json")
    monkeypatch.chdir(project / "elsewhere" / "x")
    assert pound.prepare(loaded).ground.acceleration.shape[0] == 23


# --- missing files: exit 2 naming the file and the field ------------------------------------------


def refused(*args: str) -> str:
    result = invoke(*args)
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr)
    return result.stderr


def test_missing_component_file_of_an_inline_record(project, monkeypatch):
    models = project / "project" / "models"
    (project / "project" / "records" / "quake.AT2").unlink()
    monkeypatch.chdir(project / "elsewhere")  # holds records/quake.AT2 relative to itself: not read
    message = refused("validate", models / "inline.json")
    assert f"{models / 'inline.json'}: excitation.record.L.file: " in message
    assert f"{project / 'project' / 'records' / 'quake.AT2'}: no such file" in message


def test_missing_record_definition_file(project, monkeypatch):
    models = project / "project" / "models"
    (models / "defs" / "rec.record.toml").unlink()
    monkeypatch.chdir(project / "elsewhere" / "x")  # holds a defs/rec.record.toml decoy
    message = refused("validate", models / "named.json")
    assert f"{models / 'named.json'}: excitation.record: " in message
    assert str(models / "defs" / "rec.record.toml") in message


def test_missing_component_file_of_a_record_definition(project, monkeypatch):
    models = project / "project" / "models"
    definition = models / "defs" / "rec.record.toml"
    definition.write_text(definition.read_text().replace('file = "data/quake.AT2"', 'file = "data/gone.AT2"', 1))
    monkeypatch.chdir(project / "elsewhere" / "x")
    message = refused("validate", models / "named.json")
    assert f"{models / 'named.json'}: excitation.record: {definition}: L.file: " in message
    assert f"{models / 'defs' / 'data' / 'gone.AT2'}: no such file" in message
    message = refused("record", definition)
    assert f"{definition}: L.file: {models / 'defs' / 'data' / 'gone.AT2'}: no such file" in message


def test_missing_record_file_given_to_pound_record(project, monkeypatch):
    monkeypatch.chdir(project / "elsewhere")
    message = refused("record", "nowhere/quake.AT2")
    assert "nowhere/quake.AT2: no such file" in message


def test_a_component_file_name_with_a_nul_is_refused(tmp_path):
    """A component's file name holding a NUL (the record fuzzer drew one) is no file name at all:
    exit 2 naming the field, not a crash in the path's resolution."""
    definition = tmp_path / "nul.record.toml"
    definition.write_text('[L]\nfile = "a\\u0000b.txt"\ndt = 0.01\nunits = "g"\n')
    result = runner.invoke(app, ["record", str(definition)], env={"POUND_DEBUG": "1", "COLUMNS": "200"})
    assert result.exit_code == 2, result.stderr
    assert "L.file" in result.stderr and "NUL" in result.stderr
