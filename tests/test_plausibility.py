"""Plausibility warnings: each fires on its case, the shipped inputs raise none, and they
reach validate, run, --json, the result file and --strict; a refusal blames the input most
likely at fault."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.api import prepare
from pounding_cli.cli import app
from pounding_cli.errors import InputError
from pounding_cli.model import read_document
from pounding_cli.plausibility import CHECKS, Notice, notices

from conftest import INPUTS, ROOT, load_doc, model_doc, square_building

runner = CliRunner()


def fields_of(doc: dict) -> dict[str, str]:
    """{field: message} of the notices of a model dict."""
    return {n.field: n.message for n in notices(prepare(load_doc(doc)))}


def short(doc: dict, duration: float = 2.0) -> dict:
    doc["analysis"] = {"duration": duration, **doc.get("analysis", {})}
    return doc


# --- each warning on its case ----------------------------------------------------------------


@pytest.mark.parametrize(
    "modulus, likely",
    [(25000.0, "MPa typed as Pa (25000 MPa = 25 GPa: write elastic_modulus = 2.5e+10)"),
     (21.0, "GPa typed as Pa (21 GPa = 21 GPa: write elastic_modulus = 2.1e+10)"),
     (2.1e7, "kN/m² (kPa) typed as Pa")],
)  # fmt: skip
def test_elastic_modulus_below_1_gpa_names_the_likely_unit(modulus: float, likely: str) -> None:
    doc = short(model_doc())
    doc["materials"]["concrete"]["elastic_modulus"] = modulus
    found = fields_of(doc)
    message = found["materials.concrete.elastic_modulus"]
    assert "is below 1 GPa" in message and likely in message, message


def test_elastic_modulus_of_25000_gives_the_long_period_warning_too() -> None:
    doc = short(model_doc(square_building(storeys=4)))
    doc["materials"]["concrete"]["elastic_modulus"] = 25000.0
    found = fields_of(doc)
    t1 = float(found["buildings[0]"].split("T1 = ")[1].split(" s")[0])
    assert t1 > 100, found["buildings[0]"]
    assert "beyond the 0.02–6 s" in found["buildings[0]"]


@pytest.mark.parametrize(
    "rho, likely",
    [(2.5, "t/m³ (g/cm³) typed as kg/m³: write density = 2500"),
     (25.0, "unit weight in kN/m³ (25 kN/m³ is 2548 kg/m³: write density = 2548)"),
     (7.85e4, "extra factor of 1000")],
)  # fmt: skip
def test_density_outside_structural_materials_names_the_likely_unit(rho: float, likely: str) -> None:
    doc = short(model_doc())
    doc["materials"]["concrete"]["density"] = rho
    message = fields_of(doc)["materials.concrete.density"]
    assert "outside 300–20,000 kg/m³" in message and likely in message, message
    doc["materials"]["concrete"]["density"] = 2400.0
    assert "materials.concrete.density" not in fields_of(doc)


def test_elastic_modulus_above_1_tpa() -> None:
    doc = short(model_doc())
    doc["materials"]["concrete"]["elastic_modulus"] = 2.1e13 / 10
    assert "above 1 TPa" in fields_of(doc)["materials.concrete.elastic_modulus"]


@pytest.mark.parametrize(
    "key, value, word, limits",
    [("mass_per_area", 50.0, "below", "100–5,000 kg/m²"), ("mass_per_area", 8000.0, "above", "100–5,000 kg/m²"),
     ("height", 0.3, "below", "2–10 m"), ("height", 30.0, "above", "2–10 m")],
)  # fmt: skip
def test_floor_mass_per_area_and_storey_height_outside_their_ranges(key: str, value: float, word: str,
                                                                    limits: str) -> None:  # fmt: skip
    doc = short(model_doc())
    doc["buildings"][0]["floors"][0][key] = value
    message = fields_of(doc)[f"buildings[0].floors[0].{key}"]
    assert f"{word} the {limits}" in message, message


def test_floor_mass_given_in_kg_is_checked_per_area() -> None:
    doc = short(model_doc())
    floor = doc["buildings"][0]["floors"][0]
    del floor["mass_per_area"]
    floor["mass"] = 64.0  # tonnes typed as kg: 1 kg/m² on 64 m²
    message = fields_of(doc)["buildings[0].floors[0].mass"]
    assert "64 kg on 64 m², 1 kg/m²" in message and "below" in message, message


def test_fundamental_period_below_0_02_s() -> None:
    doc = short(model_doc(square_building(section=(2.0, 2.0))))  # 2 m × 2 m columns on a light floor
    doc["buildings"][0]["floors"][0]["mass_per_area"] = 150.0
    message = fields_of(doc)["buildings[0]"]
    assert "is below the 0.02–6 s" in message, message


def test_pga_above_3_g_blames_the_scale() -> None:
    doc = short(model_doc())
    doc["excitation"]["scale"] = 10.0  # Ridgecrest CCC: 0.5 g → 5 g
    found = fields_of(doc)
    assert "above the 3 g" in found["excitation.scale"], found


def test_pga_above_3_g_blames_the_units_of_the_strongest_component() -> None:
    doc = short(model_doc())
    doc["excitation"]["record"]["L"]["units"] = "g"  # values in m/s² read as g
    found = fields_of(doc)
    assert "m/s² read as g" in found["excitation.record.L.units"], found


def _write_mseed(path: Path, channel: str) -> None:
    from obspy import Stream, Trace

    t = np.arange(400) * 0.01
    trace = Trace(np.sin(2 * np.pi * t).astype(np.float64),
                  header={"network": "XX", "station": "TEST", "channel": channel, "delta": 0.01})  # fmt: skip
    Stream([trace]).write(str(path), format="MSEED")


def _write_at2(path: Path, component: str) -> None:
    text = (ROOT / "tests/records/data/synthetic.AT2").read_text()
    path.write_text(text.replace("SYNTH STATION 7, 90", f"SYNTH STATION 7, {component}"))


@pytest.mark.parametrize("kind", ["seed HHZ", "at2 UP", "at2 V", "cosmos Up"])
def test_vertical_component_used_as_l_or_t(kind: str, tmp_path: Path) -> None:
    fmt, mark = kind.split()
    doc = short(model_doc(), 0.2)
    if fmt == "seed":
        _write_mseed(tmp_path / "z.mseed", mark)
        doc["excitation"]["record"]["T"] = {"file": str(tmp_path / "z.mseed"), "units": "m/s2"}
        field = "excitation.record.T.file"
    elif fmt == "at2":
        _write_at2(tmp_path / "v.AT2", mark)
        doc["excitation"]["record"]["T"] = {"file": str(tmp_path / "v.AT2"), "units": "g"}
        field = "excitation.record.T.file"
    else:
        v1 = ROOT / "tests/records/data/synthetic_2ch.V1"
        doc["excitation"]["record"]["T"] = {"file": str(v1), "trace": 1, "units": "g"}
        field = "excitation.record.T.trace"
    doc["excitation"]["record"]["L"] = dict(doc["excitation"]["record"]["T"])
    doc["excitation"]["record"]["L"].update({"file": str(ROOT / "tests/records/data/synthetic.AT2"), "units": "g"})
    doc["excitation"]["record"]["L"].pop("trace", None)
    found = fields_of(doc)
    assert "marks vertical" in found[field], found
    assert "excitation.record.L.file" not in found, found  # the horizontal AT2 (component 90) is not flagged


def test_vertical_component_of_a_record_definition_names_that_file(tmp_path: Path) -> None:
    _write_mseed(tmp_path / "z.mseed", "HNZ")
    _write_mseed(tmp_path / "e.mseed", "HNE")
    (tmp_path / "rec.record.toml").write_text(
        'L = { file = "e.mseed", units = "m/s2" }\nT = { file = "z.mseed", units = "m/s2" }\n'
    )
    doc = short(model_doc(), 2.0)
    doc["excitation"]["record"] = str(tmp_path / "rec.record.toml")
    found = [n for n in notices(prepare(load_doc(doc))) if "vertical" in n.message]
    assert [(n.file, n.field) for n in found] == [(str(tmp_path / "rec.record.toml"), "T.file")]


@pytest.mark.parametrize("factor, word", [(1000.0, "1,000 times"), (1 / 1000, "1/1,000 of")])
def test_impact_stiffness_by_hand_far_from_the_materials(factor: float, word: str) -> None:
    doc = short(load_doc_dict("paper_pounding.toml"))
    doc["contact"]["k_normal"] = 2.064e10 * factor
    doc["contact"]["k_tangential"] = 4.586e9  # the materials' own: no warning
    found = fields_of(doc)
    assert f"k_normal = {2.064e10 * factor:.4g} N/m² is {word} the materials' own" in found["contact.k_normal"], found
    assert "contact.k_tangential" not in found


def load_doc_dict(name: str) -> dict:
    return read_document(INPUTS / name)


# --- the shipped inputs, and the mechanism -------------------------------------------------


@pytest.mark.parametrize("path", sorted(p.name for p in INPUTS.glob("*.toml") if ".sweep." not in p.name
                                        and ".record." not in p.name))  # fmt: skip
def test_shipped_models_raise_no_warning(path: str) -> None:
    assert [str(n) for n in prepare(INPUTS / path).notices] == []


def test_shipped_sweeps_raise_no_warning() -> None:
    from pounding_cli.sweep.plan import plan_sweep

    for path in sorted(INPUTS.glob("*.sweep.toml")):
        assert plan_sweep(path, strict=True).warnings == [], path


def test_a_check_is_added_by_appending_one_function(monkeypatch: pytest.MonkeyPatch) -> None:
    def titled(scene):
        if not scene.loaded.model.title:
            yield Notice(str(scene.loaded.source), "title", "the model has no title")

    monkeypatch.setattr("pounding_cli.plausibility.CHECKS", [*CHECKS, titled])
    assert [n.field for n in prepare(load_doc(short(model_doc()))).notices] == ["title"]


# --- where they appear -------------------------------------------------------------------------


@pytest.fixture
def odd_model(tmp_path: Path) -> Path:
    text = (INPUTS / "paper_wide_gap.toml").read_text()
    text = text.replace("elastic_modulus = 21e9", "elastic_modulus = 21000").replace(
        'dt = "auto"', 'dt = "auto"\nduration = 1.0')
    text = text.replace('"records/', f'"{INPUTS}/records/')
    path = tmp_path / "odd.toml"
    path.write_text(text)
    return path


def test_validate_prints_them_on_stderr_and_json_carries_them(odd_model: Path) -> None:
    r = runner.invoke(app, ["validate", str(odd_model)])
    assert r.exit_code == 0, r.output
    lines = [line for line in r.stderr.splitlines() if line.startswith(f"{odd_model}: ")]
    assert lines[0].startswith(f"{odd_model}: materials.concrete.elastic_modulus: E = 21000 Pa (21 kPa) is below 1 GPa")
    assert [line.split(": ")[1] for line in lines] == ["materials.concrete.elastic_modulus", "buildings[0]", "buildings[1]"]
    assert "elastic_modulus" not in r.stdout
    r = runner.invoke(app, ["validate", str(odd_model), "--json"])
    warnings = json.loads(r.stdout)["warnings"]
    assert [sorted(w) for w in warnings] == [["field", "file", "message"]] * 3
    assert warnings[0]["field"] == "materials.concrete.elastic_modulus" and warnings[0]["file"] == str(odd_model)


def test_strict_makes_them_exit_2_naming_file_and_field(odd_model: Path, tmp_path: Path) -> None:
    r = runner.invoke(app, ["validate", str(odd_model), "--strict"])
    assert r.exit_code == 2
    assert r.stderr.startswith(f"{odd_model}: materials.concrete.elastic_modulus: E = 21000 Pa")
    assert r.stderr.rstrip().endswith("(--strict: 3 plausibility warnings made errors)")
    out = tmp_path / "out.h5"
    r = runner.invoke(app, ["run", str(odd_model), "-o", str(out), "--strict", "--no-progress"])
    assert r.exit_code == 2 and "--strict" in r.stderr
    assert not out.exists()


def test_run_prints_them_and_the_result_file_keeps_them(odd_model: Path, tmp_path: Path) -> None:
    out = tmp_path / "out.h5"
    r = runner.invoke(app, ["run", str(odd_model), "-o", str(out), "--no-progress", "--json"])
    assert r.exit_code == 0, r.output
    assert f"{odd_model}: materials.concrete.elastic_modulus: " in r.stderr
    summary = json.loads(r.stdout)
    assert [w["field"] for w in summary["warnings"]] == ["materials.concrete.elastic_modulus", "buildings[0]",
                                                          "buildings[1]"]  # fmt: skip
    with h5py.File(out, "r") as f:
        table = f["diagnostics/warnings"]
        assert table.attrs["units"] == "-, -, -"
        assert [row["field"].decode() for row in table[()]] == [w["field"] for w in summary["warnings"]]
    assert pound.read_hdf5(out).warnings == summary["warnings"]


def test_a_file_without_warnings_reads_back_none(tmp_path: Path) -> None:
    result = pound.run_model(load_doc(short(model_doc(), 0.5)), output=tmp_path / "ok.h5")
    with h5py.File(tmp_path / "ok.h5", "a") as f:
        assert f["diagnostics/warnings"].shape == (0,)
        del f["diagnostics/warnings"]  # as written before the table existed
    assert result.warnings == [] and pound.read_hdf5(tmp_path / "ok.h5").warnings == []


def test_sweep_strict_refuses_naming_the_case(tmp_path: Path) -> None:
    from pounding_cli.sweep.plan import plan_sweep

    sweep = tmp_path / "s.sweep.toml"
    sweep.write_text(f'base = "{INPUTS / "paper_wide_gap.toml"}"\n[parameters]\n"materials.concrete.elastic_modulus" = '
                     '[21e9, 21000.0]\n"analysis.duration" = [1.0]\n')  # fmt: skip
    plan = plan_sweep(sweep)
    assert any("materials.concrete.elastic_modulus: E = 21000 Pa" in line for line in plan.warnings), plan.warnings
    with pytest.raises(InputError) as caught:
        plan_sweep(sweep, strict=True)
    message = str(caught.value)
    assert message.startswith(f"{sweep}: case ") and "elastic_modulus" in message
    assert "[from parameters" in message and message.endswith("(--strict: plausibility warnings are errors)")


# --- refusals blame the input most likely at fault -------------------------------------------


def test_a_floor_of_1_kg_per_m2_is_refused_naming_the_mass_not_k_normal() -> None:
    doc = load_doc_dict("paper_pounding.toml")
    doc["buildings"][0]["floors"][0]["mass_per_area"] = 1.0
    with pytest.raises(InputError) as caught:
        prepare(load_doc(doc))
    assert caught.value.field == "buildings[0].floors[0].mass_per_area", str(caught.value)
    assert "mass_per_area = 1 kg/m² is below the 100–5,000 kg/m²" in caught.value.message


def test_a_plausible_model_beyond_the_step_limit_still_blames_the_contact(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("POUND_MAX_STEPS", "1e5")
    with pytest.raises(InputError) as caught:
        prepare(INPUTS / "paper_pounding.toml")
    assert caught.value.field == "contact.k_normal", str(caught.value)
