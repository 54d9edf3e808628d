"""Checking every case of a sweep before anything runs, and what each case is.

Two passes, so that a mistake costs seconds rather than a failed night:

1. here, for every case: write its values into the base model's document (a path that
   does not fit is an error naming the sweep-file field) and validate it as a model file;
2. in the worker processes, for every distinct case document: everything ``pound validate``
   does besides (assemble the buildings, read and process the record, choose the time
   grid), which also gives the case's ``input_sha256``: the hash of its resolved model,
   its record files and pound's version, whose first 12 hex digits name its file.

Any problem in either pass raises one :class:`~pounding_cli.errors.InputError` listing
every problem, each naming the sweep file, the case and the field.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from .. import __version__
from ..errors import InputError, PoundError
from ..model import LoadedModel, read_document, validate_model
from ..model.sweep import LoadedSweep, load_sweep, parse_path
from .columns import (
    CASE_COLUMNS,
    RESULT_COLUMNS,
    TIME_COLUMNS,
    Column,
    building_columns,
    parameter_column,
    storey_columns,
    yielding_columns,
)
from .document import CaseDocument, CaseProblem, case_document, describe_problem, gather
from .expand import CaseSpec, expand
from .paths import PathError, select
from .pool import Outcome, Task
from .suites import with_suite
from .tasks import check_case

HASH_DIGITS = 12
"""Hex digits of input_sha256 that name a case's file."""


@dataclass
class PlannedCase:
    """One case, checked: its model document, resolved values and hash."""

    spec: CaseSpec
    document: dict[str, Any]
    values: dict[str, Any]  # swept path → the value the case's model resolved to
    storeys: dict[str, int]  # building → number of storeys
    input_sha256: str = ""
    yielding: dict[str, tuple[bool, bool]] = field(default_factory=dict)  # building → (inelastic columns, isolated)

    @property
    def hash(self) -> str:
        return self.input_sha256[:HASH_DIGITS]


@dataclass
class Plan:
    """A sweep's cases, checked, with what the summary reports about them."""

    sweep: LoadedSweep
    cases: list[PlannedCase]
    parameter_paths: list[str]
    buildings: dict[str, int] = field(default_factory=dict)  # building → most storeys over the cases
    yielding: dict[str, tuple[bool, bool]] = field(default_factory=dict)  # building → (inelastic columns, isolated) in some case
    warnings: list[str] = field(default_factory=list)  # the cases' plausibility warnings, each once (gather)

    @property
    def base(self) -> Path:
        return self.sweep.base

    def runs(self) -> dict[str, PlannedCase]:
        """One case per distinct hash (the first of those sharing inputs)."""
        out: dict[str, PlannedCase] = {}
        for case in self.cases:
            out.setdefault(case.hash, case)
        return out

    def columns(self) -> list[Column]:
        """The summary's columns (docs/sweep.md, "Summary")."""
        params = [parameter_column(p, [c.values.get(p) for c in self.cases]) for p in self.parameter_paths]
        named = self.sweep.sweep.summary.columns
        per_building = [c for b in self.buildings
                        for c in building_columns(b) + yielding_columns(b, *self.yielding.get(b, (False, False)))]  # fmt: skip
        per_storey = [c for b, cols in named.items() for col in cols for c in storey_columns(b, col, self.buildings.get(b, 0))]
        return CASE_COLUMNS + params + RESULT_COLUMNS + per_building + per_storey + TIME_COLUMNS

    def manifest(self) -> dict[str, Any]:
        """The sweep.json document: enough to rebuild the summary without the sweep file."""
        s = self.sweep.sweep
        return {
            "pound_version": __version__,
            "title": s.title,
            "sweep_file": str(self.sweep.source),
            "base": str(self.base),
            "studies": {name: study.description for name, study in s.all_studies().items()},
            "sweep": json.loads(s.model_dump_json()),
            "columns": [c.as_dict() for c in self.columns()],
            "cases": [
                {"study": c.spec.study, "case": c.spec.name, "hash": c.hash, "input_sha256": c.input_sha256,
                 "parameters": c.values}  # fmt: skip
                for c in self.cases
            ],
        }


def plan_sweep(
    sweep: str | Path | LoadedSweep,
    run_tasks: Callable[[list[Task]], Any] | None = None,
    on_progress: Callable[[int, int], None] | None = None,
    strict: bool = False,
) -> Plan:
    """Expand and check every case (module docstring). `run_tasks` runs the second pass's
    tasks (an executor's ``run``; in this process if None); `on_progress(done, total)`.
    The cases' plausibility warnings are gathered in `Plan.warnings`; with `strict` they are
    problems, refused as the others are."""
    loaded = sweep if isinstance(sweep, LoadedSweep) else load_sweep(sweep)
    specs = with_suite(loaded, expand(loaded.sweep))
    paths = list(dict.fromkeys(p for spec in specs for p in spec.parameters))
    documents, cases = _documents(loaded, specs, paths)
    warnings = _check(loaded, documents, cases, run_tasks, on_progress, strict)
    buildings: dict[str, int] = {}
    yielding: dict[str, tuple[bool, bool]] = {}
    for case in cases:
        for name, n in case.storeys.items():
            buildings[name] = max(buildings.get(name, 0), n)
        for name, (columns, isolated) in case.yielding.items():
            before = yielding.get(name, (False, False))
            yielding[name] = (before[0] or columns, before[1] or isolated)
    return Plan(loaded, cases, paths, buildings, yielding, warnings)


def _documents(loaded: LoadedSweep, specs: list[CaseSpec], paths: list[str]) -> tuple[list[CaseDocument], list[PlannedCase]]:
    """Pass 1: every case's document, validated as a model file (the validated model is
    kept only as long as it takes to read the case's values from it)."""
    try:
        base = read_document(loaded.base)
    except InputError as exc:
        raise InputError(str(exc), file=loaded.source, field="base") from None
    documents, cases, problems = [], [], []
    for spec in specs:
        try:
            doc = case_document(base, spec, loaded.source)
            model = validate_model(doc.document, loaded.base)
        except CaseProblem as exc:
            problems += exc.problems
            if exc.case is not None:  # the values that did fit may hold mistakes of their own
                try:
                    validate_model(exc.case.document, loaded.base)
                except InputError as invalid:
                    problems += describe_problem(exc.case, str(invalid), loaded.base, loaded.source)
            continue
        except InputError as exc:
            problems += describe_problem(doc, str(exc), loaded.base, loaded.source)
            continue
        documents.append(doc)
        cases.append(_case(doc, model, paths))
    if problems:
        raise InputError(gather(problems))
    return documents, cases


def _case(doc: CaseDocument, model: LoadedModel, paths: list[str]) -> PlannedCase:
    dump = model.model.model_dump(mode="json")
    values = {path: _resolved(dump, path, doc.spec.parameters.get(path)) for path in paths}
    # an isolated building's storey 1 is its isolation storey, below the floors of the model
    storeys = {b.name: len(b.storeys()) + (b.isolation is not None) for b in model.model.buildings}
    yielding = {
        b.name: (any(c.hysteresis is not None for floor in b.storeys() for c in floor.all_columns()),
                 b.isolation is not None)
        for b in model.model.buildings
    }  # fmt: skip
    return PlannedCase(doc.spec, doc.document, values, storeys, yielding=yielding)


def _resolved(dump: dict[str, Any], path: str, assigned: Any) -> Any:
    """The value at `path` in the validated model (one value if every place agrees)."""
    try:
        found = [v for _, v in select(dump, parse_path(path))]
    except PathError:
        return assigned
    return found[0] if all(v == found[0] for v in found) else found


def _check(
    loaded: LoadedSweep,
    documents: list[CaseDocument],
    cases: list[PlannedCase],
    run_tasks: Callable[[list[Task]], Any] | None,
    on_progress: Callable[[int, int], None] | None,
    strict: bool = False,
) -> list[str]:
    """Pass 2: prepare each distinct document in the workers; fill in the hashes. Returns
    the cases' plausibility warnings, gathered (with `strict`: problems)."""
    columns = loaded.sweep.summary.columns
    distinct: dict[str, list[int]] = {}
    for i, case in enumerate(cases):
        distinct.setdefault(json.dumps(case.document, sort_keys=True), []).append(i)
    tasks: list[Task] = [(key, check_case, (cases[ix[0]].document, str(loaded.base), columns))
                         for key, ix in distinct.items()]  # fmt: skip
    outcomes = run_tasks(tasks) if run_tasks is not None else (_here(t) for t in tasks)
    problems, warnings, strict_found = [], [], False
    for done, (key, ok, value) in enumerate(outcomes, start=1):
        first = documents[distinct[key][0]]
        if not ok:
            value = {"problem": f"{loaded.base}: internal error while checking the case: {value}"}
        if "problem" in value:
            problems += describe_problem(first, value["problem"], loaded.base, loaded.source)
        else:
            for i in distinct[key]:
                cases[i].input_sha256 = value["input_sha256"]
        if value.get("warnings"):
            lines = describe_problem(first, "\n".join(value["warnings"]), loaded.base, loaded.source)
            (problems if strict else warnings).extend(lines * len(distinct[key]))
            strict_found = strict
        if "columns_problem" in value:
            problems.append((value["columns_problem"], f"{loaded.source}: summary.columns: case "
                             f"{first.spec.label!r}: {value['columns_problem']}"))  # fmt: skip
        if on_progress is not None:
            on_progress(done, len(tasks))
    if problems:
        raise InputError(gather(problems) + (" (--strict: plausibility warnings are errors)" if strict_found else ""))
    _refuse_collisions(cases)
    return gather(warnings).splitlines() if warnings else []


def _here(task: Task) -> Outcome:
    key, function, args = task
    return key, True, function(*args)


def _refuse_collisions(cases: list[PlannedCase]) -> None:
    seen: dict[str, str] = {}
    for case in cases:
        other = seen.setdefault(case.hash, case.input_sha256)
        if other != case.input_sha256:  # 1 in 10^14 per pair: say so rather than mix files
            raise PoundError(f"two cases' input hashes share their first {HASH_DIGITS} digits ({case.hash}); "
                             "please report this")  # fmt: skip
