"""The command line's small frictions: shell completion, "$schema" in input files, TOML dates,
tables to a pipe, sweep --json as JSON Lines, --help placeholders and examples, run_sweep from
a plain script."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.errors import InputError
from pounding_cli.model import load_model, read_document
from pounding_cli.model.record import load_record
from pounding_cli.schema import model_schema, record_schema, sweep_schema

from conftest import INPUTS

runner = CliRunner()
COMMANDS = ["validate", "run", "sweep", "schema", "record", "bench", "report", "export"]


def pound(*args: str, env: dict[str, str] | None = None, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pounding_cli", *args], capture_output=True, text=True, timeout=600,
                          env={**os.environ, **(env or {})}, cwd=cwd)  # fmt: skip


# --- shell completion ----------------------------------------------------------------------


def test_completion_script_and_completions() -> None:
    # typer finds the user's shell itself (shellingham); a test has none to find, so it names
    # one, as typer's own tests do
    r = pound("--show-completion", "bash", env={"_TYPER_COMPLETE_TEST_DISABLE_SHELL_DETECTION": "1"})
    assert r.returncode == 0, r.stderr
    assert "_pound_completion()" in r.stdout and "_POUND_COMPLETE=complete_bash" in r.stdout
    assert "--install-completion" in runner.invoke(app, ["--help"]).stdout
    r = pound(env={"_POUND_COMPLETE": "complete_bash", "COMP_WORDS": "pound va", "COMP_CWORD": "1"})
    assert r.stdout.split() == ["validate"]
    r = pound(env={"_POUND_COMPLETE": "complete_bash", "COMP_WORDS": "pound export out.h5 --cs", "COMP_CWORD": "3"})
    assert r.stdout.split() == ["--csv"]


# --- "$schema" and #:schema ------------------------------------------------------------------


def test_json_model_with_schema_key_is_the_model_without_it(tmp_path: Path) -> None:
    doc = read_document(INPUTS / "paper_wide_gap.toml")
    for name in ("L", "T"):
        doc["excitation"]["record"][name]["file"] = str(INPUTS / doc["excitation"]["record"][name]["file"])
    (tmp_path / "plain.json").write_text(json.dumps(doc))
    (tmp_path / "tagged.json").write_text(json.dumps({"$schema": "../schemas/model.schema.json", **doc}))
    assert load_model(tmp_path / "tagged.json").model == load_model(tmp_path / "plain.json").model
    jsonschema.validate({"$schema": "../schemas/model.schema.json", **doc}, model_schema())
    r = runner.invoke(app, ["validate", str(tmp_path / "tagged.json"), "--json"])
    assert r.exit_code == 0, r.output


def test_toml_schema_comment_and_key_are_ignored(tmp_path: Path) -> None:
    text = (INPUTS / "paper_wide_gap.toml").read_text().replace('"records/', f'"{INPUTS}/records/')
    (tmp_path / "comment.toml").write_text("#:schema ../schemas/model.schema.json\n" + text)
    (tmp_path / "key.toml").write_text('"$schema" = "https://pound.invalid/schemas/model.schema.json"\n' + text)
    (tmp_path / "plain.toml").write_text(text)
    reference = load_model(tmp_path / "plain.toml").model
    assert load_model(tmp_path / "comment.toml").model == reference
    assert load_model(tmp_path / "key.toml").model == reference


def test_record_and_sweep_files_take_a_schema_key(tmp_path: Path) -> None:
    record = read_document(INPUTS / "ridgecrest2019_ccc.record.toml")
    for name in ("L", "T"):
        record[name]["file"] = str(INPUTS / record[name]["file"])
    (tmp_path / "r.record.json").write_text(json.dumps({"$schema": "record.schema.json", **record}))
    assert load_record(tmp_path / "r.record.json").L.trace == "HNE"
    jsonschema.validate({"$schema": "record.schema.json", **record}, record_schema())
    sweep = {"$schema": "sweep.schema.json", "base": str(INPUTS / "paper_wide_gap.toml"),
             "parameters": {"excitation.angle": [0, 90]}}  # fmt: skip
    jsonschema.validate(sweep, sweep_schema())
    (tmp_path / "s.sweep.json").write_text(json.dumps(sweep))
    r = runner.invoke(app, ["validate", str(tmp_path / "s.sweep.json"), "--json"])
    assert r.exit_code == 0, r.output
    assert len(json.loads(r.stdout)) == 2


def test_a_schema_key_that_is_no_text_is_refused(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps({"$schema": 3, **read_document(INPUTS / "paper_wide_gap.toml")}))
    with pytest.raises(InputError) as caught:
        load_model(tmp_path / "m.json")
    assert caught.value.field == '"$schema"' and "as text" in caught.value.message


# --- TOML dates ----------------------------------------------------------------------------


@pytest.mark.parametrize("value, text", [("1995-01-17", "1995-01-17"),
                                         ("1995-01-16T20:46:52Z", "1995-01-16T20:46:52+00:00"),
                                         ("1995-01-17 05:46:52", "1995-01-17T05:46:52")])  # fmt: skip
def test_a_toml_date_is_its_iso_text(value: str, text: str, tmp_path: Path) -> None:
    source = (INPUTS / "ridgecrest2019_ccc.record.toml").read_text().replace('"records/', f'"{INPUTS}/records/')
    path = tmp_path / "r.record.toml"
    path.write_text(f"date = {value}\n" + "\n".join(line for line in source.splitlines() if not line.startswith("date")))
    assert load_record(path).date == text
    doc = read_document(path)
    assert doc["date"] == text
    jsonschema.validate(doc, record_schema())
    date_schema = record_schema()["properties"]["date"]
    assert {"type": "string", "format": "date"} in date_schema["anyOf"]  # an editor takes an unquoted date


def test_a_toml_date_in_a_number_field_says_what_it_got(tmp_path: Path) -> None:
    text = (INPUTS / "paper_wide_gap.toml").read_text().replace("height = 3.0               # m", "height = 2024-03-01")
    (tmp_path / "m.toml").write_text(text.replace('"records/', f'"{INPUTS}/records/'))
    with pytest.raises(InputError) as caught:
        load_model(tmp_path / "m.toml")
    assert "buildings[0].floors[0].height" in str(caught.value) and "'2024-03-01'" in str(caught.value)


# --- tables to a pipe ------------------------------------------------------------------------


@pytest.mark.parametrize("columns", [None, "40"])
def test_tables_to_a_pipe_are_never_cut(columns: str | None) -> None:
    r = pound("validate", str(INPUTS / "paper_studies.sweep.toml"), env={"COLUMNS": columns} if columns else None)
    assert r.returncode == 0, r.stderr
    row = next(line for line in r.stdout.splitlines() if "case 3:" in line)
    assert "case 3: e_y = +0.4 m left, −0.4 m right, pounding" in row and row.rstrip().endswith("│")
    assert "…" not in r.stdout


# --- --help ----------------------------------------------------------------------------------


@pytest.mark.parametrize("command", [*COMMANDS, None])
def test_help_names_values_not_python_types_and_ends_with_examples(command: str | None) -> None:
    args = [command, "--help"] if command else ["--help"]
    r = runner.invoke(app, args, env={"COLUMNS": "200"}, prog_name="pound")
    assert r.exit_code == 0, r.output
    for python_type in ("<bool>", "<str>", "<path>", "<int>", "<float>", "<list"):
        assert python_type not in r.stdout, f"pound {command} --help shows {python_type}"
    tail = r.stdout.rstrip().split("Examples:")[-1].strip().splitlines()
    assert "Examples:" in r.stdout and 1 <= len(tail) <= 3, r.stdout[-400:]
    assert all(line.strip().startswith(f"pound {command or ''}".strip()) for line in tail if line.strip())


def test_help_placeholders_say_what_a_value_is() -> None:
    def line_of(command: str, option: str) -> list[str]:
        text = runner.invoke(app, [command, "--help"], env={"COLUMNS": "200"}, prog_name="pound").stdout
        words = next(line for line in text.splitlines() if f"{option} " in line).replace("│", " ").split()
        return [w for w in words if w != "*"]  # "*": required

    assert line_of("sweep", "--jobs")[:3] == ["--jobs", "-j", "N"]
    assert line_of("sweep", "--scheduler")[:2] == ["--scheduler", "URL"]
    assert line_of("sweep", "--output")[:3] == ["--output", "-o", "DIR"]
    assert line_of("export", "--csv")[:2] == ["--csv", "DIR"]
    assert line_of("run", "--output")[:3] == ["--output", "-o", "FILE"]
    assert line_of("record", "--dt")[:2] == ["--dt", "SECONDS"]


# --- sweep --json: JSON Lines; run_sweep from a plain script ---------------------------------


@pytest.fixture
def tiny_sweep(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.sweep.toml"
    path.write_text(f'base = "{INPUTS / "paper_wide_gap.toml"}"\n[parameters]\n"excitation.angle" = [0, 90]\n'
                    '"analysis.duration" = [0.5]\n')  # fmt: skip
    return path


def test_sweep_json_is_json_lines(tiny_sweep: Path, tmp_path: Path) -> None:
    r = pound("sweep", str(tiny_sweep), "-o", str(tmp_path / "out"), "--jobs", "2", "--json")
    assert r.returncode == 0, r.stderr
    rows = [json.loads(line) for line in r.stdout.splitlines()]
    assert [row["status"] for row in rows] == ["complete", "complete"]
    assert sorted(row["excitation.angle"] for row in rows) == [0, 90]


def test_run_sweep_from_a_plain_script_without_a_main_guard(tiny_sweep: Path, tmp_path: Path) -> None:
    script = tmp_path / "script.py"
    script.write_text("import pounding_cli\n\n"
                      f"outcome = pounding_cli.run_sweep({str(tiny_sweep)!r}, {str(tmp_path / 'out')!r}, jobs=2)\n"
                      "print(sorted(row['status'] for row in outcome.rows))\n")  # fmt: skip
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "['complete', 'complete']"
