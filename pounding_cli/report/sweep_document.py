"""The report of a sweep folder: its JSON document (``pound report DIR/ --json``), the JSON
Schema of that document, and its tables.

The document holds the summary as the folder's case files give it now (:mod:`.sweep_data`)
— every column described, one row per case, the rows exactly the objects of ``pound sweep
--json`` (validated by ``schemas/sweep-summary.schema.json``) — with the sweep's title,
files, studies and counts. The tables show the cases with their parameters and results in
mm, mrad and kN; a parameter value that is a list or a table (an inline record) is shortened
to its name or to about 40 characters there, and kept whole in the JSON.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from pydantic import BaseModel, ConfigDict

from .sweep_data import FROM_CASE_FILES, MANIFEST, SUMMARY, Sweep, column_names, open_sweep, select, short_value
from .tables import TableSpec


class _Output(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)


class SummaryColumn(_Output):
    """One column of the summary table."""

    name: str
    """Column name: a case column, a swept path, or a result such as peak_isd_x_m[left/C9/1]."""
    kind: str
    """"case", "parameter" or "result"."""
    dtype: str
    """Value type: "str", "int", "float", "bool" or "json"."""
    units: str
    """Unit of the values ("-" or "" for none)."""
    description: str
    """What the column holds."""


class Counts(_Output):
    """How many cases, and what became of them."""

    cases: int
    """Rows of the summary (cases of the selected studies)."""
    complete: int
    """Cases that ran to the end."""
    failed: int
    """Cases that failed (their files, if any, hold partial results)."""
    pending: int
    """Cases not run yet."""


class SweepReport(_Output):
    """The document ``pound report DIR/ --json`` prints for a sweep folder."""

    folder: str
    """The sweep's output folder."""
    title: str
    """The sweep's title."""
    pound_version: str
    """Version of pound that ran the sweep (of its manifest, sweep.json)."""
    sweep_file: str
    """The sweep file that was run."""
    base: str
    """The base model of the sweep."""
    studies: dict[str, str]
    """Study name → description (one entry "" for a sweep of one study)."""
    selected_studies: list[str] | None
    """The studies the report is restricted to (--study), or null for all."""
    source: str
    """Where the rows come from: "case files" (sweep.json and each case's file as they stand
    now) or "summary.h5" (a summary without its manifest or case files, as last written)."""
    complete: bool
    """Whether every case of the report ran to the end."""
    counts: Counts
    """Cases complete, failed and pending."""
    columns: list[SummaryColumn]
    """Every column of the summary, in order."""
    rows: list[dict[str, Any]]
    """One object per case, keys the column names (a `pound sweep --json` line): values as in
    summary.h5, null where a case has no value."""


def sweep_summary(folder: str | Path | Sweep, studies: Sequence[str] | None = None) -> dict[str, Any]:
    """The JSON document of ``pound report DIR/ --json`` (``studies``: only those)."""
    from ..sweep.summary import counts

    sweep = select(folder if isinstance(folder, Sweep) else open_sweep(folder), studies)
    rows = sweep.rows
    n = counts(rows)
    return SweepReport(
        folder=str(sweep.folder),
        title=sweep.title,
        pound_version=str(sweep.attrs.get("pound_version", "")),
        sweep_file=str(sweep.attrs.get("sweep_file", "")),
        base=str(sweep.attrs.get("base", "")),
        studies=sweep.studies,
        selected_studies=list(studies) if studies else None,
        source=sweep.source,
        complete=n["complete"] == n["cases"],
        counts=Counts(**n),
        columns=[SummaryColumn(**c) for c in sweep.columns],
        rows=rows,
    ).model_dump(mode="json")


def sweep_schema() -> dict[str, Any]:
    """JSON Schema of :func:`sweep_summary`'s document; each row refers to the sweep-summary
    schema (``sweep-summary.schema.json``) of one summary row."""
    from ..schema import SCHEMA_BASE

    schema = SweepReport.model_json_schema(mode="serialization")
    schema["properties"]["rows"]["items"] = {"$ref": SCHEMA_BASE + "sweep-summary.schema.json"}
    return schema


def status_line(doc: dict[str, Any]) -> str | None:
    """The warning above a sweep's report when some case failed or has not run, or when the
    rows come from summary.h5 alone; else None."""
    n = doc["counts"]
    parts = []
    if not doc["complete"]:
        failed = [r for r in doc["rows"] if r["status"].startswith("failed")]
        parts.append(f"INCOMPLETE SWEEP: {n['cases']} cases: {n['complete']} complete, {n['failed']} failed, "
                     f"{n['pending']} pending (not run yet)")  # fmt: skip
        if failed:
            names = "; ".join(f"{(r['study'] + '/') if r['study'] else ''}{r['case']}: "
                              f"{r['status'].removeprefix('failed: ')}" for r in failed[:5])  # fmt: skip
            parts.append(f"FAILED: {names}{'; …' if len(failed) > 5 else ''}")
        parts.append("Their results are missing or partial; rerun the sweep to complete them")
    if doc["source"] != FROM_CASE_FILES:
        parts.append(f"Rows read from {SUMMARY} as the sweep last wrote it: the folder has no {MANIFEST} or no "
                     "cases/ to read them from")  # fmt: skip
    return ". ".join(parts) + "." if parts else None


def _cell(value: Any, scale: float = 1.0, digits: int = 4) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"{scale * value:.{digits}g}"
    return short_value(value)


def sweep_tables(doc: dict[str, Any], column: str | None = None) -> list[TableSpec]:
    """The sweep table (title, files, counts) and the cases table: parameters, impacts, peak
    force, and per building the largest peak interstorey deflections — or, with `column`
    ("left:C9"), that column's largest over the storeys — and, for buildings with yielding
    members, the largest column ductility and the largest isolator displacement."""
    n = doc["counts"]
    about = TableSpec("Sweep", ["", ""], [
        ["title", doc["title"] or "-"], ["folder", doc["folder"]], ["sweep file", doc["sweep_file"]],
        ["base model", doc["base"]],
        ["cases", f"{n['cases']}: {n['complete']} complete, {n['failed']} failed, {n['pending']} pending"],
        *[[f"study {name!r}", text or "-"] for name, text in doc["studies"].items() if name],
    ])  # fmt: skip
    params = [c["name"] for c in doc["columns"] if c["kind"] == "parameter"]
    groups = _deflection_groups(doc, column)
    headers = (["study"] if any(r["study"] for r in doc["rows"]) else []) + ["case", "status", *params,
               "impacts", "peak F_N (kN)"]  # fmt: skip
    for label, _ in groups:
        headers += [f"{label} Δx (mm)", f"{label} Δy (mm)", f"{label} Δθ (mrad)"]
    yielding = _yielding_columns(doc)
    headers += [label for label, _, _ in yielding]
    rows = []
    for r in doc["rows"]:
        row = ([r["study"]] if headers[0] == "study" else []) + [short_value(r["case"]), short_value(r["status"])]
        row += [_cell(r[p]) for p in params] + [_cell(r["impacts"]), _cell(r["peak_impact_force_N"], 1e-3, 5)]
        for _, names in groups:
            row += [_cell(_largest(r, names[k]), 1e3) for k in range(3)]
        row += [_cell(r[name], scale) for _, name, scale in yielding]
        rows.append(row)
    first = len(headers) - len(yielding) - 3 * len(groups) - 2 - len(params)
    cases = TableSpec("Cases (peak interstorey deflections: building axes)", headers, rows,
                      right=set(range(first, len(headers))))  # fmt: skip
    return [about, cases]


def _yielding_columns(doc: dict[str, Any]) -> list[tuple[str, str, float]]:
    """(header, summary column, factor) of the yielding-member columns of the summary."""
    out = []
    for c in doc["columns"]:
        name = c["name"]
        if name.startswith("max_ductility["):
            out.append((f"{name[len('max_ductility['):-1]} μ max", name, 1.0))
        elif name.startswith("peak_isolator_displacement_m["):
            out.append((f"{name[len('peak_isolator_displacement_m['):-1]} isolator |δ| (mm)", name, 1e3))
    return out


def _largest(row: dict[str, Any], names: list[str]) -> float | None:
    values = [row[n] for n in names if row.get(n) is not None]
    return max(values) if values else None


def _deflection_groups(doc: dict[str, Any], column: str | None) -> list[tuple[str, list[list[str]]]]:
    """(label, [x names, y names, θ names]) per building: its largest-peak columns, or the
    per-storey columns of `column`."""
    names = [c["name"] for c in doc["columns"] if c["kind"] == "result"]
    if column:
        sweep = Sweep(Path(doc["folder"]), {}, doc["columns"], doc["rows"])
        out = []
        for building, storeys in column_names(sweep, column).items():
            out.append((f"{building} {column.rpartition(':')[2]}", [[s[k] for s in storeys] for k in range(3)]))
        return out
    buildings = [n[len("peak_isd_x_m["):-1] for n in names if n.startswith("peak_isd_x_m[") and "/" not in n]
    return [(b, [[f"peak_isd_x_m[{b}]"], [f"peak_isd_y_m[{b}]"], [f"peak_isd_theta_rad[{b}]"]]) for b in buildings]
