"""The result file of a run in independent groups (city/grouped.py), written group by group.

Each group's buildings go into the file as the group ends; of its result only what the merge
needs stays in memory: the peaks, the impact log, the columns of its contact histories that
are not all zeros (sparse.SparseColumns: a few of thousands), its energies and diagnostics.
So the parent process holds one group's histories at a time, not the district's (issue 30:
10,000 buildings), and the file is the one write_hdf5 would write of the merged result: the
same layout and values, the buildings in the model's order whatever order the groups end in.

The file is written under a temporary name and renamed when complete (atomic.atomic_stream);
signals are deferred only while a part is written, so Ctrl-C and SIGTERM stop the run at
once between the groups, and nothing is left behind.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Iterator

import h5py
import numpy as np

from ..atomic import atomic_stream, hdf5_writer
from ..interrupts import checkpoint, deferred, results_written
from .hdf5 import FILE_OPTIONS, _write_all_but_buildings, _write_building, _write_time_and_ground
from .result import CONTACT_HISTORIES, BuildingResult, ContactResult, RunResult
from .sparse import held


class GroupedFile:
    """An open result file taking groups' results (add) and then the merged rest (finish)."""

    def __init__(self, f: h5py.File, names: list[str]):
        self.f = f
        self.names = names
        self.scales: tuple[h5py.Dataset, h5py.Dataset] | None = None  # /time and the axes X, Y
        self.finished = False

    def add(self, result: RunResult) -> RunResult:
        """Write the buildings of one group's result (its contact histories already sparse, as
        run_group returns them); returns it without the buildings' histories
        (without_histories), which is what the merge needs."""
        with deferred():
            if self.scales is None:  # the first group: /time, /ground, and every building's group in order
                self.scales = _write_time_and_ground(self.f, result)
                buildings = self.f.create_group("buildings", track_order=True)
                for name in self.names:
                    buildings.create_group(name)
            for name, b in result.buildings.items():
                checkpoint()  # a signal meanwhile abandons the file here
                _write_building(self.f["buildings"][name], b, self.scales[0])
            checkpoint()
        return without_histories(result)

    def finish(self, merged: RunResult) -> None:
        """The file's attributes, /impacts, /energy and /diagnostics of the merged result (its
        contact histories SparseColumns or arrays)."""
        if self.scales is None:
            raise ValueError("no group's result was added")
        with deferred():
            _write_all_but_buildings(self.f, merged, *self.scales)
            checkpoint()
        self.finished = True


@contextmanager
def grouped_file(path: Path, names: list[str]) -> Iterator[GroupedFile]:
    """A GroupedFile for `path`, buildings `names` in order; renamed into place when the block
    ends after finish(), removed when it raises (then nothing is written)."""
    with atomic_stream(path, committed=results_written) as tmp, hdf5_writer(tmp, **FILE_OPTIONS) as f:
        stream = GroupedFile(f, names)
        yield stream
        if not stream.finished:
            raise RuntimeError(f"{path}: the grouped result file was left unfinished")


def without_histories(result: RunResult) -> RunResult:
    """`result` with its buildings' histories (time along axis 0) replaced by arrays of no
    samples; the time axis, ground motion, energies, peaks, impact log, contact histories and
    diagnostics are kept."""
    return replace(result, buildings={n: _building_without_histories(b) for n, b in result.buildings.items()})


def with_sparse_contact(result: RunResult) -> RunResult:
    """`result` with its contact histories as their columns that are not all zeros
    (SparseColumns): what a group's worker sends back (a hundred buildings' candidates hold
    ~190 MB of histories densely, nearly all zeros)."""
    c = result.contact
    return replace(result, contact=replace(c, **{name: held(getattr(c, name)) for name in CONTACT_HISTORIES}))


def _none(a: np.ndarray | None) -> np.ndarray | None:
    """An array of no samples shaped as `a` otherwise (a fresh one: a slice would keep `a`)."""
    return None if a is None else np.zeros((0, *a.shape[1:]), dtype=a.dtype)


def _building_without_histories(b: BuildingResult) -> BuildingResult:
    forces = b.forces
    if forces is not None:
        forces = replace(forces, storey_shear=_none(forces.storey_shear), base_shear=_none(forces.base_shear),
                         floor_contact=_none(forces.floor_contact), column_shear=_none(forces.column_shear),
                         column_moment=_none(forces.column_moment))  # fmt: skip
    yielding = b.yielding
    if yielding is not None:
        yielding = replace(yielding, deflection=_none(yielding.deflection), force=_none(yielding.force))
    return replace(b, displacement=_none(b.displacement), velocity=_none(b.velocity),
                   acceleration=_none(b.acceleration), forces=forces, yielding=yielding)  # fmt: skip


def contact_without_samples(c: ContactResult) -> ContactResult:
    """A merged ContactResult whose histories are SparseColumns, with arrays of no samples in
    their place: what the run returns once the file holds them."""
    return replace(c, **{name: np.zeros((0, *getattr(c, name).shape[1:])) for name in CONTACT_HISTORIES})
