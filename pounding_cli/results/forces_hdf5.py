"""The forces of a building in the HDF5 file: /buildings/<name>/forces (histories) and the
peaks beside the others in /buildings/<name>/peaks (docs/user-guide.md, "HDF5 layout")."""

from __future__ import annotations

from collections.abc import Callable

import h5py
import numpy as np

from ..assembly.force_gauges import STOREY_COMPONENTS, STOREY_UNITS
from .hdf5 import _dataset, _labels
from .sparse import read_sparse
from .result import ForceResult

STOREY_DESCRIPTION = ("the resultant of the forces the storey's columns (or bearings) carry, positive along their "
                      "deflection (top minus bottom): V_x, V_y along building x, y and T about the mass centre of "
                      "the floor above (at rest); V_X, V_Y along global X, Y and T_O about the global origin")  # fmt: skip
COLUMN_DESCRIPTION = "per column line and storey; NaN where a line has no column in a storey"
MOMENT_DESCRIPTION = ("end moment of a column fixed at both ends, |M| = |V|·h/2: [x] from the shear along local x "
                      "(bending about local y), [y] from the shear along local y; ") + COLUMN_DESCRIPTION  # fmt: skip
FLOOR_FORCE = ("F_X", "F_Y", "M_Z")


def write_forces(g: h5py.Group, peaks: h5py.Group, f: ForceResult, time: h5py.Dataset, floor: h5py.Dataset,
                 storey: h5py.Dataset, column: h5py.Dataset) -> None:  # fmt: skip
    """The histories into g (/buildings/<name>/forces), the peaks into peaks."""
    component = _labels(g, "storey_force", list(STOREY_COMPONENTS), "storey shear components: " + STOREY_DESCRIPTION)
    axis = _labels(g, "column_axis", ["x", "y"], "the column's local axes (section widths b_x, b_y)")
    units = ", ".join(STOREY_UNITS).replace("·", "*")
    sampling = "output interval; peaks (in ../peaks) use every step and the exact motion between steps"
    _dataset(g, "storey_shear", f.storey_shear, units, (time, storey, component), description=STOREY_DESCRIPTION,
             sampling=sampling)  # fmt: skip
    _dataset(g, "base_shear", f.base_shear, units, (time, component), sampling=sampling,
             description="the shear of the storey on the building's ground (storey 1)")  # fmt: skip
    _dataset(g, "floor_contact", f.floor_contact, "N, N, N*m", (time, floor, _labels(g, "floor_force", list(FLOOR_FORCE))),
             axes="global", point="mass centre", description="the contact forces on each floor", sampling=sampling,
             sparse=True)  # fmt: skip
    if f.column_shear is not None:
        _dataset(g, "column_shear", f.column_shear, "N", (time, column, storey, axis), axes="column local x, y",
                 description=COLUMN_DESCRIPTION, sampling=sampling)  # fmt: skip
        _dataset(g, "column_moment", f.column_moment, "N*m", (time, column, storey, axis), description=MOMENT_DESCRIPTION,
                 sampling=sampling)  # fmt: skip
    _dataset(peaks, "storey_shear", f.peak_storey_shear, units, (storey, component),
             description="peak |.| of each component; " + STOREY_DESCRIPTION)  # fmt: skip
    _dataset(peaks, "base_shear", f.peak_base_shear, units, (component,), description="peak |.| of each component")
    _dataset(peaks, "column_shear", f.peak_column_shear, "N", (column, storey, axis), axes="column local x, y",
             description="peak |V|; " + COLUMN_DESCRIPTION)  # fmt: skip
    _dataset(peaks, "column_moment", f.peak_column_moment, "N*m", (column, storey, axis),
             description="peak " + MOMENT_DESCRIPTION)  # fmt: skip


def read_forces(g: h5py.Group, arrays: Callable[[h5py.Dataset], np.ndarray]) -> ForceResult | None:
    """A building's forces from its group (None in files written before they existed); its
    histories through `arrays` (hdf5.read_hdf5's FileArrays: mapped from the file), the contact
    forces on its floors as their stored columns (sparse.read_sparse: floors that were struck)."""
    if "forces" not in g:
        return None
    forces, peaks = g["forces"], g["peaks"]
    return ForceResult(
        storey_shear=arrays(forces["storey_shear"]),
        base_shear=arrays(forces["base_shear"]),
        floor_contact=read_sparse(forces["floor_contact"]),
        peak_storey_shear=peaks["storey_shear"][()],
        peak_base_shear=peaks["base_shear"][()],
        peak_column_shear=peaks["column_shear"][()],
        peak_column_moment=peaks["column_moment"][()],
        column_shear=arrays(forces["column_shear"]) if "column_shear" in forces else None,
        column_moment=arrays(forces["column_moment"]) if "column_moment" in forces else None,
    )
