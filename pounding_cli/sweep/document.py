"""Each case's model document: the base model with the case's values written in, and the
messages that name the case and the sweep-file field behind a problem.

A problem found in a case's model (by validation, assembly or the record) is reported as

    sweep.toml: case "6.1/case 2": paper_kobe.toml: buildings[0].floors[0].eccentricity: … [from cases["case 2"]["buildings.left.floors[*].eccentricity"] = [0, "a"]]

naming the sweep file, the case, the model file and field as ``pound validate`` would, and
the sweep-file field whose value was written there (when one was).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .expand import CASE, PARAMETER, Assignment, CaseSpec, show
from .paths import Location, PathError, assign, location_text, overlaps


@dataclass
class CaseDocument:
    """A case's model document and where each of its assignments wrote."""

    spec: CaseSpec
    document: dict[str, Any]
    written: list[tuple[Assignment, list[Location]]] = field(default_factory=list)

    def origin_of(self, model_field: str) -> Assignment | None:
        """The last assignment that wrote at, inside or around `model_field` (a field path as
        validation errors print it, e.g. 'buildings[0].floors[0].eccentricity[1]')."""
        for assignment, locations in reversed(self.written):
            for loc in locations:
                text = location_text(loc)
                if _within(model_field, text) or _within(text, model_field):
                    return assignment
        return None


class CaseProblem(Exception):
    """A case cannot be built; `key` groups the same problem met in many cases. `problems`
    holds every (key, text) found in the case, `case` the document with the assignments that
    did fit written in (None when the case's values conflict), so that it can still be
    validated for problems of its other values."""

    def __init__(self, key: str, text: str, problems: list[tuple[str, str]] | None = None,
                 case: CaseDocument | None = None):  # fmt: skip
        super().__init__(text)
        self.key = key
        self.text = text
        self.problems = problems or [(key, text)]
        self.case = case


def case_document(base: dict[str, Any], spec: CaseSpec, sweep_file: Path) -> CaseDocument:
    """The base document with the case's assignments applied in order; raises CaseProblem
    for a path that does not fit (naming every such path of the case, each once), or a named
    case and a parameter setting one field."""
    case = CaseDocument(spec, copy.deepcopy(base))
    problems = []
    for assignment in spec.assignments:
        try:
            locations = assign(case.document, assignment.steps, assignment.value)
        except PathError as exc:
            problems.append((f"{assignment.origin}: {exc}",
                             f"{sweep_file}: {assignment.origin}: case {spec.label!r}: {exc}"))  # fmt: skip
            continue
        case.written.append((assignment, locations))
    if problems:
        raise CaseProblem(*problems[0], problems=problems, case=case)
    _check_conflicts(case, sweep_file)
    return case


def _check_conflicts(case: CaseDocument, sweep_file: Path) -> None:
    named = [(a, locs) for a, locs in case.written if a.layer == CASE]
    swept = [(a, locs) for a, locs in case.written if a.layer == PARAMETER]
    for a, a_locs in named:
        for b, b_locs in swept:
            hit = next(((x, y) for x in a_locs for y in b_locs if overlaps(x, y)), None)
            if hit is not None:
                text = (f"{a.origin}: case {case.spec.label!r}: sets {location_text(hit[0])}, and so does "
                        f"{b.origin} ({location_text(hit[1])}); a named case and a parameter may not set "
                        "the same field")  # fmt: skip
                raise CaseProblem(f"{a.origin}|{b.origin}", f"{sweep_file}: {text}")


def describe_problem(case: CaseDocument, message: str, base: Path, sweep_file: Path) -> list[tuple[str, str]]:
    """(grouping key, line) for each line of a model's error message about this case."""
    out = []
    for line in message.splitlines():
        model_field = _field_of(line, base)
        origin = case.origin_of(model_field) if model_field else None
        text = line
        if origin is not None:
            text += f" [from {origin.origin} = {show(origin.value)}]"
        out.append((f"{origin.origin if origin else ''}|{line}", f"{sweep_file}: case {case.spec.label!r}: {text}"))
    return out


def _field_of(line: str, base: Path) -> str:
    """The model field a 'file: field: message' line names ('' if none)."""
    prefix = f"{base}: "
    if not line.startswith(prefix):
        return ""
    rest = line[len(prefix):]
    return rest.split(": ", 1)[0] if ": " in rest else ""


def _within(inner: str, outer: str) -> bool:
    """'a[0].b.c' lies within 'a[0].b'; 'a[0].bc' does not."""
    return inner == outer or (inner.startswith(outer) and inner[len(outer)] in ".[")


def gather(problems: list[tuple[str, str]], limit: int = 20) -> str:
    """One message from many problems: each distinct one once (with how many more cases it
    concerns), at most `limit` of them."""
    first: dict[str, str] = {}
    more: dict[str, int] = {}
    for key, text in problems:
        if key in first:
            more[key] += 1
        else:
            first[key], more[key] = text, 0
    lines = [text + (f" (and {more[key]} more case{'s' if more[key] > 1 else ''})" if more[key] else "")
             for key, text in first.items()]  # fmt: skip
    if len(lines) > limit:
        lines = lines[:limit] + [f"… and {len(lines) - limit} more problems"]
    return "\n".join(lines)
