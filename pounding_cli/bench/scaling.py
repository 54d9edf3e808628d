"""`pound bench --scaling`: solver cost against the number of buildings in a row.

Rows of 1, 5, 10, 20 and 40 three-storey buildings (unlike neighbours, 3 cm apart, the shipped
record × 1.5, 10 s): the cost per CDM step, and the hybrid's solver time per simulated
second. With n buildings in a row there are 3·n(n−1)/2 candidate pairs (floors at one level
of different buildings); the broad phase sweeps and prunes (solver/broad_phase.py), so the
step costs in proportion to the DOFs and the pairs whose boxes overlap, not to the candidate
pairs.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

from ..api import execute, prepare
from ..model import read_document, validate_model
from .run import Setting, scene_files, with_setting
from .crossover import EVERY_PAIR
from .stability import _row

COUNTS = (1, 5, 10, 20, 40)


@dataclass(frozen=True)
class Point:
    buildings: int
    dofs: int
    pairs: int
    cdm_us_per_step: float
    hybrid_s_per_simulated_s: float
    impacts: int


def scaling(counts: tuple[int, ...] = COUNTS, duration: float = 10.0, log=lambda _: None) -> list[Point]:
    base = next(p for p in scene_files() if p.stem == "row_of_5")
    out = []
    for n in counts:
        log(f"{n} buildings")
        doc = _row(n)(copy.deepcopy(read_document(base)))
        doc["analysis"]["duration"] = duration
        doc.setdefault("contact", {})["reach"] = EVERY_PAIR  # every pair of a level, as the sweep and prune meets them
        scene = prepare(validate_model(doc, base))
        cdm = execute(with_setting(scene, Setting("cdm", "cdm", dt=2e-5)))
        hybrid = execute(scene)
        out.append(Point(n, scene.system.n_dof, scene.contact.n_pairs,
                         1e6 * cdm.diagnostics["wall_time_s"] / cdm.diagnostics["steps"],
                         hybrid.diagnostics["wall_time_s"] / duration, hybrid.contact.impact_count))  # fmt: skip
    return out


def markdown(points: list[Point]) -> str:
    header = ["buildings", "DOFs", "candidate pairs", "CDM µs/step", "µs/step per DOF", "hybrid solver s per simulated s",
              "impacts"]  # fmt: skip
    return table(header, [[f"{p.buildings}", f"{p.dofs}", f"{p.pairs}", f"{p.cdm_us_per_step:.2f}",
                           f"{p.cdm_us_per_step / p.dofs:.3f}", f"{p.hybrid_s_per_simulated_s:.4f}", f"{p.impacts}"]
                          for p in points])  # fmt: skip


def table(header: list[str], rows: list[list[str]]) -> str:
    """A Markdown table of right-aligned columns."""
    lines = ["| " + " | ".join(header) + " |", "|" + " ---: |" * len(header)]
    return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows]) + "\n"
