"""`pound bench --start`: how long a command takes from a cold process, and where a run's time
goes (issue 28, the cold start).

Every measurement is a fresh interpreter started as a user starts pound (`python -m
pounding_cli …`, from a scratch folder, the kernels already in numba's cache: one untimed run
first fills it). The commands are timed whole, wall clock, median of the repeats. The
breakdown repeats the work of `pound run` on the bench's pounding scene stage by stage in a
child of its own, timing each stage: numba's stages (its import, its CPU target's start-up,
which the first cached kernel of a process pays, and loading the time loop's kernels) are
what no change inside pound can remove; the rest is pound's.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from .scaling import table

SCENE = "paper_pounding.toml"
"""The bench scene timed: the paper's buildings, one impact, the 34 s Ridgecrest record (MiniSEED)."""

STAGES = (
    ("numpy", "numpy's import"),
    ("cli", "the command line (typer, rich)"),
    ("models", "the input models (pydantic)"),
    ("modules", "pound's other modules (assembly, results: shapely, h5py)"),
    ("load", "reading and validating the model file"),
    ("prepare", "the record (obspy) and the assembly"),
    ("numba", "numba's import"),
    ("target", "numba's CPU target start-up (the first cached kernel)"),
    ("solver", "the solver's modules"),
    ("kernels", "loading the time loop's cached kernels"),
    ("solve", "the time loop"),
    ("write", "results and the HDF5 file"),
)
"""The breakdown's stages, in the order a run meets them, with their descriptions."""

NUMBA_STAGES = ("numba", "target", "kernels")

_BREAKDOWN = r"""
import time
t0 = time.perf_counter()
import sys, json
marks = {}
def mark(name):
    global t0
    t = time.perf_counter(); marks[name] = t - t0; t0 = t
import numpy as np
mark("numpy")
from pounding_cli.cli import app
mark("cli")
import pounding_cli.model
mark("models")
from pounding_cli.api import execute, prepare
mark("modules")
from pounding_cli.model import load_model
loaded = load_model(sys.argv[1])
mark("load")
scene = prepare(loaded)
mark("prepare")
import numba
mark("numba")
from pounding_cli.records.spectrum_kernel import peak_displacements
peak_displacements(np.zeros(3), np.zeros((8, 1)), np.zeros(1))
mark("target")
from pounding_cli.solver import simulate
mark("solver")
result = execute(scene, sys.argv[2])
total = time.perf_counter() - t0
d = result.diagnostics
marks["kernels"] = d["compile_time_s"]
marks["solve"] = d["wall_time_s"]
marks["write"] = total - d["compile_time_s"] - d["wall_time_s"]
print(json.dumps(marks))
from pounding_cli.__main__ import end_now
end_now(0)  # as the command ends
"""


@dataclass(frozen=True)
class CommandTime:
    command: str
    median_s: float
    low_s: float
    high_s: float


@dataclass(frozen=True)
class StartReport:
    repeats: int
    commands: list[CommandTime]
    stages: dict[str, float]  # median of each stage (STAGES, and "interpreter": the rest of the process), s
    process_s: float  # median wall time of the breakdown's process, s (its start-up included)
    load: float  # the machine's 1-minute load average when the measurement began

    @property
    def numba_s(self) -> float:
        return sum(self.stages[k] for k in NUMBA_STAGES)


def _scene_folder() -> Path:
    return Path(str(resources.files("pounding_cli.bench") / "scenes"))


def _timed(args: list[str], cwd: Path) -> tuple[float, str]:
    start = time.perf_counter()
    done = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(args[2:])} failed (exit {done.returncode}): {done.stderr.strip()[-2000:]}")
    return wall, done.stdout


def start_times(repeats: int = 5, log=lambda _: None) -> StartReport:  # type: ignore[no-untyped-def]
    """Time pound's commands from cold processes (median of `repeats`) and break a run down."""
    load = os.getloadavg()[0]
    scene = str(_scene_folder() / SCENE)
    pound = [sys.executable, "-m", "pounding_cli"]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        result = str(folder / "run.h5")
        commands = (
            ("pound --help", [*pound, "--help"]),
            ("pound validate", [*pound, "validate", scene]),
            ("pound run", [*pound, "run", scene, "-o", result, "--force", "--no-progress"]),
            ("pound report --json", [*pound, "report", result, "--json"]),
        )
        log("filling the kernel cache (one untimed run)")
        _timed(commands[2][1], folder)
        times: list[CommandTime] = []
        for name, args in commands:
            log(name)
            walls = [_timed(args, folder)[0] for _ in range(repeats)]
            times.append(CommandTime(name, statistics.median(walls), min(walls), max(walls)))
        log("the stages of a run")
        marks, walls = [], []
        for _ in range(repeats):
            wall, stdout = _timed([sys.executable, "-c", _BREAKDOWN, scene, str(folder / "stages.h5")], folder)
            (folder / "stages.h5").unlink()
            marks.append(json.loads(stdout.strip().splitlines()[-1]))
            walls.append(wall)
            marks[-1]["interpreter"] = wall - sum(marks[-1].values())
    stages = {key: statistics.median(m[key] for m in marks) for key, _ in STAGES + (("interpreter", ""),)}
    return StartReport(repeats, times, stages, statistics.median(walls), load)


def markdown(report: StartReport) -> str:
    commands = table(
        ["command", "median s", "fastest s", "slowest s"],
        [[c.command, f"{c.median_s:.2f}", f"{c.low_s:.2f}", f"{c.high_s:.2f}"] for c in report.commands],
    )
    rows = [[text, f"{report.stages[key]:.3f}", "numba" if key in NUMBA_STAGES else "pound, its libraries"] for key, text in STAGES]
    rows.append(["the interpreter's start and exit (the process's wall time less the stages)",
                 f"{report.stages['interpreter']:.3f}", "Python"])  # fmt: skip
    stages = table(["stage of `pound run` (bench scene paper_pounding)", "median s", "whose"], rows)
    return (
        f"Cold processes, kernels cached; median of {report.repeats}; load average {report.load:.1f} when it began.\n\n"
        f"{commands}\n"
        f"Where a run's time goes (the same work, stage by stage, in a process of its own; wall "
        f"{report.process_s:.2f} s, of which numba {report.numba_s:.2f} s):\n\n{stages}"
    )
