"""A suite made concrete for one model: every case (record × orientation), its record
definition (a table with absolute component paths) and its scale factor.

    suite = resolve_suite("far-field", scene)
    suite.cases[0].label, suite.cases[0].factor

A built-in name ("far-field", "near-field") is the FEMA P695 set normalised by P695
(scaling.method "p695"); any other name is the path of a suite file (model/suite.py).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..model.record import Record, load_record
from ..model.suite import BUILTIN, Scaling, SuiteFile, load_suite_file
from ..records.combine import RecordOrigin, record_motion
from .scaling import check_period, method_factor

ORIENTATIONS = {"as-given": ("LT",), "both": ("LT", "TL")}
"""The orientations of each record: LT as given, TL with the components swapped."""


@dataclass(frozen=True)
class SuiteCase:
    """One case of a suite: a record in one orientation, and the factor on the model's scale."""

    label: str  # "<record>-LT" or "<record>-TL"
    record: str  # the suite record's name
    orientation: str  # "LT" or "TL"
    definition: dict[str, Any]  # the record definition, component files absolute
    factor: float  # s_i·F·m_i (suites.scaling), dimensionless


@dataclass(frozen=True)
class Suite:
    """A suite resolved for a model."""

    name: str  # the built-in name, or the suite file's path
    source: Path | None  # the suite file, None for a built-in
    file: SuiteFile
    period: float | None  # s: the period of Sa scaling, resolved
    cases: list[SuiteCase]

    def describe(self) -> dict[str, Any]:
        """What the results record about the suite (JSON-ready)."""
        return {"suite": self.name, "title": self.file.title, "orientations": self.file.orientations,
                "scaling": json.loads(self.file.scaling.model_dump_json()), "period_s": self.period,
                "records": len({c.record for c in self.cases}), "cases": len(self.cases)}  # fmt: skip


def resolve_suite(spec: str | Path, scene: Any, records_folder: Path | None = None) -> Suite:
    """The suite named by `spec` for the prepared `scene` (its buildings give T1); built-in
    records are written under `records_folder` (default: pound's cache, suites.builtin)."""
    if str(spec) in BUILTIN:
        file = SuiteFile(builtin=str(spec), scaling=Scaling(method="p695"))
        return _resolve(str(spec), None, file, scene, records_folder)
    path = Path(spec)
    if not path.exists() and not path.suffix:
        raise InputError(f"no built-in suite {str(spec)!r} and no such file: the built-in suites are "
                         f"{', '.join(BUILTIN)}; otherwise give the path of a suite file (.toml or .json)", field="--suite")  # fmt: skip
    return _resolve(str(path), path, load_suite_file(path), scene, records_folder)


def _resolve(name: str, source: Path | None, file: SuiteFile, scene: Any, records_folder: Path | None) -> Suite:
    where = source if source is not None else "--suite " + name
    entries = _entries(file, source, records_folder)
    period = _period(file.scaling, scene, where)
    cases = []
    for entry_name, record, origin, scale, normalisation, at in entries:
        scaling = file.scaling
        if scaling.method in ("pga", "sa"):  # from the record's motion; the others need not read it
            motion = record_motion(record, origin)
            if period is not None:
                check_period(period, motion.dt, "scaling.period", where)
            m = method_factor(scaling.method, motion.acceleration, motion.dt, period=period,
                              target=scaling.target_pga if scaling.method == "pga" else scaling.target_sa)  # fmt: skip
        else:
            _check_files(record, origin)
            m = method_factor(scaling.method, {}, 0.0, normalisation=normalisation)
        definition = _absolute(record, origin)
        for orientation in ORIENTATIONS[file.orientations]:
            cases.append(SuiteCase(f"{entry_name}-{orientation}", entry_name, orientation,
                                   _oriented(definition, orientation), scale * scaling.factor * m))  # fmt: skip
    return Suite(name, source, file, period, cases)


def _entries(file: SuiteFile, source: Path | None, records_folder: Path | None) -> list[tuple[Any, ...]]:
    """(name, Record, RecordOrigin, scale, normalisation, field) of every record."""
    if file.builtin is not None:
        from .builtin import builtin_records

        out = []
        for r in builtin_records(file.builtin, records_folder):
            origin = RecordOrigin(Path(r.definition["L"]["file"]).parent / f"{r.name}.record", "")
            out.append((r.name, Record.model_validate(r.definition), origin, 1.0, r.normalisation, r.name))
        return out
    assert source is not None
    out = []
    for i, entry in enumerate(file.records):
        at = f"records[{i}].record"
        if isinstance(entry.record, Record):
            origin = RecordOrigin(source, at + ".", base=source.parent.resolve())
            out.append((entry.name, entry.record, origin, entry.scale, None, at))
            continue
        path = source.parent / entry.record
        if not path.is_file():
            raise InputError(f"no record definition file {str(path)!r} (paths are relative to the suite file)",
                             file=source, field=at)  # fmt: skip
        try:
            record = load_record(path)
        except InputError as exc:
            raise InputError(str(exc), file=source, field=at) from None
        out.append((entry.name, record, RecordOrigin(path, "", (source, at)), entry.scale, None, at))
    return out


def _period(scaling: Scaling, scene: Any, where: object) -> float | None:
    """The period of Sa scaling, s: given, or T1 of the named building."""
    if scaling.method != "sa":
        return None
    if isinstance(scaling.period, float | int):
        return float(scaling.period)
    by_name = {b.name: b for b in scene.system.buildings}
    if scaling.period not in by_name:
        raise InputError(f"no building {scaling.period!r} in the model {scene.loaded.source}; its buildings: "
                         f"{', '.join(by_name)} (or give the period in s)", file=where, field="scaling.period")  # fmt: skip
    return float(by_name[scaling.period].modes.periods[0])


def _check_files(record: Record, origin: RecordOrigin) -> None:
    """InputError naming the field of a component file that does not exist (before any run)."""
    for name, component in record.components().items():
        if not (origin.folder / component.file).is_file():
            raise origin.error(f"{name}.file", f"no such file {str(origin.folder / component.file)!r}")


def _absolute(record: Record, origin: RecordOrigin) -> dict[str, Any]:
    """The record definition as a table whose component files are absolute paths."""
    out = record.model_dump(mode="json", exclude_defaults=True)
    for name in ("L", "T"):
        if name in out:
            out[name]["file"] = str((origin.folder / out[name]["file"]).resolve())
    return out


def _oriented(definition: dict[str, Any], orientation: str) -> dict[str, Any]:
    """The definition with L and T exchanged for "TL" (each azimuth stays with its name)."""
    if orientation == "LT" or "L" not in definition or "T" not in definition:
        return definition
    out = json.loads(json.dumps(definition))
    out["L"], out["T"] = definition["T"].copy(), definition["L"].copy()
    for name in ("L", "T"):
        out[name].pop("azimuth", None)
        if "azimuth" in definition[name]:
            out[name]["azimuth"] = definition[name]["azimuth"]
    return out
