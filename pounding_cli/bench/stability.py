"""`pound bench --stability`: push the solver and check it never returns garbage silently.

Every case either completes with its energy balance closed (< 1 % of the input), or is
refused before it starts (exit 2, with what to change), or stops as failed (exit 1, partial
results marked) — the report says which, and the test suite checks it (test_stability.py).
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from ..errors import InputError
from ..model import read_document, validate_model
from .run import scene_files

BALANCE_OK = 0.01


@dataclass(frozen=True)
class Case:
    name: str
    edit: Callable[[dict[str, Any]], dict[str, Any]]
    base: str = "paper_pounding"


@dataclass(frozen=True)
class Outcome:
    case: str
    result: str  # "complete", "refused: …" or "failed: …"
    steps: int
    wall_time: float  # s, whole run
    energy_balance: float
    impacts: int

    @property
    def acceptable(self) -> bool:
        """Completed with a closed balance, or refused/failed with a reason: never garbage."""
        if self.result == "complete":
            return self.energy_balance < BALANCE_OK
        return self.result.startswith(("refused: ", "failed: "))


def _set(path: str, value: Any) -> Callable[[dict[str, Any]], dict[str, Any]]:
    def edit(doc: dict[str, Any]) -> dict[str, Any]:
        node = doc
        keys = path.split(".")
        for key in keys[:-1]:
            node = node.setdefault(key, {})
        node[keys[-1]] = value
        return doc

    return edit


def _both(*edits):
    def edit(doc):
        for e in edits:
            doc = e(doc)
        return doc

    return edit


def _tall(storeys: int):
    def edit(doc):
        doc["buildings"][0]["floors"][0]["repeat"] = storeys
        doc["buildings"][0]["floors"][0]["column_grid"]["section"] = [0.9, 0.9]
        return doc

    return edit


def _row(n: int):
    def edit(doc):
        proto = doc["buildings"][0]
        doc["buildings"] = []
        for i in range(n):
            b = copy.deepcopy(proto)
            b["name"] = f"b{i + 1}"
            b["origin"] = [i * 8.03, 0.0]
            width = (0.35, 0.5, 0.3, 0.45)[i % 4]  # unlike neighbours, so that they pound
            b["floors"][0]["column_grid"]["section"] = [width, width]
            doc["buildings"].append(b)
        return doc

    return edit


def _gap(x: float, turn: float = 0.0):
    def edit(doc):
        doc["buildings"][1]["origin"] = [8.0 + x, 0.0]
        doc["buildings"][1]["rotation"] = turn
        return doc

    return edit


CASES = [
    *(Case(f"CDM at {f:g} × the stability limit", _both(_set("analysis.integrator", "cdm"),
                                                        _set("analysis.dt", f * 0.01219)), "linear")
      for f in (0.1, 0.5, 0.9, 1.0, 1.5)),  # fmt: skip
    *(Case(f"k_N = {k:.0e} N/m²", _set("contact.k_normal", k)) for k in (1e7, 1e9, 1e11, 1e12)),
    Case("Δt = 1e-4 s with contact (above the contact estimate)", _set("analysis.dt", 1e-4)),
    Case("PGA 3 g", _set("excitation.scale", 3.0 / 0.526)),
    Case("50-storey building", _tall(50)),
    Case("10 buildings in a row", _row(10), "row_of_5"),
    Case("200 s (record then free vibration)", _set("analysis.duration", 200.0)),
    Case("nearly touching: gap 1 µm", _gap(1e-6)),
    Case("nearly parallel: gap 1 mm, turned 0.01°", _gap(1e-3, -0.01)),
]


def run_case(case: Case) -> Outcome:
    from ..api import run_model

    base = next(p for p in scene_files() if p.stem == case.base)
    doc = case.edit(copy.deepcopy(read_document(base)))
    t0 = time.perf_counter()
    try:
        result = run_model(validate_model(doc, base))
    except InputError as exc:
        return Outcome(case.name, f"refused: {exc.message}", 0, time.perf_counter() - t0, 0.0, 0)
    status = result.status
    return Outcome(case.name, status, result.diagnostics["steps"], time.perf_counter() - t0,
                   result.balance_error_ratio, result.contact.impact_count)  # fmt: skip


def stability(cases: list[Case] | None = None, log: Callable[[str], None] = lambda _: None) -> list[Outcome]:
    out = []
    for case in cases or CASES:
        log(case.name)
        out.append(run_case(case))
    return out


def markdown(outcomes: list[Outcome]) -> str:
    lines = ["| case | outcome | steps | run (s) | energy balance | impacts | acceptable |",
             "| --- | --- | ---: | ---: | ---: | ---: | :---: |"]  # fmt: skip
    for o in outcomes:
        text = o.result if len(o.result) < 140 else o.result[:137] + "…"
        lines.append(f"| {o.case} | {text} | {o.steps:,} | {o.wall_time:.2f} | {o.energy_balance:.1e} | "
                     f"{o.impacts} | {'yes' if o.acceptable else '**no**'} |")  # fmt: skip
    return "\n".join(lines) + "\n"


__all__ = ["CASES", "Case", "Outcome", "markdown", "stability", "Path"]
