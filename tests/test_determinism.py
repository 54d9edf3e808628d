"""Determinism: the same input gives bitwise-identical results, and input_sha256 identifies
the input exactly (resolved model, record bytes, pound version).

The model is the shipped paper_pounding.toml cut to 20 s (one impact), copied with its record
into tmp_path. Two `pound run` subprocesses write two HDF5 files; every dataset must be equal
bit for bit, and every attribute too, except the diagnostics that time the run.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

import pounding_cli
from pounding_cli import api
from pounding_cli.model import read_document

from conftest import INPUTS

TIMINGS = {"wall_time_s", "compile_time_s", "us_per_step", "run_time_s"}
"""Diagnostics that measure the run, not its result."""


def write_model(folder: Path, **analysis) -> Path:
    """paper_pounding.toml as JSON in `folder` (20 s unless told), beside a copy of its record."""
    (folder / "records").mkdir(parents=True, exist_ok=True)
    shutil.copy(INPUTS / "records" / "ridgecrest2019_ccc.mseed", folder / "records")
    doc = read_document(INPUTS / "paper_pounding.toml")
    doc["analysis"].update({"duration": 20.0, **analysis})
    path = folder / "model.json"
    path.write_text(json.dumps(doc))
    return path


def pound_run(model: Path, output: Path) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("POUND_")}
    done = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(output), "--json"],
                          capture_output=True, text=True, env=env, timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr


def contents(path: Path) -> tuple[dict[str, np.ndarray], dict[str, dict]]:
    """Every dataset (by name) and the attributes of every object (timings left out)."""
    datasets: dict[str, np.ndarray] = {}
    attrs: dict[str, dict] = {}

    def visit(name: str, obj) -> None:
        if isinstance(obj, h5py.Dataset):
            datasets[name] = obj[()]
        attrs[name] = {k: referred(obj.file, v) for k, v in obj.attrs.items() if k not in TIMINGS}

    with h5py.File(path, "r") as f:
        attrs["/"] = dict(f.attrs)
        f.visititems(visit)
    return datasets, attrs


def referred(f: h5py.File, value):
    """An attribute holding object references (the dimension scales' DIMENSION_LIST and
    REFERENCE_LIST) as the text of the names of the objects they point to, which two runs
    must share; any other attribute as it is."""

    def names(v):
        if isinstance(v, h5py.Reference):
            return f[v].name
        if isinstance(v, (np.ndarray, np.void, tuple, list)):
            return tuple(names(x) for x in (v.tolist() if isinstance(v, np.void) else v))
        return v.item() if isinstance(v, np.generic) else v

    holds_references = isinstance(value, np.ndarray) and (value.dtype == object or value.dtype.names)
    return repr(names(value)) if holds_references else value


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.names:  # a table: column by column (NaN in a float column, as in xi, is NaN in both)
        return all(same_bits(a[name], b[name]) for name in a.dtype.names)
    if a.dtype.kind in "fc":  # compare the bytes: NaN == NaN, -0.0 != 0.0
        return np.ascontiguousarray(a).tobytes() == np.ascontiguousarray(b).tobytes()
    return bool(np.array_equal(a, b))


def test_two_runs_give_bitwise_identical_files(tmp_path):
    model = write_model(tmp_path)
    pound_run(model, tmp_path / "a.h5")
    pound_run(model, tmp_path / "b.h5")
    data_a, attrs_a = contents(tmp_path / "a.h5")
    data_b, attrs_b = contents(tmp_path / "b.h5")
    assert sorted(data_a) == sorted(data_b) and len(data_a) > 20
    different = [name for name in data_a if not same_bits(data_a[name], data_b[name])]
    assert not different, f"datasets differ between two runs: {different}"
    assert attrs_a["/"]["status"] == "complete"
    assert attrs_a["/"]["input_sha256"] == attrs_b["/"]["input_sha256"]
    assert attrs_a["/"]["input_sha256"] == api.input_sha256(*_loaded_and_ground(model))
    assert data_a["impacts/events"].shape[0] >= 1, "the run should include an impact"
    assert sorted(attrs_a) == sorted(attrs_b)
    for name in attrs_a:
        assert sorted(attrs_a[name]) == sorted(attrs_b[name]), name
        for key, value in attrs_a[name].items():
            assert same_bits(value, attrs_b[name][key]), (name, key, value, attrs_b[name][key])


def _loaded_and_ground(model: Path):
    scene = api.prepare(model)
    return scene.loaded, scene.ground


def sha(model: Path) -> str:
    return api.input_sha256(*_loaded_and_ground(model))


def test_input_hash_is_stable_and_follows_the_model(tmp_path):
    model = write_model(tmp_path)
    first = sha(model)
    assert sha(model) == first
    same = write_model(tmp_path / "copy")  # the same input in another folder
    assert sha(same) == first
    longer = write_model(tmp_path / "longer", duration=20.5)
    assert sha(longer) != first
    doc = json.loads(model.read_text())
    doc["excitation"]["angle"] = 1e-12  # the smallest change to the model
    (tmp_path / "turned.json").write_text(json.dumps(doc))
    assert sha(tmp_path / "turned.json") != first


def test_input_hash_follows_every_byte_of_the_record(tmp_path):
    import obspy

    model = write_model(tmp_path)
    doc = json.loads(model.read_text())
    doc["excitation"]["components"] = ["L"]  # HNE applied; HNN read but not applied
    l_only = tmp_path / "L_only.json"
    l_only.write_text(json.dumps(doc))
    first, first_l_only = sha(model), sha(l_only)
    record = tmp_path / "records" / "ridgecrest2019_ccc.mseed"
    stream = obspy.read(str(record))
    north = stream.select(channel="HNN")[0]
    north.data = north.data.copy()
    north.data[1000] = np.nextafter(north.data[1000], np.inf)  # one sample of T, one bit
    stream.write(str(record), format="MSEED", encoding="FLOAT64", reclen=4096)
    assert sha(model) != first
    assert sha(l_only) != first_l_only, "the hash must follow every file the record reads"


def test_input_hash_follows_a_record_definition_and_its_files(tmp_path):
    model = write_model(tmp_path)
    definition = tmp_path / "quake.record.toml"
    definition.write_text(
        'name = "Ridgecrest"\n[L]\nfile = "records/ridgecrest2019_ccc.mseed"\ntrace = "HNE"\nunits = "m/s2"\n'
        '[T]\nfile = "records/ridgecrest2019_ccc.mseed"\ntrace = "HNN"\nunits = "m/s2"\n'
    )
    doc = json.loads(model.read_text())
    doc["excitation"]["record"] = "quake.record.toml"
    model.write_text(json.dumps(doc))
    first = sha(model)
    definition.write_text(definition.read_text().replace('"Ridgecrest"', '"Ridgecrest 2019"'))
    assert sha(model) != first, "the hash must follow the bytes of the record definition file"


def test_input_hash_includes_the_pound_version(tmp_path, monkeypatch):
    model = write_model(tmp_path)
    first = sha(model)
    monkeypatch.setattr(api, "__version__", pounding_cli.__version__ + ".post1")
    assert sha(model) != first
