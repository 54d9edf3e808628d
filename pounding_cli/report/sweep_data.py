"""Reading a sweep's output folder for a report: the summary table as rows, its columns.

The folder is what ``pound sweep`` writes (docs/sweep.md, "The output folder"). The rows are
built as :func:`pounding_cli.sweep.read_summary` builds them — the manifest ``sweep.json``
lists every case, its hash and swept values and the columns; each case's file in ``cases/``
gives its status and results — and nothing is written. ``summary.h5`` is not read: a sweep
killed with ``kill -9`` never rewrites it, so it may lack cases or say "pending" for cases
done since. Only a folder without the manifest or the case files (a summary copied alone) is
read from ``summary.h5``, and the report says so. Rows come back as the JSON rows of
``pound sweep --json`` (null for no value).
"""

from __future__ import annotations

import fnmatch
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from ..errors import InputError

SUMMARY = "summary.h5"
MANIFEST = "sweep.json"
CASES = "cases"
FROM_CASE_FILES = "case files"
FROM_SUMMARY = "summary.h5"


@dataclass
class Sweep:
    """A sweep's summary: attributes (pound_version, title, sweep_file, base, studies),
    columns (name, kind, dtype, units, description), rows, and where the rows were read:
    :data:`FROM_CASE_FILES` (the manifest and the case files) or :data:`FROM_SUMMARY`."""

    folder: Path
    attrs: dict[str, Any]
    columns: list[dict[str, str]]
    rows: list[dict[str, Any]]
    source: str = FROM_CASE_FILES

    @property
    def title(self) -> str:
        return str(self.attrs.get("title") or self.folder.name)

    @property
    def studies(self) -> dict[str, str]:
        """Study name → description ("" → "" for a sweep of one study)."""
        studies = self.attrs.get("studies", {})
        if isinstance(studies, dict):
            return studies
        try:
            return json.loads(studies)
        except json.JSONDecodeError:
            return {}

    def names(self, kind: str | None = None) -> list[str]:
        """Column names, of one kind ("case", "parameter", "result") or all."""
        return [c["name"] for c in self.columns if kind is None or c["kind"] == kind]

    def column(self, name: str) -> dict[str, str]:
        """The description of column `name`."""
        for c in self.columns:
            if c["name"] == name:
                return c
        raise KeyError(name)

    def label(self, row: dict[str, Any]) -> str:
        """"study/case", or the case alone in a sweep of one study."""
        return f"{row['study']}/{row['case']}" if row["study"] else str(row["case"])


def is_sweep_folder(path: Path) -> bool:
    """Whether `path` is a folder written by `pound sweep`."""
    return path.is_dir() and ((path / SUMMARY).exists() or (path / MANIFEST).exists())


def open_sweep(folder: str | Path) -> Sweep:
    """Read a sweep folder as its case files stand now (the module's docstring), writing
    nothing; InputError naming the folder if it is not one."""
    folder = Path(folder)
    if (folder / MANIFEST).exists() and (folder / CASES).is_dir():
        return _from_case_files(folder)
    if (folder / SUMMARY).exists():
        return _from_summary(folder)
    if (folder / MANIFEST).exists():
        raise InputError(f"it has a {MANIFEST} but no {CASES}/ folder and no {SUMMARY}: no case has run; run the "
                         "sweep into it", file=folder)  # fmt: skip
    raise InputError(f"not a sweep output folder (no {MANIFEST}); give a folder written by `pound sweep` or "
                     "result files", file=folder)  # fmt: skip


def _from_case_files(folder: Path) -> Sweep:
    """The rows of read_summary, with the manifest's attributes and columns."""
    from ..sweep.store import OutputFolder
    from ..sweep.summary import summary_rows

    out = OutputFolder(folder)
    manifest = out.read_manifest()
    try:
        columns = manifest["columns"]
        rows = summary_rows(out, manifest)
    except (KeyError, TypeError) as exc:
        raise InputError(f"{MANIFEST} is not the manifest of a pound sweep (no {exc})", file=folder) from None
    attrs = {key: manifest.get(key, "") for key in ("pound_version", "title", "sweep_file", "base")}
    attrs["studies"] = manifest.get("studies", {})
    return Sweep(folder, attrs, columns, rows, FROM_CASE_FILES)


def _from_summary(folder: Path) -> Sweep:
    """The table of summary.h5 as the sweep last wrote it."""
    import h5py

    path = folder / SUMMARY
    try:
        with h5py.File(path, "r") as f:
            attrs = {k: _plain(v) for k, v in f.attrs.items()}
            table = f["cases"][()]
            columns = json.loads(f["cases"].attrs["columns"])
    except (OSError, KeyError, json.JSONDecodeError) as exc:
        raise InputError(f"cannot read the sweep summary ({exc})", file=path) from None
    rows = [{c["name"]: _value(record[c["name"]], c["dtype"]) for c in columns} for record in table]
    return Sweep(folder, attrs, columns, rows, FROM_SUMMARY)


def _plain(value: Any) -> Any:
    if hasattr(value, "item"):
        return value.item()
    return value.decode() if isinstance(value, bytes) else value


def _value(raw: Any, dtype: str) -> Any:
    """A summary.h5 cell as the JSON row has it: None for NaN and for the −1 of no impacts."""
    value = _plain(raw)
    if dtype == "float":
        return None if not math.isfinite(value) else float(value)
    if dtype == "int":
        return None if value < 0 else int(value)
    if dtype == "bool":
        return bool(value)
    if dtype == "json":
        return json.loads(value) if value else None
    return str(value)


SHORT = 40
"""Characters a parameter value may take in a table cell or a legend."""


def short_value(value: Any, width: int = SHORT) -> str:
    """A value as a table cell or legend shows it: a table with a `name` (an inline record)
    by its name, other lists and tables as JSON without their empty entries (a record's
    unset "" and null fields), cut to `width` characters with "…". CSV and JSON keep the
    whole value."""
    if isinstance(value, dict) and isinstance(value.get("name"), str) and value["name"].strip():
        text = value["name"].strip()
    elif isinstance(value, (list, dict)):
        text = json.dumps(_without_empty(value), ensure_ascii=False)
    else:
        text = str(value)
    return text if len(text) <= width else text[: width - 1] + "…"


def _without_empty(value: Any) -> Any:
    """`value` without the entries of its tables that are "", null, [] or {} (recursively)."""
    if isinstance(value, dict):
        kept = {k: _without_empty(v) for k, v in value.items()}
        return {k: v for k, v in kept.items() if v not in ("", None, [], {})}
    if isinstance(value, list):
        return [_without_empty(v) for v in value]
    return value


def select(sweep: Sweep, studies: Sequence[str] | None = None) -> Sweep:
    """The sweep restricted to some studies (InputError for a study it does not have)."""
    if not studies:
        return sweep
    known = sorted({r["study"] for r in sweep.rows})
    unknown = [s for s in studies if s not in known]
    if unknown:
        raise InputError(f"no study {unknown[0]!r}; studies: {', '.join(repr(k) for k in known)}", file=sweep.folder,
                         field="--study")  # fmt: skip
    return Sweep(sweep.folder, sweep.attrs, sweep.columns, [r for r in sweep.rows if r["study"] in studies],
                 sweep.source)  # fmt: skip


def match_cases(sweep: Sweep, patterns: Sequence[str]) -> list[dict[str, Any]]:
    """Rows whose "study/case" or case matches one of the shell-style `patterns`, in order."""
    rows = [r for r in sweep.rows if any(fnmatch.fnmatchcase(sweep.label(r), p) or fnmatch.fnmatchcase(r["case"], p)
                                         for p in patterns)]  # fmt: skip
    if not rows:
        raise InputError(f"no case matches {', '.join(map(repr, patterns))}; cases: "
                         f"{', '.join(repr(sweep.label(r)) for r in sweep.rows[:10])}"
                         + (", …" if len(sweep.rows) > 10 else ""), file=sweep.folder, field="--case")  # fmt: skip
    return rows


def match_columns(sweep: Sweep, patterns: Sequence[str]) -> list[str]:
    """Result columns matching the shell-style `patterns` (``peak_isd_x_m[left/C9/*]``: brackets
    are literal here), in the summary's order."""
    def fits(name: str, pattern: str) -> bool:
        literal = "".join({"[": "[[]", "]": "[]]"}.get(ch, ch) for ch in pattern)
        return fnmatch.fnmatchcase(name, literal)

    names = [n for n in sweep.names("result") if any(fits(n, p) for p in patterns)]
    if not names:
        raise InputError(f"no summary column matches {', '.join(map(repr, patterns))}; columns: "
                         f"{', '.join(sweep.names('result')[:12])}, …", file=sweep.folder, field="--y")  # fmt: skip
    return names


def column_names(sweep: Sweep, column: str) -> dict[str, list[list[str]]]:
    """For `column` ("C9" or "left:C9"): building → per storey, the names of its x, y and θ
    summary columns. InputError if the sweep's summary has no such columns (``[summary]
    columns`` of the sweep file chooses them)."""
    building, _, name = column.rpartition(":")
    out: dict[str, list[list[str]]] = {}
    for c in sweep.names("result"):
        if not c.startswith("peak_isd_x_m[") or c.count("/") != 2:
            continue
        b, col, storey = c[len("peak_isd_x_m["):-1].split("/")
        if col == name and (not building or b == building):
            out.setdefault(b, []).append([c, c.replace("_x_m[", "_y_m["), c.replace("_x_m[", "_theta_rad[")])
    if not out:
        have = sorted({c[c.index("[") + 1:c.rindex("/")].replace("/", ":") for c in sweep.names("result")
                       if c.count("/") == 2})  # fmt: skip
        raise InputError(f"the sweep's summary has no per-storey columns of {column!r}; it has "
                         f"{', '.join(have) or 'none'} (the sweep file's [summary] columns choose them)",
                         file=sweep.folder, field="--column")  # fmt: skip
    return out


def numeric_parameters(sweep: Sweep) -> list[str]:
    """Parameter columns with numbers that take more than one value."""
    out = []
    for name in sweep.names("parameter"):
        values = {r[name] for r in sweep.rows if isinstance(r[name], (int, float)) and not isinstance(r[name], bool)}
        if len(values) > 1:
            out.append(name)
    return out
