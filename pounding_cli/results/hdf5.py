"""Writing and reading the HDF5 result file (the layout is a contract:
docs/user-guide.md, "HDF5 layout").

Files are written beside their final name and renamed into place only when complete
(:mod:`pounding_cli.atomic`), so a file with the final name is never half-written.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from ..atomic import atomic_path, hdf5_writer
from ..interrupts import checkpoint, results_written
from .result import (
    CONTACT_HISTORIES,
    ENERGY_NAMES,
    EVENT_DTYPE,
    MEMBER_DTYPE,
    PAIR_DTYPE,
    BuildingResult,
    ContactResult,
    RunResult,
    YieldingResult,
)
from .column_demand import DEMAND_DTYPE, DEMAND_UNITS
from .file_arrays import ALIGNMENT, MAP_BYTES, FileArrays
from .sparse import create_sparse, read_sparse

EVENT_UNITS = "-, -, -, s, s, N, N*s, m2, m, m, m, -, -, m, s, -, N, -, -, -, -, s, s, -"
PAIR_UNITS = "-, -, -, -, m, N/m2, N/m, -, -"


def h5_dtype(dtype: np.dtype) -> np.dtype:
    """The dtype of a table with its Python-string (object) fields as HDF5 strings."""
    return np.dtype([(name, h5py.string_dtype() if dtype[name] == object else dtype[name]) for name in dtype.names])


COLUMN_DTYPE = np.dtype(
    [
        ("name", h5py.string_dtype()),
        ("x", np.float64),
        ("y", np.float64),
        ("X", np.float64),
        ("Y", np.float64),
        ("section", np.float64, (2,)),
        ("angle", np.float64),
    ]
)

FLOOR_DTYPE = np.dtype(
    [
        ("level", np.int64),
        ("elevation", np.float64),
        ("mass", np.float64),
        ("rotational_inertia", np.float64),
        ("X", np.float64),
        ("Y", np.float64),
    ]
)


def _dataset(group: h5py.Group, name: str, data: np.ndarray, units: str, dims: tuple[h5py.Dataset, ...] = (),
             sparse: bool = False, **attrs: Any) -> h5py.Dataset:  # fmt: skip
    """A dataset with its units, attributes and dimension scales; `sparse`: only its columns
    that are not all zeros are written, chunked and compressed (sparse.py)."""
    ds = create_sparse(group, name, data) if sparse else group.create_dataset(name, data=data, track_times=False)
    ds.attrs["units"] = units
    for key, value in attrs.items():
        ds.attrs[key] = value
    _dims(ds, *dims, group=group)
    return ds


# --- dimension scales: what makes the file a netCDF-4 file that xarray opens with named
# dimensions (xarray.open_dataset(path, engine="h5netcdf", group=...) or open_datatree) ---


def _scale(group: h5py.Group, name: str, values: Any, units: str = "-", description: str = "") -> h5py.Dataset:
    """A dimension scale `name` in `group` holding the labels of that dimension (netCDF: a
    coordinate variable): numbers, or strings for names."""
    values = np.asarray(values)
    data = values.astype(h5py.string_dtype()) if values.dtype.kind in "OUS" else values
    ds = group.create_dataset(name, data=data, dtype=h5py.string_dtype() if values.dtype.kind in "OUS" else None,
                              track_times=False)  # fmt: skip
    ds.attrs["units"] = units
    if description:
        ds.attrs["description"] = description
    ds.make_scale(name)
    return ds


def _labels(group: h5py.Group, name: str, labels: list[str], description: str = "") -> h5py.Dataset:
    return _scale(group, name, np.array(labels, dtype=object), "-", description)


def _dims(ds: h5py.Dataset, *scales: h5py.Dataset, group: h5py.Group | None = None) -> None:
    """Attach `scales` to the axes of `ds` (in `group`) in order. A scale kept in another group
    is also linked into ds's group under its name (an HDF5 hard link, not a copy), so that
    opening that group alone gives it as a coordinate."""
    group = ds.parent if group is None else group
    for axis, scale in enumerate(scales):
        ds.dims[axis].attach_scale(scale)
        name = scale.name.rsplit("/", 1)[-1]
        if name not in group:
            group[name] = scale


def write_hdf5(result: RunResult, path: str | Path) -> Path:
    """Write a run's results to `path` atomically; returns the path. A file that cannot be
    written is an InputError naming `path` and the system's reason (pounding_cli.atomic)."""
    path = Path(path)
    with atomic_path(path, committed=results_written) as tmp:
        with hdf5_writer(tmp, **FILE_OPTIONS) as f:
            _write(f, result)
    result.output = path
    return path


FILE_OPTIONS: dict[str, Any] = {"track_order": True, "alignment_threshold": MAP_BYTES, "alignment_interval": ALIGNMENT}
"""h5py.File's options for a result file, of any number of buildings (building_time)."""


def _write(f: h5py.File, r: RunResult) -> None:
    time, axis = _write_time_and_ground(f, r)
    buildings = f.create_group("buildings", track_order=True)
    for name, b in r.buildings.items():
        checkpoint()  # a SIGTERM meanwhile abandons the file here (atomic_path removes it)
        _write_building(buildings.create_group(name), b, time)
    _pause_for_tests()
    checkpoint()
    _write_all_but_buildings(f, r, time, axis)


def _write_time_and_ground(f: h5py.File, r: RunResult) -> tuple[h5py.Dataset, h5py.Dataset]:
    """/time and /ground; returns the scales of time and of the global axes X, Y."""
    time = _scale(f, "time", r.time, "s", "times of the stored samples")
    ground = f.create_group("ground")
    axis = _labels(ground, "axis", ["X", "Y"], "global axes")
    _dataset(ground, "acceleration", r.ground_acceleration, "m/s2", (time, axis), columns="X, Y", axes="global")
    return time, axis


def _write_all_but_buildings(f: h5py.File, r: RunResult, time: h5py.Dataset, axis: h5py.Dataset) -> None:
    """The file's attributes, /impacts, /energy and /diagnostics."""
    from .. import __version__

    f.attrs["pound_version"] = __version__
    f.attrs["input_sha256"] = r.input_sha256
    f.attrs["model"] = r.model_json
    f.attrs["units"] = "SI"
    f.attrs["status"] = r.status
    _write_contact(f.create_group("impacts"), r.contact, time, axis)
    term = _labels(f, "energy_term", list(ENERGY_NAMES), "the columns of /energy")
    _dataset(f, "energy", r.energy, "J", (time, term), columns=", ".join(ENERGY_NAMES))
    diag = f.create_group("diagnostics")
    for key, value in r.diagnostics.items():
        diag.attrs[key] = value
    _write_warnings(diag, r.warnings)


WARNING_DTYPE = np.dtype([("file", h5py.string_dtype()), ("field", h5py.string_dtype()), ("message", h5py.string_dtype())])


def _write_warnings(g: h5py.Group, warnings: list[dict[str, str]]) -> None:
    """/diagnostics/warnings: the run's plausibility warnings, one row each (none: 0 rows)."""
    rows = np.array([(w["file"], w["field"], w["message"]) for w in warnings], dtype=WARNING_DTYPE)
    ds = g.create_dataset("warnings", data=rows, track_times=False)
    _dims(ds, _scale(g, "warning", np.arange(rows.size)))
    ds.attrs["units"] = "-, -, -"
    ds.attrs["description"] = ("plausibility warnings (pounding_cli.plausibility): the file, the model field "
                               "and what is odd about its value; the run went ahead")  # fmt: skip


def _pause_for_tests() -> None:
    """For tests/test_interrupts.py only: with POUND_TEST_PAUSE_WRITING="<marker>:<seconds>",
    touch the marker once the file is half-written, then wait, so that a test can kill the
    process while the file is being written, at a known moment. Without it, nothing."""
    spec = os.environ.get("POUND_TEST_PAUSE_WRITING")
    if spec:
        marker, _, seconds = spec.rpartition(":")
        Path(marker).touch()
        until = time.monotonic() + float(seconds)
        while time.monotonic() < until:  # a signal meanwhile is acted on within 50 ms
            time.sleep(0.05)
            checkpoint()


def _write_contact(g: h5py.Group, c: ContactResult, time: h5py.Dataset, axis: h5py.Dataset) -> None:
    pair = _scale(g, "pair", np.arange(c.pairs.size), description="row of /impacts/pairs")
    events = g.create_dataset("events", data=c.events.astype(h5_dtype(EVENT_DTYPE)), track_times=False)
    _dims(events, _scale(g, "event", np.arange(c.events.size), description="row of /impacts/events"))
    events.attrs["units"] = EVENT_UNITS
    events.attrs["description"] = (
        "one row per contact episode; level, floor_b: floors (1-based) of body A's and body B's "
        "buildings, floor_b 0 for an obstacle; at the step of the peak normal force (t_peak): x, y the "
        "action point (global), tangential_force_at_peak the tangential force on body B along t = z x n "
        "(signed), normal_x, normal_y the unit normal n from A into B (global); t_end NaN when the contact "
        "lasted to the end; storey_b, xi: the storey of body B's building that body A's slab struck between "
        "two floors (floor_b is the floor above it) and where along its height, (z - z_below)/h (0 and NaN "
        "for slab-slab and slab-obstacle contacts); t_start, t_end where the outlines met and parted, "
        "located inside the contact step; t_slip where the contact first slipped (t_start if from the touch), "
        "t_stick where its last slip ended (NaN if it never slipped or slipped to the end), slips the number "
        "of slip phases, the switches located inside their steps"
    )
    if c.column_demand.size:  # slab–storey impacts: what they put into the struck columns
        demand = g.create_dataset("column_demand", data=c.column_demand.astype(h5_dtype(DEMAND_DTYPE)),
                                  track_times=False)  # fmt: skip
        _dims(demand, _scale(g, "demand", np.arange(c.column_demand.size), description="row of /impacts/column_demand"))
        demand.attrs["units"] = DEMAND_UNITS
        demand.attrs["description"] = (
            "one row per slab-storey impact and struck column, at the impact's peak normal force: the "
            "column's share of it, the impact's own end shears (local axes; the shear Q, force of the part "
            "above a section on the part below) and moments by the fixed-fixed point-load formulas, the "
            "column's whole end shears (with its storey's drift K*delta), its shear_capacity and the "
            "demand/capacity ratio (NaN without a capacity); where the struck columns have local modes "
            "(a density), at the step where their whole end shear peaked from the impact's start to the "
            "next's, with the modes' restoring forces and the columns' inertia in the impact's part, and "
            "impact_moment_at_load NaN"
        )
    pairs = g.create_dataset("pairs", data=c.pairs.astype(h5_dtype(PAIR_DTYPE)), track_times=False)
    pairs.attrs["units"] = PAIR_UNITS
    pairs.attrs["description"] = ("contact candidates: the columns of the contact histories; k_normal, k_tangential "
                                  "as the law uses them (a struck storey's: in series with its columns' local "
                                  "flexibility); storey_b, xi as in events")  # fmt: skip
    _dims(pairs, pair)
    common: dict[str, Any] = dict(dims=(time, pair), sampling="output interval; peaks and the impact log use every step",
                                  sparse=True)  # fmt: skip
    _dataset(g, "normal_force", c.normal_force, "N", **common)
    _dataset(g, "tangential_force", c.tangential_force, "N", direction="t = z x n, on body B", **common)
    _dataset(g, "area", c.area, "m2", **common)
    _dataset(g, "depth", c.depth, "m", **common)
    _dataset(g, "action_point", c.action_point, "m", axes="global", **{**common, "dims": (time, pair, axis)})


def building_time(g: h5py.Group, time: h5py.Dataset) -> h5py.Dataset:
    """The time scale of building group g, to which its histories are attached: a virtual
    dataset of /time (`time`), holding no data of its own (HDF5 1.10's virtual datasets; any
    h5py, netCDF-4 and xarray read it as /time's values). Attaching every building's histories
    to /time itself would add each to /time's REFERENCE_LIST attribute, which HDF5 rewrites
    whole at every attachment: quadratic in the buildings, in time and in file space (10,000
    buildings: 13 of the file's 22 GB, and the earliest file format cannot hold the list past
    some 700 buildings at all). Each building's scale lists its own few."""
    layout = h5py.VirtualLayout(shape=time.shape, dtype=time.dtype)
    layout[:] = h5py.VirtualSource(".", time.name, shape=time.shape)  # ".": this file, whatever its name
    ds = g.create_virtual_dataset("time", layout)
    ds.attrs["units"] = "s"
    ds.attrs["description"] = "times of the stored samples: /time (a virtual dataset of it)"
    ds.make_scale("time")
    return ds


def _write_building(g: h5py.Group, b: BuildingResult, time: h5py.Dataset) -> None:
    """Building b into group g; `time`: /time, of which its histories get a view (building_time)."""
    time = building_time(g, time)
    n = b.elevation.size
    floor = _scale(g, "floor", np.arange(1, n + 1), description="floor level, 1 = lowest")
    storey = _scale(g, "storey", np.arange(1, n + 1), description="storey s is below floor s")
    column = _labels(g, "column", list(b.column_names), "column line names, rows of columns")
    component = _labels(g, "component", ["u_x", "u_y", "theta_z"], "translations x, y and the twist about z")
    common = dict(dims=(time, floor, component), components="u_x, u_y, theta_z", axes="global", point="mass centre")
    _dataset(g, "displacement", b.displacement, "m, m, rad", reference="relative to the ground", **common)
    _dataset(g, "velocity", b.velocity, "m/s, m/s, rad/s", reference="relative to the ground", **common)
    _dataset(g, "acceleration", b.acceleration, "m/s2, m/s2, rad/s2", reference="absolute", **common)
    cols = np.empty(len(b.column_names), dtype=COLUMN_DTYPE)
    cols["name"] = b.column_names
    cols["x"], cols["y"] = b.column_local.T
    cols["X"], cols["Y"] = b.column_plan.T
    cols["section"] = b.column_section
    cols["angle"] = b.column_angle
    ds = g.create_dataset("columns", data=cols, track_times=False)
    ds.attrs["units"] = "-, m, m, m, m, m, deg"
    ds.attrs["description"] = "x, y: building coordinates; X, Y: global; section [b_x, b_y]"
    _dims(ds, column)
    floors = np.empty(b.elevation.size, dtype=FLOOR_DTYPE)
    floors["level"] = np.arange(1, b.elevation.size + 1)
    floors["elevation"] = b.elevation
    floors["mass"], floors["rotational_inertia"] = b.floor_mass.T
    floors["X"], floors["Y"] = b.mass_centre.T
    ds = g.create_dataset("floors", data=floors, track_times=False)
    ds.attrs["units"] = "-, m, kg, kg*m2, m, m"
    ds.attrs["description"] = "X, Y: the floor's mass centre at rest, global coordinates"
    _dims(ds, floor)
    peaks = g.create_group("peaks")
    _dataset(
        peaks, "interstorey_deflection", b.interstorey_deflection, "m, m, rad", (column, storey, component),
        axes="building", description="peak |Δu_x|, |Δu_y|, |Δθ| per column and storey; NaN where absent",
    )  # fmt: skip
    _dataset(peaks, "displacement", b.peak_displacement, "m, m, rad", (floor, component), axes="global",
             reference="relative to the ground")  # fmt: skip
    _dataset(peaks, "acceleration", b.peak_acceleration, "m/s2, m/s2, rad/s2", (floor, component), axes="global",
             reference="absolute")  # fmt: skip
    modes = g.create_group("modes")
    mode = _scale(modes, "mode", np.arange(1, b.periods.size + 1), description="mode number, longest period first")
    direction = _labels(modes, "direction", ["x", "y", "theta_z"], "building axes x, y and the twist about z")
    _dataset(modes, "period", b.periods, "s", (mode,))
    _dataset(modes, "participating_mass_ratio", b.participation, "-", (mode, direction), columns="x, y, theta_z",
             axes="building")  # fmt: skip
    modes.attrs["rayleigh_a0"], modes.attrs["rayleigh_a1"] = b.rayleigh
    modes.attrs["rayleigh_units"] = "a0: 1/s, a1: s"
    if b.isolated:  # C = Tᵀ(a0·M_s + a1·K_s)T + C_b: on the superstructure's deformation (docs/theory.md §12)
        modes.attrs["rayleigh_of"] = "superstructure on a fixed base, acting on its deformation"
    g.attrs["isolated"] = b.isolated
    g.attrs["base_elevation"] = b.base_elevation  # m: the building's ground; floors.elevation is absolute
    if b.yielding is not None:
        yielding = g.create_group("yielding")
        _write_yielding(yielding, b.yielding, time)
        for name in ("ductility", "residual_deflection", "member", "local_axis"):  # hard links: one dataset, two names
            peaks[name] = yielding[name]
    if b.forces is not None:
        from .forces_hdf5 import write_forces  # it builds on this module's helpers

        write_forces(g.create_group("forces"), peaks, b.forces, time, floor, storey, column)


def _write_yielding(g: h5py.Group, y: YieldingResult, time: h5py.Dataset) -> None:
    member = _scale(g, "member", np.arange(y.members.size), description="row of yielding/members")
    local = _labels(g, "local_axis", ["x", "y"], "the member's local axes")
    ds = g.create_dataset("members", data=y.members.astype(h5_dtype(MEMBER_DTYPE)), track_times=False)
    _dims(ds, member)
    ds.attrs["units"] = "-, -, -, m, m, deg, N/m, N, -, -"
    ds.attrs["description"] = (
        "yielding members: kind column or isolator; storey 1-based (an isolated building's storey 1 is "
        "the isolation storey); X, Y global plan position; angle of the local x axis from global X; "
        "stiffness, yield_force, post_yield_ratio along local x, y; elliptical: coupled yield surface"
    )
    common = dict(dims=(time, member, local), axes="member local x, y", sampling="output interval; peaks use every step")
    _dataset(g, "deflection", y.deflection, "m", description="interstorey deflection, top minus bottom", **common)
    _dataset(g, "force", y.force, "N", description="member shear force", **common)
    peaks = ["|dx|", "|dy|", "|d|", "|fx|", "|fy|", "|f|"]
    _dataset(g, "peak", y.peak, "m, m, m, N, N, N", (member, _labels(g, "quantity", peaks, "the columns of peak")),
             columns=", ".join(peaks), axes="member local x, y")  # fmt: skip
    rows = "the yielding members, as in yielding/members (also reachable as peaks/<this name>)"
    _dataset(g, "ductility", y.ductility, "-", (member, local), columns="x, y", rows=rows,
             description="peak |deflection| / yield deflection")  # fmt: skip
    _dataset(g, "residual_deflection", y.residual_deflection, "m", (member, local), axes="member local x, y", rows=rows,
             description="deflection at rest once the motion has died away elastically from the final state")  # fmt: skip


def read_hdf5(path: str | Path) -> RunResult:
    """Read a result file written by :func:`write_hdf5`. The buildings' histories are mapped
    from the file, not read (file_arrays: the operating system reads what is used), and the
    contact histories are read as their stored columns (sparse.SparseColumns, np.asarray
    gives the whole array), so that a district's file reads in a fraction of its size."""
    path = Path(path)
    arrays = FileArrays(path)
    with h5py.File(path, "r") as f:
        buildings = {name: _read_building(g, arrays) for name, g in f["buildings"].items()}
        return RunResult(
            time=f["time"][()],
            ground_acceleration=f["ground/acceleration"][()],
            energy=f["energy"][()],
            buildings=buildings,
            status=str(f.attrs["status"]),
            model_json=str(f.attrs["model"]),
            input_sha256=str(f.attrs["input_sha256"]),
            diagnostics={k: _plain(v) for k, v in f["diagnostics"].attrs.items()},
            output=path,
            contact=_read_contact(f["impacts"]),
            warnings=_read_warnings(f["diagnostics"]),
        )


def _read_warnings(g: h5py.Group) -> list[dict[str, str]]:
    """The plausibility warnings of /diagnostics/warnings (none in files written before it)."""
    if "warnings" not in g:
        return []
    return [{k: _plain(row[k]) for k in WARNING_DTYPE.names} for row in g["warnings"][()]]


def _read_contact(g: h5py.Group) -> ContactResult:
    def table(name: str, dtype: np.dtype) -> np.ndarray:
        """The table as `dtype`; a column the file lacks (written before it existed) is NaN if
        a float, 0 if an integer."""
        raw = g[name][()]
        out = np.zeros(raw.shape, dtype)
        for field in dtype.names:
            if field not in raw.dtype.names:
                out[field] = np.nan if dtype[field] == np.float64 else 0
                continue
            column = raw[field]
            out[field] = [v.decode() for v in column] if dtype[field] == object else column
        return out

    return ContactResult(
        pairs=table("pairs", PAIR_DTYPE),
        **{name: read_sparse(g[name]) for name in CONTACT_HISTORIES},
        events=table("events", EVENT_DTYPE),
        column_demand=table("column_demand", DEMAND_DTYPE) if "column_demand" in g else None,
    )


def _read_building(g: h5py.Group, arrays: FileArrays) -> BuildingResult:
    from .forces_hdf5 import read_forces  # it builds on this module's helpers

    cols = g["columns"][()]
    floors = g["floors"][()]
    return BuildingResult(
        name=g.name.rsplit("/", 1)[-1],
        displacement=arrays(g["displacement"]),
        velocity=arrays(g["velocity"]),
        acceleration=arrays(g["acceleration"]),
        column_names=[n.decode() if isinstance(n, bytes) else str(n) for n in cols["name"]],
        column_local=np.column_stack([cols["x"], cols["y"]]),
        column_plan=np.column_stack([cols["X"], cols["Y"]]),
        column_section=cols["section"],
        column_angle=cols["angle"],
        interstorey_deflection=g["peaks/interstorey_deflection"][()],
        peak_displacement=g["peaks/displacement"][()],
        peak_acceleration=g["peaks/acceleration"][()],
        elevation=floors["elevation"],
        floor_mass=np.column_stack([floors["mass"], floors["rotational_inertia"]]),
        mass_centre=np.column_stack([floors["X"], floors["Y"]]),
        periods=g["modes/period"][()],
        participation=g["modes/participating_mass_ratio"][()],
        rayleigh=(float(g["modes"].attrs["rayleigh_a0"]), float(g["modes"].attrs["rayleigh_a1"])),
        yielding=_read_yielding(g["yielding"], arrays) if "yielding" in g else None,
        isolated=bool(g.attrs.get("isolated", False)),
        base_elevation=float(g.attrs.get("base_elevation", 0.0)),
        forces=read_forces(g, arrays),
    )


def _read_yielding(g: h5py.Group, arrays: FileArrays) -> YieldingResult:
    raw = g["members"][()]
    rows = np.zeros(raw.shape, MEMBER_DTYPE)
    for field in MEMBER_DTYPE.names:
        rows[field] = [v.decode() for v in raw[field]] if MEMBER_DTYPE[field] == object else raw[field]
    return YieldingResult(
        members=rows,
        deflection=arrays(g["deflection"]),
        force=arrays(g["force"]),
        peak=g["peak"][()],
        residual_deflection=g["residual_deflection"][()],
    )


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, bytes):
        return value.decode()
    return value


def model_of(path: str | Path) -> dict[str, Any]:
    """The resolved model stored in a result file, as a dict."""
    with h5py.File(path, "r") as f:
        return json.loads(f.attrs["model"])
