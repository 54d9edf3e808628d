"""The summary table of a sweep, rebuilt from its case files: summary.h5 and summary.csv.

The rows come from the folder's manifest (sweep.json: the cases, their hashes and swept
values, the columns) and from each case's HDF5 file (status and results), never from
memory of what ran: deleting the summary loses nothing, and rerunning the sweep (or
:func:`rebuild_summary`) writes it again. Columns: :mod:`.columns`, docs/sweep.md.

    summary.h5   /cases: a table, one row per case, one field per column; its attributes
                 `units` (one per column, comma separated, as in the result files) and
                 `columns` (JSON: name, kind, dtype, units, description of each); the file's
                 attributes: pound_version, title, sweep_file, base, studies (JSON), counts
    summary.csv  the same table: a header line of column names, then one line per case;
                 numbers at full precision, empty cells where there is no value
    summary-stats.csv  with a suite: each result column's median, lognormal β and 84th
                 percentile over the records of each group of cases (sweep.statistics)
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import atomic_path, hdf5_writer, write_text
from .columns import FORCES
from .store import COMPLETE, PENDING, OutputFolder

SUMMARY_H5 = "summary.h5"
SUMMARY_CSV = "summary.csv"


def case_results(path: Path) -> dict[str, Any]:
    """The summary's result values of one case file (reading only small datasets)."""
    import h5py

    out: dict[str, Any] = {}
    with h5py.File(path, "r") as f:
        diagnostics = f["diagnostics"].attrs
        events = f["impacts/events"]
        out["impacts"] = int(diagnostics.get("impacts", events.shape[0]))
        out["peak_impact_force_N"] = float(events["peak_normal_force"].max()) if events.shape[0] else 0.0
        out["energy_balance_error"] = float(diagnostics.get("balance_error_ratio", math.nan))
        out["solver_time_s"] = float(diagnostics.get("wall_time_s", math.nan))
        out["wall_time_s"] = float(diagnostics.get("run_time_s", math.nan))
        for name, group in f["buildings"].items():
            isd = group["peaks/interstorey_deflection"][()]  # (columns, storeys, 3)
            names = [n.decode() if isinstance(n, bytes) else str(n) for n in group["columns"]["name"]]
            for k, suffix in enumerate(("x_m", "y_m", "theta_rad")):
                values = isd[:, :, k]
                out[f"peak_isd_{suffix}[{name}]"] = _nanmax(values)
                for c, column in enumerate(names):
                    for s in range(values.shape[1]):
                        out[f"peak_isd_{suffix}[{name}/{column}/{s + 1}]"] = float(values[c, s])
            out |= force_results(name, group)
            if "yielding" in group:
                kinds = [k.decode() if isinstance(k, bytes) else str(k) for k in group["yielding/members"]["kind"]]
                columns = np.array([k == "column" for k in kinds], dtype=bool)
                isolators = np.array([k == "isolator" for k in kinds], dtype=bool)
                if columns.any():
                    out[f"max_ductility[{name}]"] = _nanmax(group["yielding/ductility"][()][columns])
                    residual = group["yielding/residual_deflection"][()][columns]
                    out[f"max_residual_deflection_m[{name}]"] = _nanmax(np.hypot(residual[:, 0], residual[:, 1]))
                if isolators.any():
                    out[f"peak_isolator_displacement_m[{name}]"] = _nanmax(group["yielding/peak"][()][isolators, 2])
    return out


def force_results(name: str, group: Any) -> dict[str, float]:
    """Building `name`'s force columns (columns.FORCES) from its group of a case file; NaN in a
    file written before pound stored forces."""
    if "base_shear" not in group["peaks"]:
        return {f"{column}[{name}]": math.nan for column, _, _ in FORCES}
    base = group["peaks/base_shear"][()]  # STOREY_COMPONENTS: V_x, V_y, T, V_X, V_Y, T_O
    values = (base[0], base[1], base[2], _nanmax(group["peaks/column_shear"][()]))
    return {f"{column}[{name}]": float(v) for (column, _, _), v in zip(FORCES, values)}


def _nanmax(values: np.ndarray) -> float:
    finite = values[~np.isnan(values)]
    return float(finite.max()) if finite.size else math.nan


def summary_rows(folder: OutputFolder, manifest: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per case of the manifest, from the folder's case files (JSON-ready values:
    null where there is no value)."""
    names = [c["name"] for c in manifest["columns"]]
    cache: dict[str, dict[str, Any]] = {}
    rows = []
    for case in manifest["cases"]:
        if case["hash"] not in cache:
            cache[case["hash"]] = case_row_values(folder, case["hash"], case["input_sha256"])
        rows.append(make_row(case, cache[case["hash"]], names))
    return rows


def make_row(case: dict[str, Any], found: dict[str, Any], names: list[str]) -> dict[str, Any]:
    """A summary row: the manifest's `case` entry, the values `found` in its file
    (:func:`case_row_values`), in the order of the column `names`."""
    row = {"study": case["study"], "case": case["case"], "hash": case["hash"], "status": found["status"],
           "file": f"cases/{case['hash']}.h5", **case["parameters"]}  # fmt: skip
    return {name: _json_ready(row.get(name, found.get(name))) for name in names}


def case_row_values(folder: OutputFolder, short_hash: str, input_sha256: str) -> dict[str, Any]:
    """Status and result values of one case, from its file; only the status without one."""
    state = folder.state(short_hash, input_sha256)
    values: dict[str, Any] = {"status": state.status}
    if state.has_results:
        try:
            values.update(case_results(folder.case_file(short_hash)))
        except (OSError, KeyError) as exc:
            values["status"] = f"failed: the case file cannot be read ({exc})"
    return values


def _json_ready(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, np.generic):
        return _json_ready(value.item())
    return value


def write_summary(folder: OutputFolder, manifest: dict[str, Any], rows: list[dict[str, Any]]) -> tuple[Path, Path]:
    """Write summary.h5 and summary.csv atomically; returns their paths."""
    h5 = folder.root / SUMMARY_H5
    with atomic_path(h5) as tmp:
        _write_h5(tmp, manifest, rows)
    if manifest.get("sweep", {}).get("suite"):  # the statistics over the suite's records
        from .statistics import write_statistics

        write_statistics(folder.root, manifest["columns"], rows)
    return h5, write_text(folder.root / SUMMARY_CSV, csv_text(manifest["columns"], rows))


def counts(rows: list[dict[str, Any]]) -> dict[str, int]:
    """Cases complete, failed and pending."""
    complete = sum(r["status"] == COMPLETE for r in rows)
    pending = sum(r["status"] == PENDING for r in rows)
    return {"cases": len(rows), "complete": complete, "failed": len(rows) - complete - pending, "pending": pending}


def _write_h5(path: Path, manifest: dict[str, Any], rows: list[dict[str, Any]]) -> None:
    from .. import __version__

    columns = manifest["columns"]
    dtype = np.dtype([(c["name"], _h5_type(c["dtype"])) for c in columns])
    table = np.zeros(len(rows), dtype=dtype)
    for c in columns:
        table[c["name"]] = [_h5_value(row[c["name"]], c["dtype"]) for row in rows]
    with hdf5_writer(path, track_order=True) as f:
        f.attrs["pound_version"] = __version__
        f.attrs["title"] = manifest.get("title", "")
        f.attrs["sweep_file"] = manifest.get("sweep_file", "")
        f.attrs["base"] = manifest.get("base", "")
        f.attrs["studies"] = json.dumps(manifest.get("studies", {}), ensure_ascii=False)
        for key, n in counts(rows).items():
            f.attrs[key] = n
        ds = f.create_dataset("cases", data=table, track_times=False)
        ds.attrs["units"] = ", ".join(c["units"] or "-" for c in columns)
        ds.attrs["columns"] = json.dumps(columns, ensure_ascii=False)
        ds.attrs["description"] = ("one row per case of the sweep; NaN (floats) and -1 (impacts) where a case "
                                   "has no results; parameter values that are lists or tables are JSON text")  # fmt: skip


def _h5_type(kind: str) -> Any:
    import h5py

    return {"float": np.float64, "int": np.int64, "bool": np.bool_}.get(kind, h5py.string_dtype())


def _h5_value(value: Any, kind: str) -> Any:
    if kind == "float":
        return math.nan if value is None else float(value)
    if kind == "int":
        return -1 if value is None else int(value)
    if kind == "bool":
        return bool(value)
    if kind == "str":
        return "" if value is None else str(value)
    return json.dumps(value, ensure_ascii=False)


def csv_text(columns: list[dict[str, Any]], rows: list[dict[str, Any]]) -> str:
    """The summary as CSV text (header line, one line per case)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([c["name"] for c in columns])
    for row in rows:
        writer.writerow([_csv_value(row[c["name"]], c["dtype"]) for c in columns])
    return buffer.getvalue()


def _csv_value(value: Any, kind: str) -> str:
    if value is None:
        return ""
    if kind == "bool":
        return "true" if value else "false"
    if kind == "json" or isinstance(value, (list, dict)):
        return json.dumps(value, ensure_ascii=False)
    return repr(value) if isinstance(value, float) else str(value)


def rebuild_summary(folder: str | Path) -> list[dict[str, Any]]:
    """Rebuild summary.h5 and summary.csv of a sweep folder from its manifest and case
    files; returns the rows."""
    out = OutputFolder(folder)
    manifest = out.read_manifest()
    rows = summary_rows(out, manifest)
    write_summary(out, manifest, rows)
    return rows


def read_summary(folder: str | Path) -> list[dict[str, Any]]:
    """The rows of a sweep folder as its case files stand now, without writing anything."""
    out = OutputFolder(folder)
    return summary_rows(out, out.read_manifest())
