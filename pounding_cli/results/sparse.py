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


def create_sparse(group: h5py.Group, name: str, data: np.ndarray) -> h5py.Dataset:
    """`data` (nt, n, ...) as a chunked, compressed dataset of which only the columns with
    values are written (module docstring)."""
    data = np.asarray(data, dtype=np.float64)
    nt = max(data.shape[0], 1)
    chunks = (min(nt, CHUNK_SAMPLES), 1, *data.shape[2:]) if data.size else None
    ds = group.create_dataset(name, shape=data.shape, dtype=np.float64, chunks=chunks, fillvalue=0.0,
                              compression="gzip" if chunks else None, compression_opts=1 if chunks else None,
                              shuffle=bool(chunks), track_times=False)  # fmt: skip
    columns = written_columns(data)
    for k in columns:
        ds[:, int(k)] = data[:, int(k)]
    ds.attrs["stored_columns"] = columns
    ds.attrs["storage"] = "sparse: only stored_columns are written; every other column reads as 0"
    return ds
