"""Time a sweep with one and two local jobs and write the result file docs/bench/sweep.md.

    python docs/sweep_timing.py

Runs `pound sweep inputs/paper_studies.sweep.toml --study 6.3` (the paper's 73 angles of
incidence on the 150 s Kobe record) into a fresh temporary folder, first with --jobs 1, then
with --jobs 2, and records the time pound reports for the runs ("N runs in T s") and the
wall time of the whole command (checking the cases and starting the workers included), with
the machine's load average. docs/sweep.md quotes the file through docs/figures.py. A timing,
so not part of `python docs/build.py` (which gives the same pages on every run): rerun this
on a quiet machine when the solver's speed changes. Needs the Kobe record in ../shared.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SWEEP = "inputs/paper_studies.sweep.toml"
STUDY = "6.3"
OUT = ROOT / "docs" / "bench" / "sweep.md"


def timed(jobs: int) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        load = os.getloadavg()[0]
        start = time.perf_counter()
        p = subprocess.run(["pound", "sweep", SWEEP, "--study", STUDY, "-o", str(Path(tmp) / "out"),
                            "--jobs", str(jobs), "--no-progress"], cwd=ROOT, capture_output=True, text=True)  # fmt: skip
        wall = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(p.stdout + p.stderr)
    m = re.search(r"(\d+) runs? in ([0-9.]+) s", p.stdout + p.stderr)
    return {"jobs": jobs, "runs": int(m.group(1)), "runs_s": float(m.group(2)), "wall_s": wall, "load": load}


def main() -> None:
    if not (ROOT.parent / "shared" / "records").is_dir():
        sys.exit("needs the Kobe record in ../shared/records (see inputs/paper_kobe.toml)")
    rows = [timed(1), timed(2)]
    lines = [f"`pound sweep {SWEEP} --study {STUDY} --jobs N` into a fresh folder, on {os.cpu_count()} CPUs "
             "(written by `python docs/sweep_timing.py`).", "",
             "| jobs | runs | runs (s) | per run (s) | whole command (s) | load average at the start |",
             "| ---: | ---: | ---: | ---: | ---: | ---: |"]  # fmt: skip
    for r in rows:
        lines.append(f"| {r['jobs']} | {r['runs']} | {r['runs_s']:.1f} | {r['runs_s'] / r['runs']:.2f} | "
                     f"{r['wall_s']:.1f} | {r['load']:.1f} |")  # fmt: skip
    lines += ["", f"Speed-up of the runs with two jobs: {rows[0]['runs_s'] / rows[1]['runs_s']:.2f}×.", ""]
    OUT.write_text("\n".join(lines), encoding="utf-8")
    print(OUT.read_text(encoding="utf-8"))


if __name__ == "__main__":
    main()
