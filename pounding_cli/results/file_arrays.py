"""The buildings' histories of a result file, read without reading them: mapped from the file.

A district's file holds gigabytes of time histories (10,000 buildings: 29 GB) of which a report
or a script looks at a few buildings, if any. `read_hdf5` therefore maps each large history
that HDF5 stores contiguously and uncompressed (the buildings' histories; pound writes them so)
into memory instead of reading it: the array is a view of one read-only map of the file
(np.memmap, mode "r"), whose pages the operating system reads when they are first touched and
may drop again under memory pressure. The arrays are read-only (`.copy()` gives one to change):
a copy-on-write map (mode "c") would be writable, but the kernel counts a private writable map
against memory and refuses one larger than memory and swap (the 10,000-building file, 29 GB,
on a machine of 24 GB: every history was then read, 18.6 GB). A file written by pound is
replaced by a rename, never changed in place, so a map stays valid as long as the result is
held. Small datasets, chunked or compressed ones (contact histories: results/sparse.py), ones
whose data is not aligned to its item size (files of pound before the alignment below), and
any on a file system that cannot map files are read as before.

pound writes large datasets aligned to ALIGNMENT bytes (h5py's alignment_threshold and
alignment_interval, HDF5's H5Pset_alignment), so that each maps as an aligned array.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

MAP_BYTES = 1 << 16
"""Datasets of at least this many bytes are mapped: a map costs a page table entry per page
touched, reading a small dataset costs less than finding it."""

ALIGNMENT = 64
"""Bytes to which the data of datasets of at least MAP_BYTES are aligned in files pound writes
(a cache line: any item size divides it)."""


class FileArrays:
    """Reads the datasets of one file: large contiguous ones as read-only views of one map of
    it."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._map: np.memmap | None | bool = None  # False: the file cannot be mapped

    def __call__(self, ds: h5py.Dataset) -> np.ndarray:
        offset = ds.id.get_offset()  # None where chunked (so possibly compressed) or never written
        dtype = ds.dtype
        if (offset is None or ds.nbytes < MAP_BYTES or dtype.kind not in "fiu" or dtype.fields is not None
                or offset % dtype.itemsize or ds.external):  # fmt: skip
            return ds[()]
        if self._map is None:
            try:
                self._map = np.memmap(self.path, dtype=np.uint8, mode="r")
            except (OSError, ValueError):  # a file system that cannot map files: read them
                self._map = False
        if self._map is False:
            return ds[()]
        return np.ndarray(ds.shape, dtype, buffer=self._map, offset=offset)

