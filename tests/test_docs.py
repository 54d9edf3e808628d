"""The docs agree with the code.

- the generated references (docs/reference/*.md) equal a fresh generation;
- every command has a help text and is documented in the CLI reference and the user guide;
- every field of every input model is in the model-fields reference;
- the TOML blocks of the user guide parse, complete models validate (and assemble, with
  their records found relative to docs/), and blocks quoted from an input file are verbatim;
- the Python snippets of the user guide run against a fresh result of the worked example;
- the error messages quoted in the user guide are what `pound validate` prints.
"""

from __future__ import annotations

import contextlib
import importlib.util
import os
import re
import shutil
import sys
import tomllib
import typing
from pathlib import Path

import pytest
import typer
from pydantic import BaseModel
from typer.testing import CliRunner

import pounding_cli
from pounding_cli.cli import app
from pounding_cli.model import PoundModel, validate_model

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
GUIDE = DOCS / "user-guide.md"
REGENERATE = "run python docs/generate_reference.py"
ERROR_DIR = "/tmp/project/inputs"  # the folder the guide's error examples were run in


def _generator():
    spec = importlib.util.spec_from_file_location("generate_reference", DOCS / "generate_reference.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while the class is built
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def generator():
    return _generator()


def _blocks(text: str, language: str) -> list[tuple[int, str, str]]:
    """(line number, marker comment or "", body) of every fenced block in `language`."""
    out = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        if lines[i].strip() == f"```{language}":
            start = i
            body = []
            i += 1
            while i < len(lines) and lines[i].strip() != "```":
                body.append(lines[i])
                i += 1
            before = [ln.strip() for ln in lines[:start] if ln.strip()]
            marker = before[-1] if before and before[-1].startswith("<!--") else ""
            out.append((start + 1, marker, "\n".join(body) + "\n"))
        i += 1
    return out


# --- (a) generated references ----------------------------------------------------------------


def test_generated_references_are_up_to_date(generator):
    for path, text in generator.generated_files().items():
        assert path.exists(), f"{path.relative_to(REPO)} is missing: {REGENERATE}"
        on_disk = path.read_text(encoding="utf-8")
        assert on_disk == text, f"{path.relative_to(REPO)} is out of date: {REGENERATE}"


def test_generation_is_deterministic(generator):
    assert generator.cli_markdown() == generator.cli_markdown()
    assert generator.model_fields_markdown() == generator.model_fields_markdown()
    assert "\x1b" not in generator.cli_markdown(), "escape codes in the CLI reference"


def test_check_mode_reports_stale_files(generator, tmp_path, monkeypatch):
    monkeypatch.setattr(generator, "MODEL_FIELDS", tmp_path / "model-fields.md")
    monkeypatch.setattr(generator, "CLI", tmp_path / "cli.md")
    monkeypatch.setattr(generator, "REFERENCE", tmp_path)
    monkeypatch.setattr(generator, "DOCS", tmp_path)
    assert generator.main(["--check"]) == 1
    assert generator.main([]) == 0
    assert generator.main(["--check"]) == 0
    (tmp_path / "cli.md").write_text("stale\n", encoding="utf-8")
    assert generator.main(["--check"]) == 1


# --- (b) commands ----------------------------------------------------------------------------


def _commands() -> dict[str, typing.Any]:
    group = typer.main.get_command(app)
    return dict(group.commands)


def test_every_command_has_help_and_is_documented():
    cli_md = (DOCS / "reference" / "cli.md").read_text(encoding="utf-8")
    guide = GUIDE.read_text(encoding="utf-8")
    commands = _commands()
    assert {"validate", "run", "schema"} <= set(commands)
    for name, command in commands.items():
        assert (command.help or "").strip(), f"command {name!r} has no help text"
        assert f"## `pound {name}`" in cli_md, f"pound {name} is not in docs/reference/cli.md: {REGENERATE}"
        assert f"pound {name}" in guide, f"pound {name} is not described in docs/user-guide.md"


def test_every_option_is_in_the_user_guide():
    guide = GUIDE.read_text(encoding="utf-8")
    group = typer.main.get_command(app)
    params = [(None, p) for p in group.params]
    params += [(name, p) for name, c in group.commands.items() for p in c.params]
    for command, param in params:
        for flag in [*param.opts, *param.secondary_opts]:
            if flag.startswith("--") and flag != "--help":
                where = f"pound {command}" if command else "pound"
                assert f"`{flag}" in guide or f"{flag}`" in guide or f"/{flag}" in guide, (
                    f"option {flag} of {where} is not mentioned in docs/user-guide.md"
                )


# --- (c) model fields ------------------------------------------------------------------------


def _models(cls: type[BaseModel], seen: dict[str, type[BaseModel]] | None = None) -> dict[str, type[BaseModel]]:
    """Every pydantic model reachable from `cls` through its fields' annotations."""
    seen = {} if seen is None else seen
    if cls.__name__ in seen:
        return seen
    seen[cls.__name__] = cls

    def walk(tp: typing.Any) -> None:
        if isinstance(tp, type) and issubclass(tp, BaseModel):
            _models(tp, seen)
        for arg in typing.get_args(tp):
            walk(arg)

    for info in cls.model_fields.values():
        walk(info.annotation)
    return seen


def _reference_sections(text: str) -> dict[str, str]:
    """Anchor id -> the text of that section of model-fields.md."""
    parts = re.split(r'<a id="([^"]+)"></a>', text)
    return {parts[i]: parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def test_every_model_field_is_in_the_reference():
    text = (DOCS / "reference" / "model-fields.md").read_text(encoding="utf-8")
    sections = _reference_sections(text)
    models = _models(PoundModel)
    exported = {
        name: obj
        for name in pounding_cli.model.__all__
        if isinstance(obj := getattr(pounding_cli.model, name), type) and issubclass(obj, BaseModel)
    }
    assert set(exported) <= set(models), f"models not reachable from PoundModel: {set(exported) - set(models)}"
    for name, model in models.items():
        section = sections.get(name.lower())
        assert section is not None, f"no section for {name} in docs/reference/model-fields.md: {REGENERATE}"
        for field_name, info in model.model_fields.items():
            key = info.alias or field_name
            assert f"| `{key}` |" in section, (
                f"{name}.{key} is not in docs/reference/model-fields.md: {REGENERATE}"
            )
            assert (info.description or "").strip(), f"{name}.{key} has no description"


def test_bounds_render_the_binding_limit(generator):
    """A number given both an exclusive and an inclusive bound (pydantic: a positive type
    with ge=1) is documented by the one that binds; at a tie, the exclusive one."""
    bounds = generator._bounds
    assert bounds({"exclusiveMinimum": 0, "minimum": 1.0, "maximum": 1e12}, "mass") == "1 ≤ mass ≤ 1e+12"
    assert bounds({"exclusiveMinimum": 2, "minimum": 1}, "x") == "> 2"
    assert bounds({"exclusiveMinimum": 1, "minimum": 1}, "x") == "> 1"
    assert bounds({"maximum": 5, "exclusiveMaximum": 3}, "x") == "< 3"
    assert bounds({"minimum": 0, "exclusiveMaximum": 0.5}, "ν") == "0 ≤ ν < 0.5"


@pytest.mark.parametrize(
    "model, field, low, rendered",
    [("Floor", "mass", 1.0, "1 ≤ mass ≤ 1e+12"), ("Floor", "mass_per_area", 0.01, "0.01 ≤ mass_per_area ≤ 1e+09"),
     ("Floor", "rotational_inertia", 1e-3, "0.001 ≤ rotational_inertia ≤ 1e+18"),
     ("Isolation", "mass", 1.0, "1 ≤ mass ≤ 1e+12")],
)  # fmt: skip
def test_documented_lower_bound_is_the_enforced_one(generator, model, field, low, rendered):
    """The reference row states the bound the model enforces: `low` passes, just below fails."""
    from pydantic import TypeAdapter, ValidationError

    from pounding_cli.model import Floor
    from pounding_cli.model.inelastic import Isolation

    cls = {"Floor": Floor, "Isolation": Isolation}[model]
    adapter = TypeAdapter(cls.model_fields[field].annotation)
    assert adapter.validate_python(low) == low
    with pytest.raises(ValidationError):
        adapter.validate_python(low * (1 - 1e-9))
    text = (DOCS / "reference" / "model-fields.md").read_text(encoding="utf-8")
    assert f"| `{field}` | number | not set | {rendered} |" in text


# --- (d), (e) TOML blocks of the user guide ---------------------------------------------------


def _toml_blocks():
    return _blocks(GUIDE.read_text(encoding="utf-8"), "toml")


def test_every_toml_block_parses():
    blocks = _toml_blocks()
    assert blocks, "docs/user-guide.md has no TOML blocks"
    for line, _, body in blocks:
        try:
            tomllib.loads(body)
        except tomllib.TOMLDecodeError as exc:
            pytest.fail(f"docs/user-guide.md line {line}: TOML block does not parse: {exc}")


def test_complete_models_validate():
    complete = [(line, body) for line, marker, body in _toml_blocks() if "complete-model" in marker]
    assert complete, "docs/user-guide.md has no block marked <!-- complete-model -->"
    for line, body in complete:
        source = DOCS / "x.toml"
        loaded = validate_model(tomllib.loads(body), source=source)
        for name in ("L", "T"):
            component = getattr(loaded.model.excitation.record, name)
            if component is not None:
                path = loaded.resolve(component.file)
                assert path.is_file(), f"docs/user-guide.md line {line}: record {component.file} not found from docs/"
        info = pounding_cli.describe(loaded)  # assembles it and reads the record
        assert info["analysis"]["steps"] > 0, f"docs/user-guide.md line {line}"


def test_quoted_blocks_are_verbatim():
    quoted = [(line, marker, body) for line, marker, body in _toml_blocks() if "from:" in marker]
    assert quoted, "docs/user-guide.md quotes nothing from the example"
    for line, marker, body in quoted:
        source = REPO / marker.removeprefix("<!--").removesuffix("-->").strip().removeprefix("from:").strip()
        assert body in source.read_text(encoding="utf-8"), (
            f"docs/user-guide.md line {line}: the block is no longer a verbatim part of {source.relative_to(REPO)}"
        )


# --- the Python snippets ----------------------------------------------------------------------


def test_python_snippets_run(tmp_path, monkeypatch):
    snippets = [(line, body) for line, marker, body in _blocks(GUIDE.read_text(encoding="utf-8"), "python")
                if "runnable" in marker]  # fmt: skip
    assert snippets, "docs/user-guide.md has no block marked <!-- runnable -->"
    shutil.copytree(REPO / "inputs", tmp_path / "inputs")
    monkeypatch.chdir(tmp_path)
    result = pounding_cli.run_model("inputs/paper_wide_gap.toml", output="paper_wide_gap.h5")
    assert result.complete
    for line, body in snippets:
        try:
            exec(compile(body, f"docs/user-guide.md:{line}", "exec"), {"__name__": "__snippet__"})
        except Exception as exc:  # noqa: BLE001 - report which snippet failed
            pytest.fail(f"docs/user-guide.md line {line}: snippet failed: {type(exc).__name__}: {exc}")
    assert os.path.exists("left_right.h5")


# --- the error messages quoted in the user guide ----------------------------------------------


def error_examples(text: str) -> list[tuple[int, str, str, str]]:
    """(line, old, new, quoted output) of every text block marked <!-- error-example: old => new -->."""
    out = []
    for line, marker, body in _blocks(text, "text"):
        match = re.fullmatch(r"<!-- error-example: (.+?) => (.+?) -->", marker)
        if match:
            out.append((line, match.group(1), match.group(2), body))
    return out


def error_output(folder: Path, old: str, new: str) -> tuple[int, str]:
    """Exit code and stderr of `pound validate model.toml` run in `folder`, where model.toml is
    the folder's paper_wide_gap.toml with the first `old` replaced by `new`."""
    example = (folder / "paper_wide_gap.toml").read_text(encoding="utf-8")
    assert old in example, f"{old!r} is not in inputs/paper_wide_gap.toml"
    (folder / "model.toml").write_text(example.replace(old, new, 1), encoding="utf-8")
    with contextlib.chdir(folder):
        result = CliRunner().invoke(app, ["validate", "model.toml"], env={"COLUMNS": "100"})
    return result.exit_code, result.stderr


def test_quoted_error_messages_are_real(tmp_path):
    examples = error_examples(GUIDE.read_text(encoding="utf-8"))
    assert len(examples) >= 2, "docs/user-guide.md shows fewer than two error examples"
    folder = tmp_path / "inputs"
    shutil.copytree(REPO / "inputs", folder)
    for line, old, new, body in examples:
        code, stderr = error_output(folder, old, new)
        assert code == 2, f"docs/user-guide.md line {line}: exit code {code}, expected 2"
        printed = ["$ pound validate model.toml", *stderr.replace(str(folder), ERROR_DIR).strip().splitlines()]
        assert printed == body.strip().splitlines(), f"docs/user-guide.md line {line}: the quoted message changed"
