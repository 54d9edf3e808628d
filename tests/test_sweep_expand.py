"""Sweeps before they run: path addressing, expansion into cases (grid, zip, named cases,
studies, set), each case's model document, and the checked plan (hashes, resolved values)."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path

import pytest

from pounding_cli.api import input_sha256, prepare
from pounding_cli.errors import InputError
from pounding_cli.model import read_document, validate_model, validate_sweep
from pounding_cli.model.sweep import parse_path
from pounding_cli.sweep import plan_sweep
from pounding_cli.sweep.document import CaseProblem, case_document
from pounding_cli.sweep.expand import expand
from pounding_cli.sweep.paths import PathError, assign, select

from conftest import INPUTS

BASE = INPUTS / "paper_pounding.toml"
SMALL = INPUTS / "pounding_angle_gap.sweep.toml"


def doc() -> dict:
    return copy.deepcopy(read_document(BASE))


def sweep_of(data: dict, where: Path = INPUTS / "x.sweep.toml"):
    return validate_sweep({"base": "paper_pounding.toml", **data}, where)


# --- paths ---------------------------------------------------------------------------------


def test_assign_by_building_name_and_wildcard():
    d = doc()
    written = assign(d, parse_path("buildings.left.floors[*].eccentricity"), [0.0, 0.4])
    assert written == [("buildings", 0, "floors", 0, "eccentricity")]
    assert d["buildings"][0]["floors"][0]["eccentricity"] == [0.0, 0.4]
    assert "eccentricity" not in d["buildings"][1]["floors"][0]


def test_assign_index_negative_index_and_every_building():
    d = doc()
    assert assign(d, parse_path("buildings.right.origin[0]"), 8.1) == [("buildings", 1, "origin", 0)]
    assert d["buildings"][1]["origin"] == [8.1, 0.0]
    assert assign(d, parse_path("buildings[-1].name"), "east") == [("buildings", 1, "name")]
    value = [0.02, 0.02]
    written = assign(d, parse_path("buildings[*].damping.ratios"), value)
    assert written == [("buildings", 0, "damping", "ratios"), ("buildings", 1, "damping", "ratios")]
    value.append(9)  # every place got its own copy
    assert d["buildings"][0]["damping"]["ratios"] == [0.02, 0.02]


def test_assign_wildcard_over_a_table():
    d = doc()
    written = assign(d, parse_path("materials[*].poisson_ratio"), 0.25)
    assert written == [("materials", "concrete", "poisson_ratio")]


def test_assign_creates_optional_fields_and_missing_tables():
    d = doc()
    del d["contact"]
    assert assign(d, parse_path("contact.enabled"), False) == [("contact", "enabled")]
    assert d["contact"] == {"enabled": False}
    validate_model(d, BASE)  # a valid model: the table was created where the model expects it


@pytest.mark.parametrize(
    "path, message",
    [
        ("buildings.centre.name", "buildings has no item named 'centre'; names: left, right"),
        ("buildings.left.floors[2].height", "buildings[0].floors has 1 items (indices 0 to 0), so [2] selects nothing"),
        ("buildings.left.floors.first", "buildings[0].floors is a list of unnamed items: select them with [i] (0 to 0) or [*]"),
        ("excitation.angle.x", "excitation.angle is a value (0.0), so it has no entry 'x'"),
        ("excitation[0]", "excitation is a table, not a list: select its entries by key"),
        ("obstacles[*].name", "obstacles is an empty list, so [*] selects nothing"),
    ],
)
def test_path_errors(path, message):
    d = doc()
    d.setdefault("obstacles", [])
    with pytest.raises(PathError, match=re.escape(message)):
        assign(d, parse_path(path), 1.0)


def test_select_reads_every_place():
    d = doc()
    assert select(d, parse_path("buildings[*].name")) == [(("buildings", 0, "name"), "left"), (("buildings", 1, "name"), "right")]
    with pytest.raises(PathError, match="has no entry 'duration'"):
        select({"analysis": {}}, parse_path("analysis.duration"))


# --- expansion ----------------------------------------------------------------------------------


def test_grid_varies_the_first_parameter_slowest():
    s = sweep_of({"parameters": {"excitation.angle": [0, 90], "excitation.scale": [1.0, 2.0, 3.0]}}).sweep
    cases = expand(s)
    assert [c.name for c in cases][:4] == [
        "excitation.angle=0, excitation.scale=1.0", "excitation.angle=0, excitation.scale=2.0",
        "excitation.angle=0, excitation.scale=3.0", "excitation.angle=90, excitation.scale=1.0",
    ]  # fmt: skip
    assert len(cases) == 6 and cases[5].parameters == {"excitation.angle": 90, "excitation.scale": 3.0}


def test_zip_takes_values_together():
    s = sweep_of({"mode": "zip", "parameters": {"excitation.angle": [0, 90], "excitation.scale": [1.0, 2.0]}}).sweep
    assert [c.parameters for c in expand(s)] == [
        {"excitation.angle": 0, "excitation.scale": 1.0}, {"excitation.angle": 90, "excitation.scale": 2.0},
    ]  # fmt: skip


def test_named_cases_times_parameters_within_a_study_and_studies_in_order():
    s = sweep_of({
        "set": {"analysis.duration": 5.0},
        "studies": {
            "ecc": {"set": {"excitation.components": ["L"]}, "cases": {"centred": {}, "e": {"buildings.left.floors[*].eccentricity": [0, 0.4]}},
                    "parameters": {"contact.enabled": [True, False]}},
            "angle": {"parameters": {"excitation.angle": {"start": 0, "stop": 90, "step": 45}}},
        },
    }).sweep  # fmt: skip
    cases = expand(s)
    assert [c.label for c in cases] == [
        "ecc/centred @ contact.enabled=true", "ecc/centred @ contact.enabled=false",
        "ecc/e @ contact.enabled=true", "ecc/e @ contact.enabled=false",
        "angle/excitation.angle=0", "angle/excitation.angle=45", "angle/excitation.angle=90",
    ]  # fmt: skip
    layers = [(a.layer, a.path) for a in cases[2].assignments]
    assert layers == [("set", "analysis.duration"), ("set", "excitation.components"),
                      ("case", "buildings.left.floors[*].eccentricity"), ("parameter", "contact.enabled")]  # fmt: skip
    assert cases[2].parameters == {"buildings.left.floors[*].eccentricity": [0, 0.4], "contact.enabled": True}


def test_later_layers_win_and_study_set_overrides_sweep_set():
    s = sweep_of({"set": {"excitation.scale": 2.0, "analysis.duration": 5.0},
                  "studies": {"a": {"set": {"excitation.scale": 3.0}, "cases": {"one": {"analysis.duration": 6.0}}}}}).sweep  # fmt: skip
    (case,) = expand(s)
    d = case_document(read_document(BASE), case, Path("x.sweep.toml")).document
    assert d["excitation"]["scale"] == 3.0 and d["analysis"]["duration"] == 6.0


def test_a_case_and_a_parameter_setting_one_field_is_an_error():
    s = sweep_of({"cases": {"c": {"excitation": {"angle": 10.0, "record": "x.record.toml"}}},
                  "parameters": {"excitation.angle": [0, 90]}}).sweep  # fmt: skip
    with pytest.raises(CaseProblem, match=r"cases\[\"c\"\]\[\"excitation\"\]: case 'c @ excitation.angle=0': sets excitation"):
        case_document(read_document(BASE), expand(s)[0], Path("x.sweep.toml"))


# --- the plan -------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small_plan():
    return plan_sweep(SMALL)  # the workers' checks run in this process


def test_plan_of_the_shipped_sweep(small_plan):
    assert len(small_plan.cases) == 8 and len(small_plan.runs()) == 8
    assert small_plan.parameter_paths == ["excitation.angle", "buildings.right.origin[0]"]
    assert small_plan.cases[3].values == {"excitation.angle": 30.0, "buildings.right.origin[0]": 8.05}
    assert all(len(c.hash) == 12 and c.input_sha256.startswith(c.hash) for c in small_plan.cases)
    assert small_plan.buildings == {"left": 4, "right": 3}
    names = [c.name for c in small_plan.columns()]
    assert names[:7] == ["study", "case", "hash", "status", "file", "excitation.angle", "buildings.right.origin[0]"]
    assert "peak_isd_theta_rad[right]" in names and "peak_isd_x_m[left/C9/4]" in names
    assert "peak_isd_x_m[left/C9/5]" not in names and names[-2:] == ["solver_time_s", "wall_time_s"]


def test_a_case_hash_is_the_input_sha256_of_its_model(small_plan):
    """The case's hash is what `pound run` of the same model stores: the case's model, run
    alone, names the same inputs."""
    case = small_plan.cases[5]
    model = copy.deepcopy(read_document(BASE))
    model["excitation"]["angle"] = 60
    model["buildings"][1]["origin"] = [8.05, 0.0]
    scene = prepare(validate_model(model, BASE))
    assert input_sha256(scene.loaded, scene.ground) == case.input_sha256


def test_identical_cases_share_a_hash_and_values_resolve_from_the_model(tmp_path):
    s = sweep_of({"cases": {"plain": {}, "same angle": {"excitation.angle": 0.0}, "tilted": {"excitation.angle": 15}},
                  "set": {"analysis.duration": 2.0}})  # fmt: skip
    plan = plan_sweep(s)
    hashes = [c.hash for c in plan.cases]
    assert hashes[0] == hashes[1] != hashes[2] and len(plan.runs()) == 2
    assert [c.values["excitation.angle"] for c in plan.cases] == [0.0, 0.0, 15.0], "unset paths show the base value"


def test_paths_in_values_are_relative_to_the_base_model(tmp_path):
    """A record path given as a value is read from the base model's folder."""
    s = sweep_of({"parameters": {"excitation.record": ["ridgecrest2019_ccc.record.toml"]}, "set": {"analysis.duration": 2.0}},
                 where=tmp_path / "elsewhere.sweep.toml")  # base is then tmp_path/paper_pounding.toml: absent
    with pytest.raises(InputError, match="base: .*paper_pounding.toml: no such file"):
        plan_sweep(s)
    s = validate_sweep({"base": str(BASE), "parameters": {"excitation.record": ["ridgecrest2019_ccc.record.toml"]},
                        "set": {"analysis.duration": 2.0}}, tmp_path / "elsewhere.sweep.toml")  # fmt: skip
    (case,) = plan_sweep(s).cases
    assert case.values == {"excitation.record": "ridgecrest2019_ccc.record.toml"}


def test_problems_name_the_case_the_field_and_the_origin():
    s = sweep_of({"parameters": {"excitation.angle": [0, "north", "south"]}})
    with pytest.raises(InputError) as info:
        plan_sweep(s)
    lines = str(info.value).splitlines()
    assert len(lines) == 2, "one line per distinct problem"
    assert lines[0].startswith(f"{INPUTS / 'x.sweep.toml'}: case 'excitation.angle=north': ")
    assert "paper_pounding.toml: excitation.angle: expected a number; got 'north'" in lines[0]
    assert lines[0].endswith('[from parameters["excitation.angle"] = north]')


def test_repeated_problems_are_counted_not_repeated():
    s = sweep_of({"parameters": {"buildings.middle.name": ["a"], "excitation.angle": [0, 1, 2, 3]}})
    with pytest.raises(InputError) as info:
        plan_sweep(s)
    (line,) = str(info.value).splitlines()
    assert "buildings has no item named 'middle'" in line and line.endswith("(and 3 more cases)")


def test_manifest_is_plain_json(small_plan):
    manifest = small_plan.manifest()
    assert json.loads(json.dumps(manifest)) == manifest
    assert [c["hash"] for c in manifest["cases"]] == [c.hash for c in small_plan.cases]
    assert manifest["sweep"]["base"] == "paper_pounding.toml" and manifest["studies"] == {"": ""}
