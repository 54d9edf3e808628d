"""read_hdf5 reads a district's file in a fraction of its size (issue 30): the buildings'
histories are mapped from the file (results/file_arrays.py), the contact histories read as
their stored columns (results/sparse.py, read_sparse). What is read must be what was written,
bit for bit; what is mapped must not be read until used, and never written back."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

import pounding_cli as pound
from pounding_cli.results.file_arrays import ALIGNMENT, MAP_BYTES, FileArrays
from pounding_cli.results.sparse import SparseColumns, written_columns

from conftest import INPUTS

HISTORIES = ("displacement", "velocity", "acceleration")
FORCE_HISTORIES = ("storey_shear", "base_shear")
CONTACT = ("normal_force", "tangential_force", "area", "depth", "action_point")
MEMMAP = np.memmap  # (a test replaces np.memmap)


def mapped(array: np.ndarray) -> bool:
    """Whether an array is a view of a file's map."""
    base = array
    while base is not None:
        if isinstance(base, MEMMAP):
            return True
        base = base.base
    return False


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    path = tmp_path_factory.mktemp("mapped") / "run.h5"
    return pound.run_model(INPUTS / "paper_pounding.toml", output=path), path


def test_the_buildings_histories_are_mapped_and_are_what_was_computed(run):
    result, path = run
    again = pound.read_hdf5(path)
    checked = 0
    for name, b in result.buildings.items():
        a = again.buildings[name]
        pairs = [(getattr(b, f), getattr(a, f)) for f in HISTORIES]
        pairs += [(getattr(b.forces, f), getattr(a.forces, f)) for f in FORCE_HISTORIES]
        for computed, read in pairs:
            assert read.nbytes >= MAP_BYTES and mapped(read)  # 2,001 samples: large enough to map
            assert read.dtype == computed.dtype and read.shape == computed.shape
            assert read.tobytes() == computed.tobytes()
            checked += 1
    assert checked == 2 * (len(HISTORIES) + len(FORCE_HISTORIES))


def test_a_mapped_history_is_read_only_and_its_copy_is_not(run):
    """Read-only, so that a script cannot take a change in memory for a change of the file (and a
    file larger than memory maps at all: file_arrays' docstring)."""
    _, path = run
    a = pound.read_hdf5(path).buildings["left"].displacement
    before = a[5].copy()
    with pytest.raises(ValueError, match="read-only"):
        a[5] = 99.0
    b = a.copy()
    b[5] = 99.0
    assert (b[5] == 99.0).all() and not mapped(b)
    assert_array_equal(pound.read_hdf5(path).buildings["left"].displacement[5], before)


def test_every_large_contiguous_dataset_pound_writes_is_aligned(run):
    _, path = run
    found = []

    def visit(name, node):
        if isinstance(node, h5py.Dataset) and node.nbytes >= MAP_BYTES and node.id.get_offset() is not None:
            found.append((name, node.id.get_offset() % ALIGNMENT))

    with h5py.File(path) as f:
        f.visititems(visit)
    assert len(found) >= 10 and all(rest == 0 for _, rest in found), found


def test_an_unaligned_or_chunked_or_small_dataset_is_read_not_mapped(tmp_path):
    """Files of pound before the alignment: their histories lie at any offset."""
    data = np.arange(20_000, dtype=np.float64)
    with h5py.File(tmp_path / "old.h5", "w") as f:  # h5py's defaults: no alignment
        f.create_dataset("pad", data=np.zeros(3, np.uint8))
        f.create_dataset("big", data=data)
        f.create_dataset("chunked", data=data, chunks=(1000,), compression="gzip")
        f.create_dataset("small", data=data[:100])
    arrays = FileArrays(tmp_path / "old.h5")
    with h5py.File(tmp_path / "old.h5") as f:
        assert f["big"].id.get_offset() % 8 != 0  # what this test is about
        for name, expect in (("big", data), ("chunked", data), ("small", data[:100])):
            read = arrays(f[name])
            assert not mapped(read) and read.tobytes() == expect.tobytes(), name


def test_a_file_that_cannot_be_mapped_is_read(run, monkeypatch):
    """Some file systems cannot map files (np.memmap raises): the histories are read instead."""
    result, path = run

    def refuse(*args, **kwargs):
        raise OSError(19, "No such device")

    monkeypatch.setattr(np, "memmap", refuse)
    again = pound.read_hdf5(path)
    for name, b in result.buildings.items():
        read = again.buildings[name].displacement
        assert not mapped(read) and read.tobytes() == b.displacement.tobytes()


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="resident memory is read from Linux's /proc")
def test_mapping_reads_nothing_until_used(tmp_path):
    """A 256 MiB history: reading it whole makes the process's resident memory grow by its
    size, mapping it and using one row by almost nothing (/proc/self/statm of a fresh process,
    before and after; the margin, 16 MiB, is far below the dataset)."""
    path = tmp_path / "big.h5"
    rows = 256 * 2**20 // (8 * 1000)
    with h5py.File(path, "w", alignment_threshold=MAP_BYTES, alignment_interval=ALIGNMENT) as f:
        ds = f.create_dataset("history", shape=(rows, 1000), dtype=np.float64)
        for start in range(0, rows, 4096):
            ds[start:start + 4096] = start
    code = """
import os, sys, h5py, numpy as np
from pounding_cli.results.file_arrays import FileArrays
def resident():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
f = h5py.File(sys.argv[1]); ds = f["history"]
before = resident()
a = FileArrays(sys.argv[1])(ds) if sys.argv[2] == "map" else ds[()]
assert a[4096, 0] == 4096.0 and a.shape == ds.shape
print(resident() - before)
"""
    grown = {how: int(subprocess.run([sys.executable, "-c", code, str(path), how], capture_output=True, text=True,
                                      check=True).stdout) / 2**20 for how in ("map", "read")}  # fmt: skip
    assert grown["read"] > 250 and grown["map"] < 16, grown  # MiB


def test_contact_histories_are_read_as_their_stored_columns(run):
    result, path = run
    again = pound.read_hdf5(path)
    for name in CONTACT:
        computed, read = getattr(result.contact, name), getattr(again.contact, name)
        assert isinstance(read, SparseColumns)
        assert_array_equal(read.columns, written_columns(computed))
        assert read.shape == computed.shape and read.ndim == computed.ndim and read.size == computed.size
        assert np.asarray(read).tobytes() == np.ascontiguousarray(computed).tobytes()
    for b in result.buildings:
        computed, read = result.buildings[b].forces.floor_contact, again.buildings[b].forces.floor_contact
        assert isinstance(read, SparseColumns) and np.asarray(read).tobytes() == computed.tobytes()


def test_a_sparse_history_indexes_as_the_dense_array():
    rng = np.random.default_rng(30)
    dense = np.zeros((50, 7, 2))
    dense[rng.integers(0, 50, 12), rng.integers(0, 7, 12)] = rng.normal(size=(12, 2))
    dense[:, 3] = 0.0  # a column that never touched
    held = SparseColumns.of(dense)
    assert 3 not in held.columns and held.values.shape[1] < 7
    for p in range(-7, 7):
        assert_array_equal(held[:, p], dense[:, p])
        assert_array_equal(held[:, p, 1], dense[:, p, 1])
        assert_array_equal(held.column(p), dense[:, p])
    for k in (0, 17, -1):
        assert_array_equal(held[k], dense[k])
        assert_array_equal(held[k, 2], dense[k, 2])
        assert_array_equal(held.row(k), dense[k])
    assert_array_equal(held[:, 1:4], dense[:, 1:4])  # anything else: from the dense array
    assert_array_equal(held[()], dense) and len(held) == len(dense)
    assert_array_equal(held[dense[:, 0, 0] > 0, 0], dense[dense[:, 0, 0] > 0, 0])
    for bad in (7, -8):
        with pytest.raises(IndexError):
            held[:, bad]
    with pytest.raises(IndexError):
        held[50]
