"""`pound export`: a result file as tidy CSV files, one per quantity, for pandas and spreadsheets.

    import pounding_cli as pound
    written = pound.export_csv("out.h5", "csv/", what=["displacement", "peaks"])
    # [{"quantity": "displacement", "file": "csv/displacement.csv", "rows": …, "columns": […]}, …]

Each file is one table: a header row naming every column with its unit in brackets
(``time [s]``, ``u_x [m]``; labels have none), then one row per observation — per stored time,
building and floor for a history, per column and storey for the peak deflections, per contact
episode for the impact log. Numbers are written in full (the shortest text that reads back
to the same float64); an absent value (a column line missing from a storey, a contact that
lasted to the end) is an empty cell. UTF-8, comma separated, RFC 4180 quoting.

:data:`QUANTITIES` lists what can be exported, each a function from a
:class:`~pounding_cli.results.RunResult` to (columns, rows); another module adds a quantity by
adding an entry (and to a group of :data:`GROUPS` if it belongs to one).

All files are written beside their final names and renamed together at the end (atomic:
nothing half-written; an interrupted or failed export leaves no file of the set); existing
files are replaced only with `force`, and an output is never the result file read.
"""

from __future__ import annotations

import csv
import math
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

import numpy as np

from .errors import InputError
from .export_forces import (column_force_peak_table, column_force_table, listed, storey_shear_peak_table,
                            storey_shear_table)

Column = tuple[str, str]  # (name, unit; "" for a label)
Table = tuple[list[Column], Iterable[list[Any]]]


@dataclass(frozen=True)
class Quantity:
    """A CSV file pound can export: its description and the function that makes its table."""

    description: str
    table: Callable[[Any], Table]


def _history(name: str, units: tuple[str, str, str]) -> Callable[[Any], Table]:
    """A building history (displacement, velocity, acceleration): one row per time, building, floor."""

    def table(r: Any) -> Table:
        labels = ("u_x", "u_y", "theta_z") if name != "acceleration" else ("a_x", "a_y", "a_theta_z")
        labels = labels if name != "velocity" else ("v_x", "v_y", "v_theta_z")
        columns = [("time", "s"), ("building", ""), ("floor", "")] + list(zip(labels, units))

        def rows() -> Iterator[list[Any]]:
            for k, t in enumerate(r.time.tolist()):
                for b in r.buildings.values():
                    values = listed(getattr(b, name)[k])
                    for f, v in enumerate(values, start=1):
                        yield [t, b.name, f, *v]

        return columns, rows()

    return table


def _ground(r: Any) -> Table:
    columns = [("time", "s"), ("a_X", "m/s2"), ("a_Y", "m/s2")]
    return columns, ([t, *a] for t, a in zip(r.time.tolist(), r.ground_acceleration.tolist()))


def _energy(r: Any) -> Table:
    from .solver import ENERGY_NAMES

    columns = [("time", "s")] + [(name, "J") for name in ENERGY_NAMES]
    return columns, ([t, *e] for t, e in zip(r.time.tolist(), r.energy.tolist()))


def _interstorey_peaks(r: Any) -> Table:
    columns = [("building", ""), ("column", ""), ("storey", ""), ("dx", "m"), ("dy", "m"), ("dtheta", "rad")]

    def rows() -> Iterator[list[Any]]:
        for b in r.buildings.values():
            for c, name in enumerate(b.column_names):
                for s, v in enumerate(b.interstorey_deflection[c].tolist(), start=1):
                    yield [b.name, name, s, *v]

    return columns, rows()


def _floor_peaks(r: Any) -> Table:
    columns = [("building", ""), ("floor", ""), ("elevation", "m"), ("u_x", "m"), ("u_y", "m"), ("theta_z", "rad"),
               ("a_x", "m/s2"), ("a_y", "m/s2"), ("a_theta_z", "rad/s2")]  # fmt: skip

    def rows() -> Iterator[list[Any]]:
        for b in r.buildings.values():
            for f in range(b.elevation.size):
                yield [b.name, f + 1, float(b.elevation[f]), *b.peak_displacement[f].tolist(),
                       *b.peak_acceleration[f].tolist()]  # fmt: skip

    return columns, rows()


def _impacts(r: Any) -> Table:
    from .results.hdf5 import EVENT_UNITS

    events = r.contact.events
    units = [u.strip() for u in EVENT_UNITS.split(",")]
    columns = [(name, "" if unit == "-" else unit) for name, unit in zip(events.dtype.names, units)]
    return columns, ([_plain(row[name]) for name in events.dtype.names] for row in events)


def _contact(r: Any) -> Table:
    from .results.sparse import held

    c = r.contact
    columns = [("time", "s"), ("pair", ""), ("body_a", ""), ("floor_a", ""), ("body_b", ""), ("floor_b", ""),
               ("normal_force", "N"), ("tangential_force", "N"), ("area", "m2"), ("depth", "m"), ("x", "m"),
               ("y", "m")]  # fmt: skip

    def rows() -> Iterator[list[Any]]:
        pairs = [[_plain(p[k]) for k in ("body_a", "floor_a", "body_b", "floor_b")] for p in c.pairs]
        histories = [held(a) for a in (c.normal_force, c.tangential_force, c.area, c.depth, c.action_point)]
        for k, t in enumerate(r.time.tolist()):
            fn, ft, area, depth, point = (a.row(k).tolist() for a in histories)
            for p, names in enumerate(pairs):
                yield [t, p, *names, fn[p], ft[p], area[p], depth[p], *point[p]]

    return columns, rows()


def _yielding(r: Any) -> Table:
    columns = [("time", "s"), ("building", ""), ("member", ""), ("name", ""), ("kind", ""), ("storey", ""),
               ("deflection_x", "m"), ("deflection_y", "m"), ("force_x", "N"), ("force_y", "N")]  # fmt: skip

    def rows() -> Iterator[list[Any]]:
        yielding = [(b.name, b.yielding) for b in r.buildings.values() if b.yielding is not None]
        for k, t in enumerate(r.time.tolist()):
            for name, y in yielding:
                d, f = listed(y.deflection[k]), listed(y.force[k])
                for m, member in enumerate(y.members):
                    yield [t, name, m, member["name"], member["kind"], int(member["storey"]), *d[m], *f[m]]

    return columns, rows()


def _plain(value: Any) -> Any:
    value = value.item() if isinstance(value, np.generic) else value
    return value.decode() if isinstance(value, bytes) else value


QUANTITIES: dict[str, Quantity] = {
    "displacement": Quantity("floor displacements u_x, u_y, θ_z at the mass centres, global axes, relative to "
                             "the ground", _history("displacement", ("m", "m", "rad"))),
    "velocity": Quantity("floor velocities, global axes, relative to the ground",
                         _history("velocity", ("m/s", "m/s", "rad/s"))),
    "acceleration": Quantity("floor accelerations, global axes, absolute",
                             _history("acceleration", ("m/s2", "m/s2", "rad/s2"))),
    "ground": Quantity("the ground acceleration along global X, Y (after θ and scale)", _ground),
    "energy": Quantity("the energy balance: input, kinetic, strain, damping, hysteretic, contact, balance error",
                       _energy),
    "contact": Quantity("each contact pair's normal and tangential force, overlap area, depth and action point "
                        "(global) at the output instants", _contact),
    "yielding": Quantity("each yielding member's deflection and force along its local axes (hysteresis loops)",
                         _yielding),
    "interstorey_peaks": Quantity("peak interstorey deflection of every column in every storey, building axes; "
                                  "empty where a column line is absent", _interstorey_peaks),
    "floor_peaks": Quantity("peak displacement (relative) and acceleration (absolute) of every floor, global axes",
                            _floor_peaks),
    "impacts": Quantity("the impact log: one row per contact episode (docs/user-guide.md, HDF5 layout)", _impacts),
    "storey_shear": Quantity("storey shears V_x, V_y and torque T (building axes, about the mass centre of the floor "
                             "above) and V_X, V_Y, T_O (global axes, about the origin); storey 1's is the base shear",
                             storey_shear_table),
    "column_forces": Quantity("each column's shear along its local x, y and end moments V*h/2 (only if the run "
                              "stored them: analysis.column_force_histories)", column_force_table),
    "storey_shear_peaks": Quantity("peak storey shears and torques, components as storey_shear", storey_shear_peak_table),
    "column_force_peaks": Quantity("peak shear along local x, y and end moments of every column in every storey",
                                   column_force_peak_table),
}  # fmt: skip
"""What `pound export --what` names; the file is <name>.csv."""

GROUPS: dict[str, list[str]] = {
    "histories": ["displacement", "velocity", "acceleration", "ground", "energy", "contact", "yielding"],
    "peaks": ["interstorey_peaks", "floor_peaks"],
    "forces": ["storey_shear", "column_forces", "storey_shear_peaks", "column_force_peaks"],
    "all": list(QUANTITIES),
}
"""Names of several quantities at once."""


def chosen(what: list[str] | None) -> list[str]:
    """The quantities `what` names (quantities or groups; None or empty: all), in the order
    of QUANTITIES; InputError naming an unknown one."""
    if not what:
        return list(QUANTITIES)
    picked: set[str] = set()
    for name in what:
        if name in GROUPS:
            picked.update(GROUPS[name])
        elif name in QUANTITIES:
            picked.add(name)
        else:
            raise InputError(f"unknown quantity {name!r}; choose from {', '.join([*QUANTITIES, *GROUPS])}",
                             field="--what")  # fmt: skip
    return [q for q in QUANTITIES if q in picked]


def export_csv(result: str | Path, folder: str | Path, what: list[str] | None = None,
               force: bool = False) -> list[dict[str, Any]]:  # fmt: skip
    """Write the quantities `what` (names of QUANTITIES or GROUPS; default all) of the result
    file `result` as <folder>/<name>.csv; returns what was written, one dict per file:
    quantity, file, rows, columns ({name, unit}), description. InputError for a file that is
    no result, an unknown quantity, a folder that cannot be made or files that exist (unless
    `force`)."""
    from .atomic import atomic_path
    from .outputs import claim, refuse_inputs

    names = chosen(what)
    result, folder = Path(result), Path(folder)
    run = _read(result)
    if folder.exists() and not folder.is_dir():
        raise InputError("is a file; give a folder for the CSV files (--csv)", file=folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder ({exc.strerror})", file=folder) from None
    paths = {name: folder / f"{name}.csv" for name in names}
    for path in paths.values():
        refuse_inputs(path, [(result, "the result file being exported")], "another folder (--csv)")
    written = []
    with ExitStack() as stack:  # every file renamed into place only once all are complete
        for path in paths.values():
            stack.enter_context(claim(path, "pound export"))
        for path in paths.values():
            if path.exists() and not force:
                raise InputError("exists; choose another folder or pass --force to overwrite it", file=path)
        for name, path in paths.items():
            tmp = stack.enter_context(atomic_path(path))
            columns, rows = QUANTITIES[name].table(run)
            count = _write_csv(tmp, columns, rows)
            written.append({"quantity": name, "file": str(path), "rows": count,
                            "columns": [{"name": c, "unit": u or None} for c, u in columns],
                            "description": QUANTITIES[name].description})  # fmt: skip
    return written


def _read(result: Path) -> Any:
    """The RunResult of a pound result file, or an InputError saying what the file is not."""
    import h5py

    from .results import read_hdf5

    if not result.is_file():
        raise InputError("no such file; give a result file written by `pound run`", file=result)
    try:
        return read_hdf5(result)
    except (OSError, KeyError) as exc:
        what = "not an HDF5 file" if isinstance(exc, OSError) and not h5py.is_hdf5(result) else "not a pound result file"
        raise InputError(f"{what} ({exc}); give a result file written by `pound run`", file=result) from None


def _write_csv(tmp: Path, columns: list[Column], rows: Iterable[list[Any]]) -> int:
    """Write the header (`name [unit]`) and the rows to `tmp` (the temporary name atomic_path
    yields); NaN as an empty cell. Returns the row count."""
    from .interrupts import checkpoint

    count = 0
    with open(tmp, "w", encoding="utf-8", newline="") as out:
        writer = csv.writer(out)
        writer.writerow([f"{name} [{unit}]" if unit else name for name, unit in columns])
        for row in rows:
            writer.writerow(["" if isinstance(v, (float, np.floating)) and math.isnan(v) else v for v in row])
            count += 1
            if count % 100_000 == 0:
                checkpoint()  # Ctrl-C or SIGTERM abandons the export here
    return count
