"""Contact histories stored in proportion to what happened (pounding_cli/results/sparse.py,
issue 30): only the columns of pairs (and floors) that touched are written, chunked and
compressed; readers see the dense values; files of the layout before still read."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
from numpy.testing import assert_array_equal

import pounding_cli as pound

from conftest import INPUTS

OLD = Path(__file__).parent / "data" / "paper_pounding_main_f3049db.h5"
"""Written by main's code at f3049db (before this layout): inputs/paper_pounding.toml with
output_interval = 0.2 s, by `pounding_cli.run_model(...)` of that commit."""


def _coarse(tmp_path: Path) -> Path:
    text = (INPUTS / "paper_pounding.toml").read_text().replace("output_interval = 0.01     # s",
                                                                 "output_interval = 0.2      # s")  # fmt: skip
    model = INPUTS / "test-coarse.toml"  # beside the shipped record
    model.write_text(text)
    return model


def test_only_columns_with_values_are_written(tmp_path):
    """Against the dense array: a column of zeros takes no chunk, a column with a value or a
    NaN is written, and the whole reads back bit for bit (NaN where it was)."""
    from pounding_cli.results.sparse import create_sparse

    rng = np.random.default_rng(30)
    data = np.zeros((1000, 50, 2))
    data[rng.integers(0, 1000, 20), rng.integers(0, 50, 20), 0] = rng.normal(size=20)
    data[5, 7, 1] = np.nan
    expect = sorted(set(np.flatnonzero(np.any(data != 0, axis=(0, 2)))))
    with h5py.File(tmp_path / "s.h5", "w") as f:
        ds = create_sparse(f, "x", data)
        assert list(ds.attrs["stored_columns"]) == expect and 7 in expect
        assert ds.id.get_num_chunks() == len(expect)
    with h5py.File(tmp_path / "s.h5") as f:
        assert f["x"][()].tobytes() == data.tobytes()


def test_a_run_stores_only_the_pairs_that_touched(tmp_path):
    """The pounding example's contact histories and floor contact forces: each dataset holds
    the columns with values, chunked and gzip-compressed, and reads back as it was computed."""
    from pounding_cli.results.sparse import written_columns

    result = pound.run_model(INPUTS / "paper_pounding.toml", output=tmp_path / "new.h5")
    assert result.contact.pairs.size == 3
    with h5py.File(tmp_path / "new.h5") as f:
        for name in ("normal_force", "tangential_force", "area", "depth", "action_point"):
            ds, data = f[f"impacts/{name}"], getattr(result.contact, name)
            assert ds.compression == "gzip" and ds.chunks[1] == 1, name
            assert_array_equal(ds.attrs["stored_columns"], written_columns(data))
            assert ds.id.get_num_chunks() == written_columns(data).size < 3, name
            assert_array_equal(ds[()], data)
    again = pound.read_hdf5(tmp_path / "new.h5")
    for name, bld in result.buildings.items():
        assert_array_equal(again.buildings[name].forces.floor_contact, bld.forces.floor_contact)


def test_a_file_written_by_the_dense_layout_still_reads(tmp_path):
    """The file of main's code reads, reports and exports; its values are today's run of the
    same model (to 1e-9 of each history's size: the same code path, bit for bit on the machine
    that wrote it)."""
    old = pound.read_hdf5(OLD)
    with h5py.File(OLD) as f:
        assert f["impacts/normal_force"].chunks is None, "the file has the dense layout"
    model = _coarse(tmp_path)
    try:
        now = pound.run_model(model)
    finally:
        model.unlink()
    for name in ("normal_force", "area", "depth"):
        a, b = getattr(old.contact, name), getattr(now.contact, name)
        assert np.allclose(a, b, rtol=0, atol=1e-9 * np.abs(b).max()), name
    for name, bld in now.buildings.items():
        assert np.allclose(old.buildings[name].displacement, bld.displacement, rtol=0,
                           atol=1e-9 * np.abs(bld.displacement).max())  # fmt: skip
    report = subprocess.run([sys.executable, "-m", "pounding_cli", "report", str(OLD), "--json"], capture_output=True,
                            text=True)  # fmt: skip
    assert report.returncode == 0, report.stderr
    assert json.loads(report.stdout)["impacts"]["count"] == 1
    export = subprocess.run([sys.executable, "-m", "pounding_cli", "export", str(OLD), "--csv", str(tmp_path / "csv"),
                             "--what", "contact"], capture_output=True, text=True)  # fmt: skip
    assert export.returncode == 0, export.stderr


def test_a_file_of_many_buildings_keeps_its_scales_attributes_dense(tmp_path, monkeypatch):
    """Each dataset attached to /time adds to its REFERENCE_LIST; HDF5's earliest format holds
    about 4,000 (a 700-building file), so above DENSE_ATTRIBUTES_BUILDINGS the file is written in
    HDF5 1.8's format. Forced here for the pounding example: it reads back the same."""
    from pounding_cli.results import hdf5

    result = pound.run_model(INPUTS / "paper_pounding.toml")
    monkeypatch.setattr(hdf5, "DENSE_ATTRIBUTES_BUILDINGS", 1)
    path = hdf5.write_hdf5(result, tmp_path / "v108.h5")
    with h5py.File(path) as f:
        assert f.id.get_create_plist().get_version()[0] >= 2, "the superblock of HDF5 1.8's format"
    again = pound.read_hdf5(path)
    for name, bld in result.buildings.items():
        assert_array_equal(again.buildings[name].displacement, bld.displacement)
    assert_array_equal(again.contact.normal_force, result.contact.normal_force)
