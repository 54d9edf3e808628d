"""Histories that are mostly zeros, stored in proportion to what happened (issue 30).

A contact history (nt, n_pairs[, 2]) holds a column per candidate pair, and nearly all of a
city block's candidates never touch: their columns are zeros. Such a dataset is stored
chunked one column (one pair, one floor) per chunk along time, gzip-compressed (level 1,
with the shuffle filter: HDF5's own filters, which any h5py, netCDF-4 or HDF5 tool reads),
with fill value 0, and only the columns with a value other than 0 are written: HDF5 stores
no chunk that was never written and reads it back as the fill value. The dataset keeps its
name, shape and values, so readers of the dense layout read it unchanged, and files written
before read as they always did. The attribute `stored_columns` lists the columns written.
"""

from __future__ import annotations

from dataclasses import dataclass

import h5py
import numpy as np

CHUNK_SAMPLES = 65_536
"""Samples per chunk along time: a chunk of one column is at most 512 KiB (1 MiB for a pair
of coordinates)."""


def written_columns(data: np.ndarray) -> np.ndarray:
    """The columns (along axis 1) that hold anything but zeros (NaN counts as something)."""
    if data.ndim < 2 or data.shape[1] == 0:
        return np.zeros(0, dtype=np.int64)
    flat = data.reshape(data.shape[0], data.shape[1], -1)
    return np.flatnonzero(np.any(flat != 0, axis=(0, 2)))


@dataclass
class SparseColumns:
    """A history (nt, n, ...) held as its columns that are not all zeros: what a run in
    independent groups keeps of each group's contact histories until the file is written
    (city/grouped.py), and what read_hdf5 reads of a file's sparse histories: a few columns of
    thousands. Readers that take either this or the dense array go through `held`;
    np.asarray gives the dense array."""

    shape: tuple[int, ...]  # of the whole history
    columns: np.ndarray  # (k,) the columns held, ascending
    values: np.ndarray  # (nt, k, ...) their values

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def __len__(self) -> int:
        return self.shape[0]

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        dense = np.zeros(self.shape, dtype=np.float64)
        dense[:, self.columns] = self.values
        return dense if dtype is None else dense.astype(dtype)

    def __getitem__(self, key):
        """Indexed as the dense array: [:, p] (a column) and [k] (a sample) without making it,
        anything else from the dense array."""
        key = key if isinstance(key, tuple) else (key,)
        if not key:
            return np.asarray(self)
        whole = isinstance(key[0], slice) and key[0] == slice(None)
        if len(key) >= 2 and whole and isinstance(key[1], (int, np.integer)):
            return self.column(int(key[1]))[(slice(None), *key[2:])]
        if isinstance(key[0], (int, np.integer)):
            return self.row(int(key[0]))[key[1:]]
        return np.asarray(self)[key]

    def column(self, p: int) -> np.ndarray:
        """Column p's history (nt, ...): zeros where it is not held."""
        n = self.shape[1]
        if not -n <= p < n:
            raise IndexError(f"column {p} of a history of {n}")
        p %= n
        i = int(np.searchsorted(self.columns, p))
        if i < self.columns.size and self.columns[i] == p:
            return self.values[:, i]
        return np.zeros((self.shape[0], *self.shape[2:]))

    def row(self, k: int) -> np.ndarray:
        """Sample k of every column (n, ...)."""
        out = np.zeros(self.shape[1:])
        out[self.columns] = self.values[k]  # an IndexError for k out of range, as the dense array
        return out

    @classmethod
    def of(cls, data: np.ndarray) -> "SparseColumns":
        data = np.asarray(data, dtype=np.float64)
        columns = written_columns(data)
        return cls(data.shape, columns, data[:, columns])

    @classmethod
    def side_by_side(cls, parts: list["SparseColumns"]) -> "SparseColumns":
        """The histories of `parts` concatenated along axis 1 (their columns renumbered)."""
        offsets = np.cumsum([0] + [p.shape[1] for p in parts])
        shape = (parts[0].shape[0], int(offsets[-1]), *parts[0].shape[2:])
        return cls(shape, np.concatenate([p.columns + o for p, o in zip(parts, offsets)]).astype(np.int64),
                   np.concatenate([p.values for p in parts], axis=1))  # fmt: skip


def held(data: np.ndarray | SparseColumns) -> SparseColumns:
    """A history as its columns that are not all zeros, however it is held."""
    return data if isinstance(data, SparseColumns) else SparseColumns.of(data)


def read_sparse(ds: h5py.Dataset) -> np.ndarray | SparseColumns:
    """A history as written: its stored columns alone where create_sparse wrote it (the rest
    are zeros and are not read), the whole array where it is dense (files before issue 30)."""
    if "stored_columns" not in ds.attrs:
        return ds[()]
    columns = np.asarray(ds.attrs["stored_columns"], dtype=np.int64).reshape(-1)
    values = np.empty((ds.shape[0], columns.size, *ds.shape[2:]))
    for i, k in enumerate(columns):  # one column is one chunk along time: read them one by one
        values[:, i] = ds[:, int(k)]
    return SparseColumns(tuple(ds.shape), columns, values)


def create_sparse(group: h5py.Group, name: str, data: np.ndarray | SparseColumns) -> h5py.Dataset:
    """`data` (nt, n, ...) as a chunked, compressed dataset of which only the columns with
    values are written (module docstring)."""
    stored = held(data)
    nt = max(stored.shape[0], 1)
    chunks = (min(nt, CHUNK_SAMPLES), 1, *stored.shape[2:]) if stored.size else None
    ds = group.create_dataset(name, shape=stored.shape, dtype=np.float64, chunks=chunks, fillvalue=0.0,
                              compression="gzip" if chunks else None, compression_opts=1 if chunks else None,
                              shuffle=bool(chunks), track_times=False)  # fmt: skip
    for i, k in enumerate(stored.columns):
        ds[:, int(k)] = stored.values[:, i]
    ds.attrs["stored_columns"] = stored.columns
    ds.attrs["storage"] = "sparse: only stored_columns are written; every other column reads as 0"
    return ds
