"""The tables of a run's report, as plain data: the CLI renders them with rich, the HTML
report as HTML tables. Built from the :func:`~pounding_cli.report.document.summary` document,
so the tables and ``--json`` cannot disagree. Units are converted for reading here only:
mm, mrad, kN, t.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass
class TableSpec:
    """One table: a title, column headers, rows of text cells; `right` marks the columns
    aligned right (numbers)."""

    title: str
    headers: list[str]
    rows: list[list[str]] = field(default_factory=list)
    right: set[int] = field(default_factory=set)


def status_line(doc: dict[str, Any]) -> str | None:
    """The warning printed above everything for a failed or partial run; None if complete."""
    if doc["complete"]:
        return None
    return (
        f"FAILED RUN: {doc['status'].removeprefix('failed: ')}. The results are partial: they end at t = "
        f"{doc['analysis']['duration_s']:.4g} s, and every peak is over that span only."
    )


def _num(value: float | None, scale: float = 1.0, digits: int = 4) -> str:
    return "-" if value is None else f"{scale * value:.{digits}g}"


def run_table(doc: dict[str, Any]) -> TableSpec:
    """Model, record, integrator, Δt, run time, impacts and energy balance, as key-value rows."""
    a, rec, imp = doc["analysis"], doc["record"], doc["impacts"]
    solver = _num(a["solver_wall_time_s"], digits=3) + " s"
    if a["us_per_step"] is not None:
        solver += f" ({a['us_per_step']:.3g} µs/step)"
    peak = imp["peak"]
    impacts = str(imp["count"]) + (f" logged of {imp['total']}" if imp["total"] != imp["count"] else "")
    if peak:
        impacts += (f"; peak normal force {peak['peak_normal_force'] / 1e3:,.0f} kN at t = {peak['t_peak']:.4f} s, "
                    f"{peak['body_a']} floor {peak['level']} against {peak['body_b']}"
                    + (f" floor {peak['floor_b']}" if peak["floor_b"] else ""))  # fmt: skip
    rows = [
        ("status", doc["status"]),
        ("model", doc["title"] or "-"),
        ("file", doc["file"]),
        ("record", f"{rec['name']}: {'+'.join(rec['components'])} at θ = {rec['angle_deg']:g}°, scale {rec['scale']:g}; "
                   f"PGA X {rec['pga_X_g']:.3f} g, Y {rec['pga_Y_g']:.3f} g"),
        ("integrator", a["integrator"] or "-"),
        ("Δt", _num(a["dt_s"]) + " s" + (f", {a['steps']:,} steps" if a["steps"] is not None else "")),
        ("duration", f"{a['duration_s']:.4g} s, output every {_num(a['output_interval_s'])} s"),
        ("run time", f"solver {solver}; compile {_num(a['compile_time_s'], digits=3)} s; "
                     f"whole run {_num(a['run_time_s'], digits=3)} s"),
        ("impacts", impacts),
        ("energy balance error", f"{100 * doc['energy']['balance_error_ratio']:.3g} % of the peak input "
                                 f"({doc['energy']['max_input_J'] / 1e3:.4g} kJ)"),
    ]  # fmt: skip
    if doc["column"]:
        rows.append(("column", doc["column"]))
    return TableSpec("Run", ["", ""], [list(r) for r in rows])


def _where(peak: dict[str, Any] | None, scale: float) -> str:
    if not peak:
        return "-"
    where = f"{peak['column']}, storey {peak['storey']}" if peak["column"] else f"storey {peak['storey']}"
    return f"{scale * peak['value']:.3g} ({where})"


def buildings_table(doc: dict[str, Any]) -> TableSpec:
    """Per building: size and the first three periods."""
    headers = ["building", "storeys", "height (m)", "mass (t)", "column lines", "T1 (s)", "T2 (s)", "T3 (s)"]
    rows = []
    for b in doc["buildings"]:
        periods = [f"{t:.4f}" for t in b["periods_s"][:3]] + ["-"] * max(0, 3 - len(b["periods_s"]))
        rows.append([b["name"], str(b["storeys"]), f"{b['height_m']:g}", f"{b['mass_kg'] / 1e3:.6g}",
                     str(b["column_lines"]), *periods])  # fmt: skip
    return TableSpec("Buildings", headers, rows, right=set(range(1, 8)))


def peaks_table(doc: dict[str, Any]) -> TableSpec:
    """Per building, the largest peak interstorey deflections over all columns and storeys,
    with the column and storey where each occurs."""
    rows = []
    for b in doc["buildings"]:
        p = b["peak_interstorey"]
        rows.append([b["name"], _where(p.get("x"), 1e3), _where(p.get("y"), 1e3), _where(p.get("theta"), 1e3)])
    return TableSpec("Largest peak interstorey deflection (building axes)",
                     ["building", "Δx (mm)", "Δy (mm)", "Δθ (mrad)"], rows)  # fmt: skip


def deflection_tables(doc: dict[str, Any]) -> list[TableSpec]:
    """Per building, per storey: the peak interstorey deflections of the --column, or the
    largest over the storey's columns with the column where each occurs."""
    out = []
    for b in doc["buildings"]:
        if doc["column"]:
            for c in b["columns"]:
                rows = [[str(s + 1), _num(dx, 1e3), _num(dy, 1e3), _num(dt, 1e3)]
                        for s, (dx, dy, dt) in enumerate(c["interstorey_deflection"])]  # fmt: skip
                out.append(TableSpec(f"Peak interstorey deflection: {b['name']}, column {c['name']} (building axes)",
                                     ["storey", "Δx (mm)", "Δy (mm)", "Δθ (mrad)"], rows, right={0, 1, 2, 3}))  # fmt: skip
            continue
        rows = [
            [str(s["storey"]), _num(s["x_m"], 1e3), s["x_column"] or "-", _num(s["y_m"], 1e3), s["y_column"] or "-",
             _num(s["theta_rad"], 1e3)]
            for s in b["storey_peaks"]
        ]  # fmt: skip
        out.append(TableSpec(f"Peak interstorey deflection: {b['name']}, largest over the columns (building axes)",
                             ["storey", "Δx (mm)", "column", "Δy (mm)", "column", "Δθ (mrad)"], rows,
                             right={0, 1, 3, 5}))  # fmt: skip
    return out


WORST = 6
"""Rows of the table of most ductile columns (a building may have hundreds of members)."""


def _mm(value: float, digits: int = 3) -> str:
    """Metres as mm; below 0.5 µm (round-off of a member that stayed elastic) as 0."""
    return "0" if abs(value) < 5e-7 else f"{1e3 * value:.{digits}g}"


def _pair(values: list[float], scale: float = 1.0, digits: int = 3) -> str:
    if scale == 1e3:
        return " / ".join(_mm(v, digits) for v in values)
    return " / ".join(f"{scale * v:.{digits}g}" for v in values)


def _member_row(m: dict[str, Any]) -> list[str]:
    return [m["name"], str(m["storey"]), f"{m['ductility'][0]:.3g}", f"{m['ductility'][1]:.3g}",
            _pair(m["peak_deflection_m"][:2], 1e3), _pair(m["residual_deflection_m"], 1e3),
            _mm(m["residual_m"])]  # fmt: skip


MEMBER_HEADERS = ["column", "storey", "μx", "μy", "peak δx / δy (mm)", "residual δx / δy (mm)", "residual |δ| (mm)"]


def yielding_tables(doc: dict[str, Any]) -> list[TableSpec]:
    """Per building with yielding members: its inelastic columns — the largest peak ductility
    per storey and the most ductile members, or with --column that column line's members in
    every storey — and its isolators, each with its peak resultant displacement and force and
    its residual displacement. Ductility μ = peak |δ| / δ_y along the member's local axes."""
    out = []
    for b in doc["buildings"]:
        y = b["yielding"]
        if not y:
            continue
        columns = [m for m in y["members"] if m["kind"] == "column"]
        if y["columns"] and not doc["column"]:
            rows = [[str(s["storey"]), f"{s['yielded']} of {s['columns']}", f"{s['ductility_x']:.3g}", s["x_column"],
                     f"{s['ductility_y']:.3g}", s["y_column"], _mm(s["residual_m"]), s["residual_column"]]
                    for s in y["storey_ductility"]]  # fmt: skip
            out.append(TableSpec(f"Inelastic columns: {b['name']}, largest peak ductility per storey (member local axes)",
                                 ["storey", "yielded", "μx", "column", "μy", "column", "residual |δ| (mm)", "column"],
                                 rows, right={0, 1, 2, 4, 6}))  # fmt: skip
            worst = sorted(columns, key=lambda m: -max(m["ductility"]))[:WORST]
            what = f"the {len(worst)} most ductile of {len(columns)}" if len(worst) < len(columns) else "all, most ductile first"
            out.append(TableSpec(f"Inelastic columns: {b['name']}, {what}", MEMBER_HEADERS,
                                 [_member_row(m) for m in worst], right=set(range(1, 7))))  # fmt: skip
        elif columns:
            out.append(TableSpec(f"Inelastic columns: {b['name']}, column {doc['column']} (member local axes)",
                                 MEMBER_HEADERS, [_member_row(m) for m in columns], right=set(range(1, 7))))  # fmt: skip
        isolators = [m for m in y["members"] if m["kind"] == "isolator"]
        if isolators:
            rows = [[m["name"], f"{1e3 * m['peak_deflection_m'][2]:.4g}", f"{m['peak_force_N'][2] / 1e3:.4g}",
                     _pair(m["yield_force_N"], 1e-3), f"{max(m['ductility']):.3g}",
                     _pair(m["residual_deflection_m"], 1e3), _mm(m["residual_m"])]
                    for m in isolators]  # fmt: skip
            out.append(TableSpec(f"Isolators: {b['name']} (storey 1, the isolation storey)",
                                 ["isolator", "peak |δ| (mm)", "peak |f| (kN)", "F_y x / y (kN)", "μ",
                                  "residual δx / δy (mm)", "residual |δ| (mm)"], rows, right=set(range(1, 7))))  # fmt: skip
    return out


def impacts_table(doc: dict[str, Any]) -> TableSpec | None:
    """Per contact candidate pair: impacts, peak normal force and its time, total impulse."""
    pairs = doc["impacts"]["pairs"]
    if not pairs:
        return None
    rows = []
    for p in pairs:
        b = f"{p['body_b']} floor {p['floor_b']}" if p["floor_b"] else p["body_b"]
        rows.append([f"{p['body_a']} floor {p['floor_a']}", b, f"{p['elevation_m']:g}", str(p["impacts"]),
                     f"{p['peak_normal_force_N'] / 1e3:,.0f}" if p["impacts"] else "-",
                     f"{p['t_peak_s']:.4f}" if p["t_peak_s"] is not None else "-",
                     f"{p['normal_impulse_Ns'] / 1e3:.4g}" if p["impacts"] else "-"])  # fmt: skip
    return TableSpec("Impacts per contact pair", ["body A", "body B", "elevation (m)", "impacts",
                     "peak F_N (kN)", "at t (s)", "impulse (kN·s)"], rows, right={2, 3, 4, 5, 6})  # fmt: skip


def energy_table(doc: dict[str, Any]) -> TableSpec:
    """The energies at the end of the run, kJ."""
    final = doc["energy"]["final_J"]
    return TableSpec("Energy at the end of the run (kJ)", list(final),
                     [[f"{v / 1e3:.4g}" for v in final.values()]], right=set(range(len(final))))  # fmt: skip


def run_tables(doc: dict[str, Any]) -> list[TableSpec]:
    """Every table of a run's report, in order."""
    from .demand_document import demand_table  # it builds on TableSpec
    from .force_tables import force_tables

    tables = [run_table(doc), buildings_table(doc), peaks_table(doc), *deflection_tables(doc), *force_tables(doc),
              *yielding_tables(doc)]  # fmt: skip
    impacts = impacts_table(doc)
    if impacts is not None:
        tables.append(impacts)
    tables += demand_table(doc)
    tables.append(energy_table(doc))
    return tables


def rich_table(spec: TableSpec) -> Any:
    """`spec` for rich: its title on a line of its own (never wrapped to the table's width)
    above a :class:`rich.table.Table`."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    key_value = all(h == "" for h in spec.headers)
    table = Table(show_header=not key_value)
    for i, h in enumerate(spec.headers):
        table.add_column(h, justify="right" if i in spec.right else "left", style="bold" if key_value and i == 0 else None)
    for row in spec.rows:
        table.add_row(*row)
    return Group(Text(spec.title, style="bold"), table)
