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

from conftest import INPUTS, load_doc
from pounding_cli.model.load import read_document

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
    same model to 1e-5 of each history's size (they were to 1e-9, the same code path bit for bit
    on the machine that wrote it, until each contact step applied the force's average over its
    hat, contact.cell_correction: a change of order (ω·Δt)²/24 ≈ 1e-6 of the impact's values)."""
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
        assert np.allclose(a, b, rtol=0, atol=1e-5 * np.abs(b).max()), name
    for name, bld in now.buildings.items():
        assert np.allclose(old.buildings[name].displacement, bld.displacement, rtol=0,
                           atol=1e-5 * np.abs(bld.displacement).max())  # fmt: skip
    report = subprocess.run([sys.executable, "-m", "pounding_cli", "report", str(OLD), "--json"], capture_output=True,
                            text=True)  # fmt: skip
    assert report.returncode == 0, report.stderr
    assert json.loads(report.stdout)["impacts"]["count"] == 1
    export = subprocess.run([sys.executable, "-m", "pounding_cli", "export", str(OLD), "--csv", str(tmp_path / "csv"),
                             "--what", "contact"], capture_output=True, text=True)  # fmt: skip
    assert export.returncode == 0, export.stderr


def _with_copies(result, copies: int):
    """`result` without its contact, its buildings repeated `copies` times under new names."""
    from dataclasses import replace

    buildings = {f"{name}{k}": b for k in range(copies) for name, b in result.buildings.items()}
    return replace(result, buildings=buildings, contact=None)


def test_each_building_hangs_on_its_own_time_scale_so_files_grow_linearly(tmp_path):
    """Every building's histories are attached to its own time scale, a virtual dataset of
    /time (hdf5.building_time), not to /time: each attachment to one scale rewrites its whole
    REFERENCE_LIST, so a file of N buildings took time and space ~N² (10,000 buildings: 13 of
    22 GB) and HDF5's earliest format could not hold the list past ~700 buildings. Here 400
    buildings (200 copies of the example's two) take the same bytes per building as 50, to
    1 % (the file's fixed part, /time, /ground and the energies, is shared out), /time lists
    none of the buildings' datasets, and each building's time reads as /time."""
    from pounding_cli.results import hdf5

    doc = read_document(INPUTS / "paper_pounding.toml")
    doc["analysis"]["duration"] = 0.5
    result = pound.run_model(load_doc(doc))
    sizes = {}
    for copies in (25, 200):
        path = hdf5.write_hdf5(_with_copies(result, copies), tmp_path / f"{copies}.h5")
        sizes[copies] = path.stat().st_size / (2 * copies)
    assert abs(sizes[200] / sizes[25] - 1) < 0.01, sizes
    with h5py.File(tmp_path / "200.h5") as f:
        listed = {f[ref].name for ref, _ in f["time"].attrs["REFERENCE_LIST"]}
        assert "/energy" in listed and not any(name.startswith("/buildings") for name in listed), listed
        building = f["buildings/right199"]
        assert building["time"].is_virtual
        assert_array_equal(building["time"][()], f["time"][()])
        assert building["displacement"].dims[0][0] == building["time"]
    again = pound.read_hdf5(tmp_path / "200.h5")
    assert_array_equal(again.buildings["left199"].displacement, result.buildings["left"].displacement)
