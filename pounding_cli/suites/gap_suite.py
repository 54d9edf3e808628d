"""`pound gap MODEL --suite SUITE`: the required separation under every record of a suite,
its distribution per pair and the pounding fragility.

    result = gap_suite("inputs/paper_pounding.toml", "far-field", "paper-far-field/", jobs=2)
    result.pairs[0]["required"]["median"], result.fragility_fit[:, 0]

Every case (record × orientation, suites.resolve) is the model with its excitation's record
replaced by the case's and its scale multiplied by the case's factor; each runs `pound gap`
(gap.required) in the sweep's executor (local processes or Dask, sweep.run) and writes
OUTPUT/cases/<case>.h5 as `pound gap -o` would. A rerun reads the complete case files of
the same inputs instead of running them again. The statistics (suites.fragility) go to
OUTPUT/gap-suite.h5 (suites.hdf5), written atomically once every case has run.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..errors import InputError
from .fragility import Lognormal, empirical_exceedance, fit_lognormal, fitted_exceedance, gap_grid
from .resolve import Suite, resolve_suite

RESULT = "gap-suite.h5"
QUANTITIES = ("required", "abs", "srss", "ddc")
"""Per-pair values of each case whose distribution over the suite is fitted (m)."""
IDENTITY = ("body_a", "floor_a", "body_b", "floor_b", "storey_b", "kind", "elevation", "xi", "clear_distance",
            "direction_x", "direction_y")  # fmt: skip


@dataclass
class GapSuiteResult:
    """The suite's cases and, per pair, the distributions and the fragility."""

    folder: Path
    suite: Suite
    cases: list[dict[str, Any]]  # label, record, orientation, factor, status, reused, elapsed_s, file
    pairs: list[dict[str, Any]]  # identity, then per quantity its Lognormal.as_dict(), p_pound_*
    values: dict[str, np.ndarray]  # quantity → (n_cases, n_pairs) m, NaN for a failed case
    gaps: np.ndarray  # (ng,) m
    fragility_empirical: np.ndarray  # (ng, n_pairs)
    fragility_fit: np.ndarray  # (ng, n_pairs)
    at: list[float] = field(default_factory=list)  # m: gaps asked for (--at)
    wall_time_s: float = 0.0

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [c for c in self.cases if c["status"] != "complete"]

    def as_dict(self) -> dict[str, Any]:
        return {"suite": self.suite.describe(), "folder": str(self.folder), "cases": self.cases, "pairs": self.pairs,
                "wall_time_s": self.wall_time_s}  # fmt: skip


def gap_suite(model: str | Path, suite: str | Path, output: str | Path | None = None, *, jobs: int | None = None,
              scheduler: str | None = None, scheduler_file: str | Path | None = None, client: Any = None,
              at: list[float] | None = None, force: bool = False,
              on_progress: Callable[[int, int], None] | None = None) -> GapSuiteResult:  # fmt: skip
    """Run every case of `suite` for `model` into `output` (default: <model>-<suite>/ in the
    current folder) and return the statistics (module docstring). `at`: gaps (m, ≥ 0) at
    which the probability of pounding is also given."""
    from ..model import load_model, read_document
    from ..sweep.run import open_executor
    from ..sweep.store import OutputFolder

    t0 = time.perf_counter()
    at = list(at or [])
    for g in at:
        if not (math.isfinite(g) and g >= 0):
            raise InputError(f"expected a gap ≥ 0 in m, got {g:g}", field="--at")
    model = Path(model)
    loaded = load_model(model)  # a bad model is refused before anything starts
    base = read_document(model)
    folder = OutputFolder(Path(output) if output is not None else default_output(model, suite))
    if scheduler is not None or scheduler_file is not None or client is not None:
        model, folder = model.absolute(), OutputFolder(folder.root.absolute())
    _check_owner(folder.root, force)
    outcomes: dict[str, Any] = {}
    with open_executor(jobs, scheduler, scheduler_file, client) as executor:
        with ThreadPoolExecutor(1) as thread:  # the model prepared and the suite resolved while the workers start
            preparing = thread.submit(_prepared, loaded, suite)
            for _ in executor.run([(k, _warm_up, ()) for k in range(getattr(executor, "jobs", 0))]):
                pass
            scene, resolved = preparing.result()
        folder.prepare()  # nothing is written before every input is checked
        with folder.locked():
            folder.remove_stale_temporaries()
            tasks = [(c.label, _task_function(), (_case_document(base, c), str(model), str(folder.case_file(c.label)),
                      str(folder.failure_file(c.label)))) for c in resolved.cases]  # fmt: skip
            for done, (label, ok, value) in enumerate(executor.run(tasks), start=1):
                outcomes[label] = value if ok else {"status": f"failed: {value}", "pairs": [], "reused": False,
                                                    "elapsed_s": None}  # fmt: skip
                if on_progress is not None:
                    on_progress(done, len(tasks))
            result = statistics(folder.root, resolved, outcomes, at)
            result.wall_time_s = time.perf_counter() - t0
            from .hdf5 import write_gap_suite

            write_gap_suite(result, folder.root / RESULT, scene)
    return result


def _check_owner(root: Path, force: bool) -> None:
    """Refuse a folder that holds files pound did not write there, unless `force`."""
    from ..sweep.store import MARKER

    if not root.exists() or force or (root / MARKER).is_file():
        return
    if not root.is_dir():
        raise InputError("is a file; give a folder for the suite's results (-o)", file=root)
    held = sorted(p.name for p in root.iterdir())
    if held:
        raise InputError(f"holds files that pound did not write ({', '.join(held[:5])}{' …' if len(held) > 5 else ''}); "
                         f"pound gap --suite writes cases/ and {RESULT} into its folder: give a new or empty folder, "
                         "or pass --force to write into this one", file=root)  # fmt: skip


def _prepared(loaded: Any, suite: str | Path) -> tuple[Any, Suite]:
    """The base model's scene (assembled, its record read) and the suite resolved for it."""
    from ..api import prepare

    scene = prepare(loaded)
    return scene, resolve_suite(suite, scene)


def default_output(model: Path, suite: str | Path) -> Path:
    """<model stem>-<suite stem>, in the current folder."""
    name = Path(str(suite)).name
    for suffix in (".suite.toml", ".suite.json", ".toml", ".json"):
        if name.lower().endswith(suffix):
            name = name[: -len(suffix)]
            break
    return Path(f"{model.stem}-{name}")


def _warm_up() -> None:
    """Import what a case needs (and load the compiled kernels), in a local worker."""
    from .gap_case import warm_up

    warm_up()


def _task_function() -> Callable[..., Any]:
    from .gap_case import gap_case

    return gap_case


def _case_document(base: dict[str, Any], case: Any) -> dict[str, Any]:
    """The base model's document with the case's record and scale."""
    import copy

    doc = copy.deepcopy(base)
    excitation = doc.setdefault("excitation", {})
    excitation["record"] = case.definition
    excitation["scale"] = float(excitation.get("scale", 1.0)) * case.factor
    return doc


def statistics(folder: Path, suite: Suite, outcomes: dict[str, Any], at: list[float]) -> GapSuiteResult:
    """The suite's result from each case's outcome (gap_case), in the suite's case order."""
    cases, rows = [], []
    for c in suite.cases:
        o = outcomes[c.label]
        cases.append({"case": c.label, "record": c.record, "orientation": c.orientation, "factor": c.factor,
                      "status": o["status"], "reused": bool(o.get("reused")), "elapsed_s": o.get("elapsed_s"),
                      "file": f"cases/{c.label}.h5"})  # fmt: skip
        rows.append(o["pairs"] if o["status"] == "complete" else None)
    keys = next((_keys(r) for r in rows if r), [])
    values = {q: np.full((len(cases), len(keys)), np.nan) for q in QUANTITIES}
    for i, r in enumerate(rows):
        if r is None:
            continue
        by_key = dict(zip(_keys(r), r))
        for j, k in enumerate(keys):
            for q in QUANTITIES:
                values[q][i, j] = by_key[k][q] if k in by_key else np.nan
    first = next((r for r in rows if r), [])
    gaps = gap_grid(values["required"])
    empirical = np.zeros((gaps.size, len(keys)))
    fitted = np.zeros((gaps.size, len(keys)))
    pairs = []
    for j, p in enumerate(first):
        fits = {q: fit_lognormal(values[q][:, j]) for q in QUANTITIES}
        empirical[:, j] = empirical_exceedance(values["required"][:, j], gaps)
        fitted[:, j] = fitted_exceedance(fits["required"], gaps)
        rest = np.array([p["clear_distance"]] + at)
        row = {k: p[k] for k in IDENTITY} | {q: fits[q].as_dict() for q in QUANTITIES}
        row["p_pound_empirical"] = float(empirical_exceedance(values["required"][:, j], rest[:1])[0])
        row["p_pound_fit"] = float(fitted_exceedance(fits["required"], rest[:1])[0])
        row["at"] = [{"gap": g, "p_empirical": float(e), "p_fit": float(f)} for g, e, f in
                     zip(at, empirical_exceedance(values["required"][:, j], rest[1:]),
                         fitted_exceedance(fits["required"], rest[1:]))]  # fmt: skip
        pairs.append(row)
    return GapSuiteResult(folder, suite, cases, pairs, values, gaps, empirical, fitted, at)


def _keys(rows: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
    return [(r["body_a"], r["floor_a"], r["body_b"], r["floor_b"], r["storey_b"]) for r in rows]


__all__ = ["GapSuiteResult", "Lognormal", "gap_suite", "statistics"]
