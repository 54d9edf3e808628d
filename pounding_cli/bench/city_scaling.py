"""`pound bench --scaling --blocks`: whole `pound run` cost of city blocks and districts (issue 30).

Each case is a model of pounding_cli/city/block.py (10 cm gaps, 2–6 storeys, the shipped
34 s Ridgecrest record) run as a user runs it, `pound run` in a process of its own: its wall
time, its peak memory (the child's maximum resident set, from the kernel's rusage), the
result file's size, the candidate pairs, the solver's time and the number of groups; then
`pound report --json` of the file, as a user reads it back: its wall time and peak memory. Grids of
3 × 3, 5 × 5 and 10 × 10, then districts of 10 × 10 blocks across 20 m streets with --jobs.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from ..atomic import write_text
from ..city.block import Block, city_document, district_buildings
from .scaling import table

CASES = ((3, 1, 1), (5, 1, 1), (10, 1, 1), (10, 10, 2))
"""(grid side, blocks, local processes)."""


@dataclass(frozen=True)
class CityPoint:
    buildings: int
    blocks: int
    jobs: int
    pairs: int
    groups: int
    solver_s: float
    run_s: float
    peak_memory_gb: float
    file_mb: float
    report_s: float
    report_memory_gb: float


def _record_folder() -> Path:
    from importlib import resources

    return Path(str(resources.files("pounding_cli.bench") / "scenes"))


def run_case(side: int, blocks: int, jobs: int, folder: Path) -> CityPoint:
    """Write the case's model into `folder`, run it with `pound run` in a child process."""
    import tomli_w  # a test dependency: the bench writes TOML models

    bx = int(round(blocks**0.5)) or 1
    buildings = district_buildings(Block(rows=side, cols=side), bx, -(-blocks // bx))[: blocks * side * side]
    model = folder / f"city_{len(buildings)}.toml"
    write_text(model, tomli_w.dumps(city_document(buildings, f"{len(buildings)} buildings", record_dir=".")))
    out = folder / f"city_{len(buildings)}.h5"
    args = [sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(out), "--force", "--json"]
    args += ["--jobs", str(jobs)] if jobs > 1 else []
    stdout, wall, usage = _child(args, f"pound run {model.name}")
    import h5py

    json.loads(stdout)  # a complete run prints its summary
    with h5py.File(out) as f:
        diag = dict(f["diagnostics"].attrs)
    size = out.stat().st_size
    report, report_wall, report_usage = _child([sys.executable, "-m", "pounding_cli", "report", str(out), "--json"],
                                               f"pound report {out.name}")  # fmt: skip
    json.loads(report)
    out.unlink()
    return CityPoint(len(buildings), blocks, jobs, int(diag.get("contact_pairs", -1)), int(diag.get("groups", 1)),
                     float(diag.get("wall_time_s", float("nan"))), wall, usage.ru_maxrss / 2**20, size / 1e6,
                     report_wall, report_usage.ru_maxrss / 2**20)  # fmt: skip


def _child(args: list[str], what: str) -> tuple[str, float, os.struct_rusage | None]:  # type: ignore[name-defined]
    """Run a command in a child process: its standard output, wall time s and rusage."""
    start = time.perf_counter()
    child = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    stdout = child.stdout.read() if child.stdout else ""
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"{what} failed")
    return stdout, wall, usage


def city_scaling(cases=CASES, log=lambda _: None) -> list[CityPoint]:  # type: ignore[no-untyped-def]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        shutil.copy(_record_folder() / "ridgecrest2019_ccc.mseed", folder)
        out = []
        for side, blocks, jobs in cases:
            log(f"{blocks} block(s) of {side} x {side}, --jobs {jobs}")
            out.append(run_case(side, blocks, jobs, folder))
        return out


def markdown(points: list[CityPoint]) -> str:
    header = ["buildings", "blocks", "--jobs", "candidate pairs", "groups", "solver s", "whole run s", "s per building",
              "peak memory GB", "file MB", "report s", "report memory GB"]  # fmt: skip
    return table(header, [[f"{p.buildings}", f"{p.blocks}", f"{p.jobs}", f"{p.pairs}", f"{p.groups}", f"{p.solver_s:.3g}",
                           f"{p.run_s:.3g}", f"{p.run_s / p.buildings:.3g}", f"{p.peak_memory_gb:.2f}",
                           f"{p.file_mb:.3g}", f"{p.report_s:.3g}", f"{p.report_memory_gb:.2f}"] for p in points])  # fmt: skip
