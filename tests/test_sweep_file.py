"""Sweep files: values of ranges and linspaces, path syntax, the schemas, the docs.

Bad sweep files and their messages are in tests/invalid/invalid_sweep_*.toml
(tests/test_invalid_inputs.py)."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import jsonschema
import pytest
from pydantic import BaseModel

from pounding_cli.model import load_sweep, validate_sweep
from pounding_cli.model.sweep import Index, Linspace, Range, Study, SummarySettings, SweepFile, parse_path, path_text
from pounding_cli.schema import sweep_schema, sweep_summary_schema
from pounding_cli.sweep.columns import CASE_COLUMNS, RESULT_COLUMNS, TIME_COLUMNS, building_columns, storey_columns

from conftest import INPUTS, ROOT

DOC = ROOT / "docs" / "sweep.md"
SWEEP_FILES = sorted(INPUTS.glob("*.sweep.toml"))


# --- values ----------------------------------------------------------------------------------


def test_range_includes_stop_on_a_step():
    angles = Range(start=0, stop=360, step=5).values()
    assert len(angles) == 73 and angles[0] == 0 and angles[-1] == 360
    assert all(isinstance(a, int) for a in angles), "a range of integers gives integers"


def test_range_rounds_decimal_steps():
    assert Range(start=0, stop=1, step=0.1).values() == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
    assert Range(start=0.05, stop=0.01, step=-0.01).values() == [0.05, 0.04, 0.03, 0.02, 0.01]
    assert Range(start=0, stop=1, step=0.3).values() == [0.0, 0.3, 0.6, 0.9], "stop off the steps is left out"


def test_linspace_includes_both_ends():
    assert Linspace(start=0, stop=0.3, num=4).values() == [0.0, 0.1, 0.2, 0.3]
    assert Linspace(start=2, stop=5, num=1).values() == [2.0]
    assert Linspace(start=1e7, stop=1e9, num=3).values() == [1e7, 5.05e8, 1e9]


def test_parameter_forms():
    s = validate_sweep({"base": "m.toml", "parameters": {"a": [1, "x", [0, 1], {"k": True}], "b": {"start": 0, "stop": 2,
                        "step": 1}, "c": {"start": 0, "stop": 1, "num": 3}}}, "s.toml").sweep  # fmt: skip
    assert s.parameters["a"] == [1, "x", [0, 1], {"k": True}]
    assert isinstance(s.parameters["b"], Range) and isinstance(s.parameters["c"], Linspace)


def test_toml_dates_become_text():
    s = validate_sweep(tomllib.loads('base = "m.toml"\nset = { "x.date" = 1995-01-17 }\ncases.a = {}'), "s.toml")
    assert s.sweep.set["x.date"] == "1995-01-17"


def test_top_level_is_one_study_named_empty():
    s = validate_sweep({"base": "m.toml", "mode": "zip", "parameters": {"a": [1, 2], "b": [3, 4]}}, "s.toml").sweep
    assert list(s.all_studies()) == [""] and s.all_studies()[""].mode == "zip"


# --- paths -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, steps",
    [
        ("excitation.angle", ("excitation", "angle")),
        ("buildings.left.floors[*].eccentricity", ("buildings", "left", "floors", Index(None), "eccentricity")),
        ("buildings.right.origin[0]", ("buildings", "right", "origin", Index(0))),
        ("buildings[-1].name", ("buildings", Index(-1), "name")),
        ('materials."C30.37".elastic_modulus', ("materials", "C30.37", "elastic_modulus")),
        ("a[0][*].b-c+d_e", ("a", Index(0), Index(None), "b-c+d_e")),
    ],
)
def test_path_syntax(text, steps):
    assert parse_path(text) == steps
    assert path_text(steps) == text


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "empty path"),
        ("excitation..angle", "expected a key at character 12"),
        ("a.b[x]", "unexpected '[' at character 4"),
        ('a."b', "unterminated quoted key at character 3"),
        ("a b", "unexpected ' ' at character 2"),
        ("[0].a", "expected a key at character 1"),
    ],
)
def test_path_syntax_errors(text, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_path(text)


# --- shipped sweep files -------------------------------------------------------------------


def test_shipped_sweep_files_are_valid():
    assert {p.name for p in SWEEP_FILES} >= {"pounding_angle_gap.sweep.toml", "paper_studies.sweep.toml"}
    for path in SWEEP_FILES:
        loaded = load_sweep(path)
        assert loaded.base.is_file(), f"{path.name}: base {loaded.sweep.base} not found"


def test_paper_studies_file_has_the_papers_three_studies():
    s = load_sweep(INPUTS / "paper_studies.sweep.toml").sweep
    assert list(s.studies) == ["6.1", "6.2", "6.3"]
    assert len(s.studies["6.1"].cases) == 5 and len(s.studies["6.2"].cases) == 3
    assert len(Range.model_validate(s.studies["6.3"].parameters["excitation.angle"].model_dump()).values()) == 73
    assert s.summary.columns == {"left": ["C9"]}


# --- schemas -------------------------------------------------------------------------------


def test_sweep_schema_accepts_the_shipped_files_and_refuses_typos():
    schema = sweep_schema()
    for path in SWEEP_FILES:
        jsonschema.validate(tomllib.loads(path.read_text(encoding="utf-8")), schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"base": "m.toml", "parmeters": {}}, schema)


def test_summary_row_schema_names_every_fixed_column():
    schema = sweep_summary_schema()
    fixed = CASE_COLUMNS + RESULT_COLUMNS + TIME_COLUMNS
    assert schema["required"] == [c.name for c in fixed]
    assert all(schema["properties"][c.name]["description"] for c in fixed)
    row = {c.name: None for c in fixed} | {"study": "", "case": "a", "hash": "0123456789ab", "status": "pending",
                                           "file": "cases/0123456789ab.h5", "excitation.angle": 30.0}  # fmt: skip
    for c in building_columns("left") + storey_columns("left", "C9", 2):
        row[c.name] = 0.01
    jsonschema.validate(row, schema)
    for bad in ({"hash": "xyz"}, {"status": "done"}, {"peak_isd_x_m[left]": -1.0}, {"peak_isd_y_m[left/C9/1]": "a"}):
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(row | bad, schema)


def test_deflection_column_names_match_the_schema_patterns():
    patterns = sweep_summary_schema()["patternProperties"]
    for column in building_columns("left") + storey_columns("tower-2", "C1.a", 3):
        assert sum(bool(re.match(p, column.name)) for p in patterns) == 1, column.name


# --- docs ----------------------------------------------------------------------------------


def _sweep_models() -> list[type[BaseModel]]:
    return [SweepFile, Study, Range, Linspace, SummarySettings]


def test_every_sweep_field_is_documented():
    """docs/sweep.md names every key of a sweep file (its field table is written by hand)."""
    text = DOC.read_text(encoding="utf-8")
    for model in _sweep_models():
        for name, info in model.model_fields.items():
            assert (info.description or "").strip(), f"{model.__name__}.{name} has no description"
            assert f"`{name}`" in text or f"{name} =" in text or f"{{ {name}" in text or f", {name}" in text, (
                f"{model.__name__}.{name} is not in docs/sweep.md"
            )


def test_every_summary_column_is_documented():
    text = DOC.read_text(encoding="utf-8")
    for column in CASE_COLUMNS + RESULT_COLUMNS + TIME_COLUMNS:
        assert f"| `{column.name}` |" in text, f"summary column {column.name} is not in docs/sweep.md"
    for pattern in ("`peak_isd_x_m[B]`", "`peak_isd_theta_rad[B/C/s]`"):
        assert pattern in text


def test_quoted_sweep_files_are_verbatim():
    text = DOC.read_text(encoding="utf-8")
    blocks = re.findall(r"<!-- from: (\S+) -->\n```toml\n(.*?)```", text, flags=re.S)
    assert blocks, "docs/sweep.md quotes no sweep file"
    for source, body in blocks:
        assert body in (ROOT / source).read_text(encoding="utf-8"), f"docs/sweep.md: block from {source} changed"


def test_toml_blocks_of_the_docs_are_valid_sweep_files():
    """Every TOML block of docs/sweep.md with a `base` key is a valid sweep file."""
    blocks = re.findall(r"```toml\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    full = [tomllib.loads(b) for b in blocks if re.search(r"^base = ", b, flags=re.M)]
    assert full
    for doc in full:
        validate_sweep(doc, DOC)


def test_schema_files_on_disk_are_current():
    for name, make in (("sweep.schema.json", sweep_schema), ("sweep-summary.schema.json", sweep_summary_schema)):
        on_disk = json.loads((ROOT / "schemas" / name).read_text(encoding="utf-8"))
        assert on_disk == make(), f"schemas/{name} is out of date: run pound schema"


def test_invalid_sweep_base_is_found_relative_to_the_sweep_file(tmp_path: Path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "x.sweep.toml").write_text('base = "../m.toml"\ncases.a = {}\n', encoding="utf-8")
    assert load_sweep(tmp_path / "sub" / "x.sweep.toml").base == tmp_path / "sub" / ".." / "m.toml"


def test_every_mistake_of_a_sweep_file_is_reported(tmp_path: Path):
    """A sweep file with a path that fits no building and a value of the wrong type reports
    both: the cases the bad path breaks are still validated for their other values."""
    from pounding_cli.errors import InputError
    from pounding_cli.sweep import plan_sweep

    base = ROOT / "tests" / "invalid" / "sweep_base" / "base.toml"
    sweep = tmp_path / "bad.sweep.toml"
    sweep.write_text(f'base = "{base.as_posix()}"\n\n[parameters]\n"excitation.angle" = [0, "north"]\n'
                     '"buildings.centre.floors[*].eccentricity" = [[0.0, 0.4]]\n', encoding="utf-8")  # fmt: skip
    with pytest.raises(InputError) as info:
        plan_sweep(sweep)
    message = str(info.value)
    assert "buildings has no item named 'centre'" in message
    assert "excitation.angle: expected a number; got 'north'" in message
    assert "[from parameters[\"excitation.angle\"] = north]" in message
