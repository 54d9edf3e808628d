"""A sweep's `suite`: every case of the sweep crossed with every case of a record suite.

Each case (study, name) becomes one case per suite case (record × orientation, suites.resolve)
named "<name> @ record=<label>", whose assignments are the case's own followed by

    excitation.record       = the record's definition (component files absolute)   (set)
    excitation.record.name  = the suite case's label, e.g. "RSN953-LT"               (parameter)
    excitation.scale        = the base model's scale × the record's factor           (parameter)

so the summary has the record and its scale as columns, and the statistics over the records
(sweep.statistics) group the cases that differ only by their record.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..model.sweep import LoadedSweep
from .expand import PARAMETER, SET, Assignment, CaseSpec

RECORD = "excitation.record.name"
"""The summary column naming each case's suite record."""
SEPARATOR = " @ record="


def with_suite(loaded: LoadedSweep, specs: list[CaseSpec]) -> list[CaseSpec]:
    """`specs` crossed with the sweep's suite (unchanged without one)."""
    name = loaded.sweep.suite
    if name is None:
        return specs
    suite = _resolve(loaded, name)
    from ..model import read_document

    base_scale = float(read_document(loaded.base).get("excitation", {}).get("scale", 1.0))
    out = []
    for spec in specs:
        for c in suite.cases:
            extra = (Assignment("excitation.record", {**c.definition, "name": c.label}, SET, "suite"),
                     Assignment(RECORD, c.label, PARAMETER, "suite"),
                     Assignment("excitation.scale", base_scale * c.factor, PARAMETER, "suite"))  # fmt: skip
            out.append(CaseSpec(spec.study, spec.name + SEPARATOR + c.label if spec.name else "record=" + c.label,
                                spec.assignments + extra))  # fmt: skip
    return out


def _resolve(loaded: LoadedSweep, name: str):  # type: ignore[no-untyped-def]
    from ..api import prepare
    from ..model import load_model
    from ..model.suite import BUILTIN
    from ..suites.resolve import resolve_suite

    try:
        scene = prepare(load_model(loaded.base))
    except InputError as exc:
        raise InputError(str(exc), file=loaded.source, field="base") from None
    target = name if name in BUILTIN else str(Path(loaded.source).parent / name)
    try:
        return resolve_suite(target, scene)
    except InputError as exc:
        raise InputError(str(exc), file=loaded.source, field="suite") from None


def group_name(case: str) -> str:
    """The case's name without its suite record: the cases of one group differ only by it."""
    return case.split(SEPARATOR)[0] if SEPARATOR in case else ("" if case.startswith("record=") else case)
