"""Run the shipped city block and write docs/city.md with its plan view.

    python docs/city_example.py

Runs inputs/city_block.toml (a 10 × 10 block of 2–6-storey buildings 8–12 cm apart, written by
inputs/make_city_block.py, under the shipped Ridgecrest record) and writes the plan view of its
lowest floors at the instant of the peak impact force to docs/images/city-plan.png (what it
shows, docs/make_report_images.py's signature, to docs/images/city-images.json, which
`python docs/build.py --check` compares), and the page docs/city.md: the candidates the reach
keeps, the impacts, and the scaling table of `pound bench --scaling --blocks`
(docs/bench/city-scaling.md). No timing is quoted from this run (those are the bench's).
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "city.md"
IMAGES = ROOT / "docs" / "images"
SIGNATURES = IMAGES / "city-images.json"
MODEL = ROOT / "inputs" / "city_block.toml"
SCALING = ROOT / "docs" / "bench" / "city-scaling.md"
SIGNED: dict[str, dict] = {}


def main() -> None:
    import pounding_cli as pound
    from make_report_images import save_signed  # docs/, the script's folder, is on sys.path
    from pounding_cli.api import prepare
    from pounding_cli.report import open_run
    from pounding_cli.report.plan import plan_figure

    IMAGES.mkdir(exist_ok=True)
    scene = prepare(MODEL)
    everything = sum(1 for _ in _all_level_pairs(scene))
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "city_block.h5"
        result = pound.run_model(MODEL, output=out)
        if not result.complete:
            sys.exit(f"{MODEL.name}: {result.status}")
        file_bytes = out.stat().st_size
        run = open_run(out, label="city_block.toml")
        save_signed(plan_figure(run, levels=[1]), IMAGES / "city-plan.png", SIGNED)
    if SCALING.exists():
        save_signed(scaling_figure(SCALING.read_text(encoding="utf-8")), IMAGES / "city-scaling.png", SIGNED)
    PAGE.write_text(page(scene, result, everything, file_bytes), encoding="utf-8")
    SIGNATURES.write_text(json.dumps(SIGNED, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {PAGE} and {SIGNATURES}", file=sys.stderr)


def scaling_figure(table: str):
    """Whole-run time and time per building against buildings, from the bench's table."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [[c.strip() for c in line.strip("|").split("|")] for line in table.splitlines()[2:] if line.strip()]
    n = np.array([float(r[0]) for r in rows])
    whole = np.array([float(r[6]) for r in rows])
    memory = np.array([float(r[8]) for r in rows])
    report = np.array([float(r[11]) if len(r) > 11 else np.nan for r in rows])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
    ax.loglog(n, whole, "o-", label="whole pound run")
    ax.loglog(n, whole / n, "s--", label="per building")
    ax.set_xlabel("buildings")
    ax.set_ylabel("wall time (s)")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    bx.semilogx(n, memory, "o-", label="pound run")
    bx.semilogx(n, report, "s--", label="pound report of its file")
    bx.legend()
    bx.set_xlabel("buildings")
    bx.set_ylabel("peak memory (GB)")
    bx.grid(True, which="both", alpha=0.3)
    fig.suptitle("pound bench --scaling --blocks (1000: 10 blocks, --jobs 2)")
    return fig


def _all_level_pairs(scene):
    """Every two floors of different buildings at one level: the candidates without a reach."""
    levels: dict[float, int] = {}
    for b in scene.system.buildings:
        for z in b.elevation:
            levels[round(float(z), 3)] = levels.get(round(float(z), 3), 0) + 1
    for n in levels.values():
        yield from range(n * (n - 1) // 2)


def single_precision_bytes(result) -> int:
    """Bytes of the buildings' histories that analysis.history_precision = "single" stores as
    float32: what the file would hold more in double precision."""
    total = 0
    for b in result.buildings.values():
        arrays = [b.displacement, b.velocity, b.acceleration]
        if b.forces is not None:
            arrays += [b.forces.storey_shear, b.forces.base_shear, b.forces.column_shear, b.forces.column_moment]
        if b.yielding is not None:
            arrays += [b.yielding.deflection, b.yielding.force]
        total += sum(a.nbytes for a in arrays if a is not None and a.dtype == np.float32)
    return total


def page(scene, result, everything: int, file_bytes: int) -> str:
    c = scene.contact
    touched = int(np.count_nonzero(np.any(result.contact.normal_force != 0, axis=0)))
    events = result.contact.events
    pairs_hit = len({int(p) for p in events["pair"]})
    scaling = SCALING.read_text(encoding="utf-8") if SCALING.exists() else "(run `pound bench --scaling --blocks --out docs/bench`)\n"
    return f"""# A city block: 100 buildings

<!-- Written by docs/city_example.py (python docs/build.py city); do not edit by hand. -->

`inputs/city_block.toml` is a 10 × 10 block of {len(scene.system.buildings)} buildings of 2–6
storeys of 3 m, 8–12 m in plan and 8–12 cm apart, drawn by `inputs/make_city_block.py`
(pounding_cli/city/block.py, seed 30), under the shipped 34 s of the 2019 Ridgecrest record.

Every two floors at one level would make {everything:,} candidate pairs. The reach keeps those of
buildings within {c.reach:.3g} m of each other (the bound from the modes and the record's spectral
displacement, [theory](theory.md#10-pounding-the-overlap-area-impact-model-paper-section-4)):
{c.n_pairs:,} pairs, of which {len(c.storeys)} slab–storey. The run logs {result.contact.impact_count}
impacts on {pairs_hit} pairs; the contact histories of {touched} pairs have a value at an output
instant, and only theirs are written to the result file (the HDF5 layout in the
[user guide](user-guide.md#hdf5-layout)). The buildings' histories, nearly all the rest, are
stored in single precision (`history_precision = "single"` in `[analysis]`, which the generator
writes; 7 significant digits): the file takes {file_bytes / 1e6:.1f} MB, where double precision
would take {(file_bytes + single_precision_bytes(result)) / 1e6:.1f} MB.

![Plan view of the first floors at the peak impact force](images/city-plan.png)

## Cost against size (`pound bench --scaling --blocks`)

The whole `pound run`, in a process of its own: wall time, peak memory (maximum resident set),
the result file; the last row is 10 such blocks across 20 m streets, run as independent groups
on 2 local processes (`--jobs 2`). Then `pound report --json` of the file, as a user reads it
back: `read_hdf5` maps the buildings' histories from the file and reads the contact histories'
stored columns alone ([user guide](user-guide.md#python-api)), so the report's memory follows
what it shows, not the file's size. Measured on a 2-core machine (the table is
docs/bench/city-scaling.md, of the last `pound bench --scaling --blocks`): compare rows, not machines.

{scaling}
![Whole run and per-building time, peak memory against buildings](images/city-scaling.png)
"""


if __name__ == "__main__":
    main()
