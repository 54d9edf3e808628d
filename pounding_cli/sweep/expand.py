"""A sweep file expanded into its cases: which values each case gives to which paths.

For each study, in the order the file lists them: its named cases (or one unnamed case)
× its parameter combinations (``grid``: every combination, the first parameter varying
slowest; ``zip``: the i-th values together; no parameters: one combination). A case's
assignments are applied to the base model's document in this order, later ones winning
where they overlap: the sweep's ``set``, the study's ``set``, the named case's table, the
parameter values. A named case and a parameter that set the same field are an error
(:func:`pounding_cli.sweep.document.case_document` checks it), the layers of ``set`` are not.
"""

from __future__ import annotations

import itertools
import json
from dataclasses import dataclass
from typing import Any

from ..model.sweep import Step, Study, SweepFile, parse_path, values_of

SET, CASE, PARAMETER = "set", "case", "parameter"


@dataclass(frozen=True)
class Assignment:
    """One value given to one path, and where in the sweep file it comes from."""

    path: str  # as written in the sweep file
    value: Any
    layer: str  # SET, CASE or PARAMETER
    origin: str  # the sweep-file field, e.g. 'studies["6.1"].cases["case 2"]["excitation.angle"]'

    @property
    def steps(self) -> tuple[Step, ...]:
        return parse_path(self.path)

    @property
    def swept(self) -> bool:
        """A parameter or a named case's value (a summary column), not a `set`."""
        return self.layer != SET


@dataclass(frozen=True)
class CaseSpec:
    """One case of the sweep before it meets the base model."""

    study: str  # "" for a sweep written at the top level
    name: str  # within the study: the named case, the parameter values, or both
    assignments: tuple[Assignment, ...]  # in the order they are applied

    @property
    def label(self) -> str:
        """The case's full name, "study/name" (or "name" without studies)."""
        return f"{self.study}/{self.name}" if self.study else self.name

    @property
    def parameters(self) -> dict[str, Any]:
        """Path → value of what this case sweeps (parameters and named-case entries)."""
        return {a.path: a.value for a in self.assignments if a.swept}


def expand(sweep: SweepFile) -> list[CaseSpec]:
    """Every case of the sweep, study by study, in file order."""
    top = [Assignment(p, v, SET, f"set[{_q(p)}]") for p, v in sweep.set.items()]
    out = []
    for study_name, study in sweep.all_studies().items():
        prefix = f"studies[{_q(study_name)}]." if study_name else ""
        shared = top + [Assignment(p, v, SET, f"{prefix}set[{_q(p)}]") for p, v in study.set.items()]
        named = _named_cases(study, prefix)
        for (case_name, case_assignments), combo in itertools.product(named, _combinations(study, prefix)):
            name = " @ ".join(x for x in (case_name, ", ".join(f"{a.path}={show(a.value)}" for a in combo)) if x)
            out.append(CaseSpec(study_name, name, tuple(shared + case_assignments + list(combo))))
    return out


def _named_cases(study: Study, prefix: str) -> list[tuple[str, list[Assignment]]]:
    if not study.cases:
        return [("", [])]
    return [
        (name, [Assignment(p, v, CASE, f"{prefix}cases[{_q(name)}][{_q(p)}]") for p, v in table.items()])
        for name, table in study.cases.items()
    ]


def _combinations(study: Study, prefix: str) -> list[tuple[Assignment, ...]]:
    columns = [
        [Assignment(path, v, PARAMETER, f"{prefix}parameters[{_q(path)}]") for v in values_of(spec)]
        for path, spec in study.parameters.items()
    ]
    if not columns:
        return [()]
    return list(itertools.product(*columns) if study.mode == "grid" else zip(*columns))


def show(value: Any) -> str:
    """A value as it appears in a case name: strings bare, everything else as compact JSON."""
    return value if isinstance(value, str) else json.dumps(value, separators=(", ", ": "), ensure_ascii=False)


def _q(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)
