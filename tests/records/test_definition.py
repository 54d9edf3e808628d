"""Record definitions: the pydantic model, inline or in a file of their own, and their errors."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli.assembly.ground import ground_motion
from pounding_cli.errors import InputError
from pounding_cli.model import read_document, validate_model
from pounding_cli.model.record import load_record, validate_record

from conftest import EXAMPLE, INPUTS, SHARED, example_doc

KOBE = SHARED / "records" / "kobe1995_kjma"
needs_kobe = pytest.mark.skipif(not KOBE.is_dir(), reason=f"PEER Kobe records absent: {KOBE}")
RAW = INPUTS / "records" / "CICCC.RAW"  # shipped (USGS, CC0)
needs_raw = pytest.mark.skipif(not RAW.is_file(), reason=f"raw COSMOS record absent: {RAW}")

COMPONENT = {"file": "records/ridgecrest2019_ccc.mseed", "trace": "HNE", "units": "m/s2"}


def record_error(data: dict) -> str:
    with pytest.raises(InputError) as info:
        validate_record(data, "r.record.toml")
    return str(info.value)


# --- the model -------------------------------------------------------------------------------


def test_metadata_and_a_toml_date():
    record = load_record(INPUTS / "ridgecrest2019_ccc.record.toml")
    assert record.date == "2019-07-06"  # a TOML date, kept as text
    assert record.magnitude == 7.1 and record.network.startswith("CI")
    assert (record.L.azimuth, record.T.azimuth) == (90.0, 360.0)
    assert record.processing.steps() == []


@pytest.mark.parametrize(("data", "expected"), [
    ({"L": {**COMPONENT, "azimuth": 361.0}}, "L.azimuth: Input should be less than or equal to 360"),
    ({"L": {**COMPONENT, "azimuth": "N"}}, "L.azimuth: expected a number"),
    ({"L": {**COMPONENT, "azimuth": 90.0}, "T": COMPONENT}, "L.azimuth is given but T.azimuth is not"),
    ({"name": "nothing"}, "a record needs at least one component"),
    ({"L": COMPONENT, "procesing": {}}, "unknown key 'procesing'; did you mean 'processing'?"),
    ({"L": COMPONENT, "processing": {"scale": 2.0, "target_pga": 0.3}}, "either scale or target_pga"),
    ({"L": COMPONENT, "processing": {"target_pga": 0.0}}, "processing.target_pga: Input should be greater than 0"),
    ({"L": COMPONENT, "processing": {"taper": 0.6}}, "processing.taper: Input should be less than or equal to 0.5"),
    ({"L": COMPONENT, "processing": {"demean": 1}}, "processing.demean: Input should be a valid boolean"),
    ({"L": COMPONENT, "processing": {"filter": {"corners": 4}}}, "give freqmin (Hz), freqmax (Hz) or both"),
    ({"L": COMPONENT, "processing": {"filter": {"freqmin": 5.0, "freqmax": 1.0}}}, "freqmin = 5 Hz must be below freqmax = 1 Hz"),
    ({"L": COMPONENT, "processing": {"window": {"start": 5.0, "end": 5.0}}}, "end = 5 s must be after start = 5 s"),
    ({"L": {**COMPONENT, "dt": 0.0}}, "L.dt: Input should be greater than or equal to 0.000001"),
    ({"L": {**COMPONENT, "dt": -0.01}}, "L.dt: Input should be greater than or equal to 0.000001"),
    ({"L": {**COMPONENT, "dt": 1e-320}}, "L.dt: Input should be greater than or equal to 0.000001"),
    ({"L": {**COMPONENT, "dt": 2.0}}, "L.dt: Input should be less than or equal to 1"),
    ({"L": {**COMPONENT, "units": "mm/s2"}}, "L.units: Input should be 'g', 'm/s2', 'cm/s2' or 'gal'"),
    ({"magnitude": 12.0, "L": COMPONENT}, "magnitude: Input should be less than or equal to 10"),
])  # fmt: skip
def test_invalid_definitions_name_the_file_and_field(data, expected):
    message = record_error(data)
    assert message.startswith("r.record.toml: "), message
    assert expected in message, message


def test_a_model_names_a_record_file_by_a_toml_or_json_path():
    doc = example_doc()
    doc["excitation"]["record"] = "kobe.txt"
    with pytest.raises(InputError, match=r"excitation.record: expected a record table or the path of a record definition file"):
        validate_model(doc, EXAMPLE)


# --- inline or in a file: the same ground motion ----------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 30.0])
def test_record_file_gives_the_inline_ground_motion_bit_for_bit(angle):
    """paper_wide_gap.toml's inline record (L = HNE, T = HNN, no azimuths) and
    ridgecrest2019_ccc.record.toml (the same traces at azimuths 90/360)."""
    inline = example_doc()
    inline["excitation"]["angle"] = angle
    by_file = example_doc()
    by_file["excitation"]["angle"] = angle
    by_file["excitation"]["record"] = "ridgecrest2019_ccc.record.toml"
    a = ground_motion(validate_model(inline, EXAMPLE))
    b = ground_motion(validate_model(by_file, EXAMPLE))
    assert np.array_equal(a.acceleration, b.acceleration)
    assert b.record_file == (INPUTS / "ridgecrest2019_ccc.record.toml").resolve()
    assert set(b.file_sha256) == {"L", "T", "definition"}


def test_json_record_definition(tmp_path):
    """A .json definition, in another folder: component files are relative to it, the
    definition relative to the model."""
    folder = tmp_path / "recs"
    folder.mkdir()
    shutil.copy(INPUTS / "records" / "ridgecrest2019_ccc.mseed", folder / "rc.mseed")
    definition = {"name": "rc", "L": {"file": "rc.mseed", "trace": "HNE", "units": "m/s2"},
                  "T": {"file": "rc.mseed", "trace": "HNN", "units": "m/s2"}}
    (folder / "rc.record.json").write_text(json.dumps(definition))
    doc = example_doc()
    doc["excitation"]["record"] = "recs/rc.record.json"
    ground = ground_motion(validate_model(doc, tmp_path / "model.toml"))
    reference = ground_motion(validate_model(example_doc(), EXAMPLE))
    assert np.array_equal(ground.acceleration, reference.acceleration)
    info = pound.describe(validate_model(doc, tmp_path / "model.toml"))
    assert info["excitation"]["record"] == "rc"
    assert info["excitation"]["record_file"].endswith("rc.record.json")
    assert info["excitation"]["directions_X_Y"] == {"L": [1.0, 0.0], "T": [0.0, 1.0]}


def test_errors_inside_a_record_file_name_it_after_the_model(tmp_path):
    (tmp_path / "bad.record.toml").write_text('[L]\nfile = "x.mseed"\nunits = "mm/s2"\n')
    doc = example_doc()
    doc["excitation"]["record"] = "bad.record.toml"
    with pytest.raises(InputError) as info:
        ground_motion(validate_model(doc, tmp_path / "model.toml"))
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'model.toml'}: excitation.record: {tmp_path / 'bad.record.toml'}: L.units: ")


def test_a_component_the_record_file_lacks(tmp_path):
    (tmp_path / "only_l.record.toml").write_text(
        f'[L]\nfile = "{(INPUTS / "records" / "ridgecrest2019_ccc.mseed").as_posix()}"\ntrace = "HNE"\nunits = "m/s2"\n'
    )
    doc = example_doc()
    doc["excitation"]["record"] = "only_l.record.toml"
    with pytest.raises(InputError, match=r"excitation.components: components lists T but .*only_l.record.toml.T is not given"):
        ground_motion(validate_model(doc, tmp_path / "model.toml"))
    doc["excitation"]["components"] = ["L"]
    assert ground_motion(validate_model(doc, tmp_path / "model.toml")).acceleration[:, 1].any() == False  # noqa: E712


def test_missing_record_file(tmp_path):
    doc = example_doc()
    doc["excitation"]["record"] = "nowhere.record.toml"
    with pytest.raises(InputError, match=r"excitation.record: .*nowhere.record.toml: no such file"):
        ground_motion(validate_model(doc, tmp_path / "model.toml"))


# --- the shipped definitions -------------------------------------------------------------------


@needs_kobe
def test_kobe_definition_reads_the_peer_files():
    """PGA 0.834 g (000) and 0.630 g (090), 7500 points at 0.02 s (the shared README's figures)."""
    from pounding_cli.records.inspect import open_record

    data = open_record(INPUTS / "kobe_jma.record.toml")
    (l, t) = data.components
    assert (l.name, t.name) == ("L", "T")
    for c, pga in ((l, 0.8342), (t, 0.6297)):
        assert c.dt == 0.02 and c.acceleration.size == 7500
        assert np.abs(c.acceleration).max() / 9.80665 == pytest.approx(pga, abs=5e-5)
        assert c.azimuth is None  # on purpose: the paper's layout is L/T, not the map (see the file)


@needs_kobe
def test_paper_kobe_model_applies_000_along_x_and_090_along_y():
    doc = read_document(INPUTS / "paper_kobe.toml")
    assert doc["excitation"]["record"] == "kobe_jma.record.toml"
    ground = ground_motion(validate_model(doc, INPUTS / "paper_kobe.toml"))
    assert np.abs(ground.acceleration[:, 0]).max() / 9.80665 == pytest.approx(0.8342, abs=5e-5)
    assert np.abs(ground.acceleration[:, 1]).max() / 9.80665 == pytest.approx(0.6297, abs=5e-5)


@needs_raw
def test_raw_ridgecrest_definition_equals_the_shipped_record_inside_its_end_tapers():
    """pound's processing of CICCC.RAW (demean, detrend, 5 % taper, 0.1-25 Hz band-pass, window
    26-60 s) is the conversion script's, sample for sample, away from the script's 1 s end tapers."""
    from pounding_cli.records.inspect import open_record

    raw = open_record(INPUTS / "ridgecrest2019_ccc_raw.record.toml").components
    shipped = open_record(INPUTS / "ridgecrest2019_ccc.record.toml").components
    for a, b in zip(raw, shipped, strict=True):
        assert a.acceleration.size == b.acceleration.size == 3401
        assert np.array_equal(a.acceleration[100:-100], b.acceleration[100:-100]), a.name
