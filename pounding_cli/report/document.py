"""The summary of a run that ``pound report`` prints, as a JSON document with a JSON Schema.

:func:`summary` is the Python API behind ``pound report out.h5 --json``: the model and
record, the integrator and run time, each building's periods and peak interstorey
deflections (per column and storey, as stored), its yielding members (inelastic columns and
isolators: peak ductility, peak deflection and force, residual deflection), the impact log and
its pairs, and the energy balance. Every number is the HDF5 dataset's value, unconverted (SI units: m, rad, s, N, J);
NaN (a column line absent from a storey, an impact lasting to the end) is null. The
classes below define the document; ``schemas/report.schema.json`` is written from them by
``pound schema``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from .document_model import _Output
from .demand_document import StruckColumn, struck_columns
from .force_document import ForceReport, force_report
from .load import Run, open_run

G = 9.80665
"""Standard gravity, m/s² (PGA in g)."""


class Peak(_Output):
    """A building's largest peak interstorey deflection of one component, and where."""

    value: float
    """The peak: m for x and y (building axes), rad for θ."""
    unit: str
    """"m" or "rad"."""
    column: str | None
    """The first column where it occurs; null for θ (a storey's twist is the same at every column)."""
    storey: int
    """The storey (1 = ground storey) where it occurs."""


class StoreyPeak(_Output):
    """The largest peak interstorey deflections of one storey over its columns."""

    storey: int
    """Storey number, 1 = ground storey (below floor 1)."""
    x_m: float | None
    """Largest peak |Δu_x| over the storey's columns, m (building axes)."""
    x_column: str | None
    """The column where x_m occurs."""
    y_m: float | None
    """Largest peak |Δu_y| over the storey's columns, m (building axes)."""
    y_column: str | None
    """The column where y_m occurs."""
    theta_rad: float | None
    """Peak |Δθ| of the storey, rad."""


class ColumnReport(_Output):
    """One column line and its peak interstorey deflections in every storey."""

    name: str
    """Column name (C1, C2, ... for a grid)."""
    x_m: float
    """Plan position, building x, m."""
    y_m: float
    """Plan position, building y, m."""
    interstorey_deflection: list[list[float | None]]
    """Per storey from the ground up: peak |Δu_x| m, |Δu_y| m (building axes), |Δθ| rad; the
    row of /buildings/<name>/peaks/interstorey_deflection; null where the column is absent."""


class MemberReport(_Output):
    """One yielding member (an inelastic column in one storey, or an isolator): a row of
    /buildings/<name>/yielding/members with its peaks, ductility and residual deflection.
    Deflections and forces are along the member's local axes."""

    name: str
    """Member name: the column line (C9; one member per storey) or the isolator (I1)."""
    kind: str
    """"column" or "isolator"."""
    storey: int
    """Storey, 1-based (storey 1 of an isolated building is the isolation storey)."""
    X_m: float
    """Plan position, global X, m."""
    Y_m: float
    """Plan position, global Y, m."""
    yield_force_N: list[float]
    """Yield force along local x, y, N."""
    yield_deflection_m: list[float]
    """Yield deflection F_y/k along local x, y, m."""
    peak_deflection_m: list[float]
    """Peak |δ_x|, |δ_y| and resultant |δ| over every step, m (the row of yielding/peak)."""
    peak_force_N: list[float]
    """Peak |f_x|, |f_y| and resultant |f| over every step, N (the row of yielding/peak)."""
    ductility: list[float]
    """Peak ductility |δ|/δ_y along local x, y (below 1: stayed elastic along that axis)."""
    residual_deflection_m: list[float]
    """Residual deflection δ_x, δ_y at rest after the run, m (signed)."""
    residual_m: float
    """Resultant residual deflection √(δ_x² + δ_y²), m."""


class StoreyDuctility(_Output):
    """The largest peak ductility of one storey's inelastic columns, per local axis."""

    storey: int
    """Storey number, 1-based."""
    columns: int
    """Inelastic columns in the storey."""
    yielded: int
    """Of them, the columns whose peak ductility exceeds 1 along some axis."""
    ductility_x: float
    """Largest peak ductility along local x."""
    x_column: str
    """The column where ductility_x occurs."""
    ductility_y: float
    """Largest peak ductility along local y."""
    y_column: str
    """The column where ductility_y occurs."""
    residual_m: float
    """Largest resultant residual deflection of the storey's columns, m."""
    residual_column: str
    """The column where residual_m occurs."""


class YieldingReport(_Output):
    """A building's yielding members: inelastic columns and isolators."""

    columns: int
    """Inelastic column members (one per column line and storey)."""
    isolators: int
    """Isolators (0 unless the building is base-isolated)."""
    max_ductility: float | None
    """Largest peak ductility over the inelastic columns, either axis; null without any."""
    max_ductility_member: MemberReport | None
    """The column member where max_ductility occurs; null without inelastic columns."""
    storey_ductility: list[StoreyDuctility]
    """Per storey with inelastic columns, its largest ductilities and residual deflection."""
    peak_isolator_displacement_m: float | None
    """Largest peak resultant isolator displacement, m; null without isolators."""
    peak_isolator_force_N: float | None
    """Largest peak resultant isolator force, N; null without isolators."""
    members: list[MemberReport]
    """Every yielding member in the file's order; with --column, the columns of that line
    and every isolator ("C9"), or none in another building than the one named ("left:C9")."""


class BuildingReport(_Output):
    """One building: size, modes and peak responses."""

    name: str
    """Building name (its HDF5 group)."""
    storeys: int
    """Number of floors (= storeys)."""
    height_m: float
    """Elevation of the top floor, m."""
    mass_kg: float
    """Total floor mass, kg."""
    column_lines: int
    """Number of column lines."""
    periods_s: list[float]
    """Natural periods, longest first, s (/modes/period)."""
    rayleigh_a0_per_s: float
    """Rayleigh mass coefficient a0, 1/s."""
    rayleigh_a1_s: float
    """Rayleigh stiffness coefficient a1, s."""
    peak_interstorey: dict[str, Peak]
    """Largest peak interstorey deflection over all columns and storeys: keys x, y, theta."""
    storey_peaks: list[StoreyPeak]
    """Per storey, the largest peak interstorey deflections over its columns."""
    columns: list[ColumnReport]
    """Every column line, or only the one asked for with --column."""
    peak_displacement: list[list[float]]
    """Per floor: peak |u_x| m, |u_y| m, |θ_z| rad, global axes, relative to the ground."""
    peak_acceleration: list[list[float]]
    """Per floor: peak absolute |a_x| m/s², |a_y| m/s², |α_z| rad/s², global axes."""
    isolated: bool
    """Whether the building is base-isolated: floor 1 is its base slab, storey 1 the isolation storey."""
    yielding: YieldingReport | None
    """Inelastic columns and isolators (/buildings/<name>/yielding); null if it has none."""
    forces: ForceReport | None = None
    """Peak storey shears and column forces; null in a file written before pound stored them."""


class ImpactEvent(_Output):
    """One contact episode: a row of /impacts/events."""

    body_a: str
    """Building (or obstacle) A."""
    body_b: str
    """Building or obstacle B."""
    level: int
    """Floor of body A, 1-based."""
    floor_b: int
    """Floor of body B, 1-based; 0 for an obstacle."""
    elevation: float
    """Elevation of the contact, m."""
    t_start: float
    """Start of the episode, s."""
    t_end: float | None
    """End of the episode, s; null if the contact lasted to the end."""
    t_peak: float
    """Time of the peak normal force, s."""
    peak_normal_force: float
    """Peak normal force, N."""
    normal_impulse: float
    """∫F_N dt over the episode, N·s."""
    peak_area: float
    """Largest overlap area, m²."""
    peak_depth: float
    """Largest overlap extent along the normal, m."""
    x: float
    """Action point at the peak force, global X, m."""
    y: float
    """Action point at the peak force, global Y, m."""
    slid: bool
    """Whether the contact slipped."""
    pair: int
    """Row of /impacts/pairs (0-based)."""
    tangential_force_at_peak: float | None
    """Tangential force on body B at the peak normal force, N, signed along t = ẑ × n; null in
    files written before the log kept it."""
    normal_x: float | None
    """Unit normal n from A into B at the peak normal force, global X component, dimensionless;
    null in files written before the log kept it."""
    normal_y: float | None
    """Unit normal n from A into B at the peak normal force, global Y component, dimensionless;
    null in files written before the log kept it."""
    t_slip: float | None = None
    """Where the contact first slipped, s (t_start if it slipped from the touch), located inside
    its step; null if it never slipped, or in files written before the log kept it."""
    t_stick: float | None = None
    """Where its last slip ended, s, located inside its step; null if it never slipped or slipped
    to its end."""
    slips: int = 0
    """Its number of slip phases (0 in files written before the log counted them)."""


class PairReport(_Output):
    """One contact candidate pair and the impacts it saw."""

    pair: int
    """Row of /impacts/pairs (0-based)."""
    body_a: str
    """Building A."""
    floor_a: int
    """Floor of A, 1-based."""
    body_b: str
    """Building or obstacle B."""
    floor_b: int
    """Floor of B, 1-based; 0 for an obstacle."""
    elevation_m: float
    """Elevation of the pair, m."""
    k_normal_N_per_m2: float
    """Impact stiffness k_N, N/m² of overlap area."""
    k_tangential_N_per_m: float
    """Tangential stiffness k_T, N/m."""
    impacts: int
    """Logged contact episodes of this pair."""
    peak_normal_force_N: float
    """Largest peak normal force of its episodes, N (0 if none)."""
    t_peak_s: float | None
    """Time of that peak, s; null if none."""
    normal_impulse_Ns: float
    """Sum of its episodes' normal impulses, N·s."""


class Impacts(_Output):
    """The impact log."""

    count: int
    """Logged contact episodes (rows of /impacts/events)."""
    total: int
    """Contact episodes counted by the solver (more than count only past the logging limit)."""
    peak_normal_force_N: float
    """Largest normal force of the run, N (0 without impacts)."""
    peak: ImpactEvent | None
    """The episode with the largest normal force; null without impacts."""
    pairs: list[PairReport]
    """Every contact candidate pair."""
    events: list[ImpactEvent]
    """Every logged episode, in the order of the log."""
    struck_columns: list[StruckColumn] = []
    """Columns struck between their floors by a neighbour's slab, with their demand/capacity (empty without such impacts)."""


class Record(_Output):
    """The ground motion as the model applied it."""

    name: str
    """The record's name, or the path of its definition file."""
    components: list[str]
    """Applied components: L, T or both."""
    angle_deg: float
    """Angle θ of component L from global X, degrees."""
    scale: float
    """The excitation's scale factor, dimensionless."""
    pga_X_g: float
    """Peak |a_X| of /ground/acceleration (at the output instants), g."""
    pga_Y_g: float
    """Peak |a_Y| of /ground/acceleration (at the output instants), g."""


class Analysis(_Output):
    """How the run was integrated and how long it took."""

    integrator: str
    """The integrator, as the run reports it."""
    dt_s: float | None
    """Time step, s."""
    steps: int | None
    """Time steps taken."""
    duration_s: float
    """Last stored time, s (short of the planned duration if the run failed)."""
    output_interval_s: float | None
    """Interval of the stored histories, s."""
    solver_wall_time_s: float | None
    """Wall time of the time loop, s."""
    compile_time_s: float | None
    """Compiling or loading the compiled loop, s."""
    run_time_s: float | None
    """The whole analysis, s."""
    us_per_step: float | None
    """Solver time per step, µs."""
    contact_steps: int | None
    """Steps with some pair in contact."""


class Energy(_Output):
    """The energy balance (relative-motion energies)."""

    balance_error_ratio: float
    """max |E_input − Σ E| over max E_input, dimensionless."""
    max_input_J: float
    """Largest input energy over the run, J."""
    final_J: dict[str, float]
    """Every column of /energy at the last stored time, J."""


class RunReport(_Output):
    """The document ``pound report out.h5 --json`` prints (several files: a list of them)."""

    file: str
    """The result file."""
    status: str
    """"complete", or "failed: …" for a run that failed (its results are partial)."""
    complete: bool
    """Whether the run completed."""
    pound_version: str
    """Version of pound that wrote the file."""
    input_sha256: str
    """Hash of the resolved model, the record files and the version."""
    title: str
    """The model's title."""
    column: str | None
    """The column the report is narrowed to (--column), or null."""
    record: Record
    """The ground motion."""
    analysis: Analysis
    """Integrator, time step and run time."""
    buildings: list[BuildingReport]
    """Each building, in the file's order."""
    impacts: Impacts
    """The impact log."""
    energy: Energy
    """The energy balance."""
    diagnostics: dict[str, Any]
    """Every attribute of /diagnostics, as stored."""


def summary(path: str | Path | Run, column: str | None = None) -> dict[str, Any]:
    """The JSON document of ``pound report PATH --json``; `column` narrows each building's
    column list to that column ("C9") or to one building's ("left:C9")."""
    run = path if isinstance(path, Run) else open_run(path)
    return report_of(run, column).model_dump(mode="json")


def report_of(run: Run, column: str | None = None) -> RunReport:
    """The summary of `run` as a validated :class:`RunReport`."""
    r = run.result
    d = r.diagnostics
    check_column(run, column)
    return RunReport(
        file=str(run.path),
        status=r.status,
        complete=r.complete,
        pound_version=_attr(run.path, "pound_version"),
        input_sha256=r.input_sha256,
        title=run.model.get("title", ""),
        column=column,
        record=_record(run),
        analysis=Analysis(
            integrator=str(d.get("integrator", "")),
            dt_s=d.get("dt"),
            steps=d.get("steps"),
            duration_s=float(r.time[-1]) if r.time.size else 0.0,
            output_interval_s=d.get("output_interval"),
            solver_wall_time_s=d.get("wall_time_s"),
            compile_time_s=d.get("compile_time_s"),
            run_time_s=d.get("run_time_s"),
            us_per_step=d.get("us_per_step"),
            contact_steps=d.get("contact_steps"),
        ),
        buildings=[_building(b, column) for b in r.buildings.values()],
        impacts=_impacts(run),
        energy=Energy(
            balance_error_ratio=r.balance_error_ratio,
            max_input_J=float(np.abs(r.energy_column("input")).max(initial=0.0)),
            final_J={name: float(r.energy[-1, k]) if r.time.size else 0.0 for k, name in enumerate(_energy_names())},
        ),
        diagnostics={k: _json_value(v) for k, v in d.items()},
    )


def check_column(run: Run, column: str | None) -> None:
    """InputError unless some building of `run` has `column` ("C9" or "left:C9")."""
    if column is None:
        return
    from ..errors import InputError

    if not any(columns_of(b, column) for b in run.result.buildings.values()):
        names = [f"{b.name}:{c}" for b in run.result.buildings.values() for c in b.column_names]
        raise InputError(
            f"no building has a column {column!r}; give a column name (C9) or building:column, one of "
            f"{', '.join(names[:30])}" + (", …" if len(names) > 30 else ""),
            file=run.path, field="--column",
        )  # fmt: skip


def columns_of(b: Any, column: str | None) -> list[int]:
    """Indices of the column lines of building `b` selected by `column` (all when None)."""
    if column is None:
        return list(range(len(b.column_names)))
    building, _, name = column.rpartition(":")
    if building and building != b.name:
        return []
    return [i for i, n in enumerate(b.column_names) if n == name]


def _attr(path: Path, name: str) -> str:
    import h5py

    with h5py.File(path, "r") as f:
        value = f.attrs.get(name, "")
    return value.decode() if isinstance(value, bytes) else str(value)


def _energy_names() -> tuple[str, ...]:
    from ..results import ENERGY_NAMES

    return tuple(ENERGY_NAMES)


def _record(run: Run) -> Record:
    e = run.model.get("excitation", {})
    rec = e.get("record", "")
    name = (rec.get("name") or "inline record") if isinstance(rec, dict) else str(rec)
    acc = np.abs(run.result.ground_acceleration)
    pga = acc.max(axis=0) / G if acc.size else np.zeros(2)
    return Record(
        name=name,
        components=list(e.get("components", [])),
        angle_deg=float(e.get("angle", 0.0)),
        scale=float(e.get("scale", 1.0)),
        pga_X_g=float(pga[0]),
        pga_Y_g=float(pga[1]),
    )


def _nullable(values: np.ndarray) -> list[Any]:
    return [None if not math.isfinite(v) else float(v) for v in np.asarray(values, dtype=float).ravel()]


def _building(b: Any, column: str | None) -> BuildingReport:
    isd = b.interstorey_deflection
    n_storeys = b.elevation.size
    peaks: dict[str, Peak] = {}
    for k, comp in enumerate(("x", "y", "theta")):
        values = isd[:, :, k]
        if values.size == 0 or np.isnan(values).all():
            continue
        c, s = np.unravel_index(np.nanargmax(values), values.shape)
        peaks[comp] = Peak(
            value=float(values[c, s]), unit="rad" if comp == "theta" else "m",
            column=None if comp == "theta" else b.column_names[c], storey=int(s) + 1,
        )  # fmt: skip
    storeys = []
    for s in range(n_storeys):
        row: dict[str, Any] = {"storey": s + 1}
        for k, comp in enumerate(("x", "y")):
            values = isd[:, s, k]
            ok = not np.isnan(values).all()
            row[f"{comp}_m"] = float(np.nanmax(values)) if ok else None
            row[f"{comp}_column"] = b.column_names[int(np.nanargmax(values))] if ok else None
        theta = isd[:, s, 2]
        row["theta_rad"] = float(np.nanmax(theta)) if not np.isnan(theta).all() else None
        storeys.append(StoreyPeak(**row))
    columns = [
        ColumnReport(
            name=b.column_names[i], x_m=float(b.column_local[i, 0]), y_m=float(b.column_local[i, 1]),
            interstorey_deflection=[_nullable(isd[i, s]) for s in range(n_storeys)],
        )  # fmt: skip
        for i in columns_of(b, column)
    ]
    return BuildingReport(
        name=b.name,
        storeys=n_storeys,
        height_m=float(b.elevation[-1] - b.base_elevation) if n_storeys else 0.0,
        mass_kg=float(b.floor_mass[:, 0].sum()),
        column_lines=len(b.column_names),
        periods_s=[float(t) for t in b.periods],
        rayleigh_a0_per_s=float(b.rayleigh[0]),
        rayleigh_a1_s=float(b.rayleigh[1]),
        peak_interstorey=peaks,
        storey_peaks=storeys,
        columns=columns,
        peak_displacement=b.peak_displacement.tolist(),
        peak_acceleration=b.peak_acceleration.tolist(),
        isolated=bool(b.isolated),
        yielding=_yielding(b, column),
        forces=force_report(b, columns_of(b, column)),
    )


def members_of(b: Any, column: str | None, kind: str | None = None) -> list[int]:
    """Indices of building `b`'s yielding members of `kind` ("column", "isolator" or both when
    None); `column` keeps only the inelastic columns of that line and the isolators ("C9"), or
    in building "left" only ("left:C9": no member of another building)."""
    y = b.yielding
    if y is None:
        return []
    out = []
    building, _, name = (column or "").rpartition(":")
    if building and building != b.name:
        return []
    for i, m in enumerate(y.members):
        if kind is not None and m["kind"] != kind:
            continue
        if column is not None and m["kind"] == "column" and m["name"] != name:
            continue
        out.append(i)
    return out


def _member(y: Any, i: int) -> MemberReport:
    m = y.members[i]
    residual = y.residual_deflection[i]
    return MemberReport(
        name=str(m["name"]), kind=str(m["kind"]), storey=int(m["storey"]), X_m=float(m["X"]), Y_m=float(m["Y"]),
        yield_force_N=m["yield_force"].tolist(), yield_deflection_m=y.yield_deflection[i].tolist(),
        peak_deflection_m=y.peak[i, :3].tolist(), peak_force_N=y.peak[i, 3:].tolist(),
        ductility=y.ductility[i].tolist(), residual_deflection_m=residual.tolist(),
        residual_m=float(np.hypot(residual[0], residual[1])),
    )  # fmt: skip


def _yielding(b: Any, column: str | None) -> YieldingReport | None:
    y = b.yielding
    if y is None or y.members.size == 0:
        return None
    kinds = y.members["kind"]
    cols = np.flatnonzero(kinds == "column")
    isos = np.flatnonzero(kinds == "isolator")
    mu = y.ductility
    residual = np.hypot(y.residual_deflection[:, 0], y.residual_deflection[:, 1])
    worst = int(cols[np.argmax(mu[cols].max(axis=1))]) if cols.size else None
    storeys = []
    for s in sorted({int(v) for v in y.members["storey"][cols]}):
        here = cols[y.members["storey"][cols] == s]
        ix, iy, ir = (int(here[np.argmax(v[here])]) for v in (mu[:, 0], mu[:, 1], residual))
        storeys.append(StoreyDuctility(
            storey=s, columns=int(here.size), yielded=int((mu[here].max(axis=1) > 1).sum()),
            ductility_x=float(mu[ix, 0]), x_column=str(y.members["name"][ix]),
            ductility_y=float(mu[iy, 1]), y_column=str(y.members["name"][iy]),
            residual_m=float(residual[ir]), residual_column=str(y.members["name"][ir]),
        ))  # fmt: skip
    return YieldingReport(
        columns=int(cols.size),
        isolators=int(isos.size),
        max_ductility=float(mu[worst].max()) if worst is not None else None,
        max_ductility_member=_member(y, worst) if worst is not None else None,
        storey_ductility=storeys,
        peak_isolator_displacement_m=float(y.peak[isos, 2].max()) if isos.size else None,
        peak_isolator_force_N=float(y.peak[isos, 5].max()) if isos.size else None,
        members=[_member(y, i) for i in members_of(b, column)],
    )


def _event(row: np.void) -> ImpactEvent:
    fields = {name: row[name] for name in ImpactEvent.model_fields}
    out = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in fields.items()}
    for name in ("t_end", "tangential_force_at_peak", "normal_x", "normal_y", "t_slip", "t_stick"):
        if not math.isfinite(out[name]):
            out[name] = None
    return ImpactEvent(**out)


def _impacts(run: Run) -> Impacts:
    c = run.result.contact
    events = [_event(row) for row in c.events]
    pairs = []
    for i, p in enumerate(c.pairs):
        mine = c.events[c.events["pair"] == i]
        top = int(np.argmax(mine["peak_normal_force"])) if mine.size else None
        pairs.append(
            PairReport(
                pair=i, body_a=str(p["body_a"]), floor_a=int(p["floor_a"]), body_b=str(p["body_b"]),
                floor_b=int(p["floor_b"]), elevation_m=float(p["elevation"]),
                k_normal_N_per_m2=float(p["k_normal"]), k_tangential_N_per_m=float(p["k_tangential"]),
                impacts=int(mine.size),
                peak_normal_force_N=float(mine["peak_normal_force"][top]) if top is not None else 0.0,
                t_peak_s=float(mine["t_peak"][top]) if top is not None else None,
                normal_impulse_Ns=float(mine["normal_impulse"].sum()),
            )  # fmt: skip
        )
    peak = events[int(np.argmax(c.events["peak_normal_force"]))] if events else None
    return Impacts(
        count=len(events),
        total=int(run.result.diagnostics.get("impacts", len(events))),
        peak_normal_force_N=c.peak_force,
        peak=peak,
        pairs=pairs,
        events=events,
        struck_columns=struck_columns(c.column_demand),
    )


def _json_value(value: Any) -> Any:
    """An HDF5 attribute value as JSON (arrays as lists, NaN and inf as null)."""
    if isinstance(value, np.ndarray):
        return [_json_value(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def summary_schema() -> dict[str, Any]:
    """JSON Schema of the document :func:`summary` returns."""
    return RunReport.model_json_schema(mode="serialization")
