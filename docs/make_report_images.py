#!/usr/bin/env python
"""Regenerate the images of docs/report.md from the shipped examples.

    python docs/make_report_images.py

Runs inputs/paper_pounding.toml (the paper's buildings 5 cm apart: one impact) and
inputs/paper_wide_gap.toml (0.5 m apart: none) into a temporary folder, and a sweep of the
pounding example (:data:`SWEEP`: the angle of incidence from 0° to 360° in 10° steps, and the
paper's section 6.1 cases with and without pounding), then draws every plot of ``pound
report`` through the Python API into docs/images/ (report-*.png, the animation
report-plan.gif, report-sweep-*.png). For the yielding members it also runs
inputs/isolated_moat.toml (a base-isolated building on nine lead-rubber bearings, its moat
wall 10 cm away) and inputs/paper_inelastic.toml (every column yields) and draws their
hysteresis loops (report-loops-isolators.png, report-loops-columns.png). Nothing is edited by
hand. About two minutes on 2 cores.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"
IMAGES = ROOT / "docs" / "images"

SWEEP = """
title = "Pounding example: angle of incidence, eccentricity"

[summary]
columns = { left = ["C9"] }

[studies.angle]
description = "Angle of incidence θ from 0° to 360° in 10° steps, both components"
parameters = { "excitation.angle" = { start = 0, stop = 360, step = 10 } }

[studies.eccentricity]
description = "The paper's section 6.1 cases on this record: L along x only"
set = { "excitation.components" = ["L"] }

[studies.eccentricity.cases]
"case 1: no eccentricity, pounding" = {}
"case 2: left e_y = 0.4 m, pounding" = { "buildings.left.floors[*].eccentricity" = [0.0, 0.4] }
"case 4: as case 1, no pounding" = { "contact.enabled" = false }
"case 5: as case 2, no pounding" = { "buildings.left.floors[*].eccentricity" = [0.0, 0.4], "contact.enabled" = false }
"""
"""The sweep behind the sweep images (over inputs/paper_pounding.toml)."""


def run_examples(folder: Path) -> dict:
    """Run the two shipped examples; name → report.Run."""
    import pounding_cli as pound
    from pounding_cli.report import open_run

    runs = {}
    for name, model in (("pounding", "paper_pounding.toml"), ("wide gap", "paper_wide_gap.toml")):
        path = folder / f"{model.removesuffix('.toml')}.h5"
        result = pound.run_model(INPUTS / model, output=path)
        if not result.complete:
            sys.exit(f"{model}: {result.status}")
        runs[name] = open_run(path, label=f"{name} ({model})")
    return runs


def run_images(runs: dict) -> list[Path]:
    """The plots of one run (the pounding example), the profiles of both, the animation."""
    from pounding_cli.report.animate import animate_plan
    from pounding_cli.report.energy import energy_figure
    from pounding_cli.report.ground import ground_figure
    from pounding_cli.report.histories import displacement_figure
    from pounding_cli.report.impacts import impact_figure
    from pounding_cli.report.plan import plan_figure
    from pounding_cli.report.profiles import profile_figure
    from pounding_cli.report.style import save_as

    run = runs["pounding"]
    figures = {
        "report-ground": ground_figure(run),
        "report-displacement": displacement_figure(run, [("left", 3), ("right", 3)]),
        "report-profiles": profile_figure([runs["pounding"], runs["wide gap"]], column="left:C9"),
        "report-impacts": impact_figure(run),
        "report-energy": energy_figure(run),
        "report-plan": plan_figure(run),
    }
    written = [save_as(fig, IMAGES, stem, "png") for stem, fig in figures.items()]
    gif = IMAGES / "report-plan.gif"
    animate_plan(run, gif, level=3, start=12.5, end=16.5, max_frames=80)
    return [*written, gif]


def yielding_images(folder: Path) -> list[Path]:
    """The hysteresis loops of the isolators of isolated_moat.toml and of the most ductile
    column of each storey of paper_inelastic.toml's left building."""
    import pounding_cli as pound
    from pounding_cli.report import open_run
    from pounding_cli.report.loops import loop_figure
    from pounding_cli.report.style import save_as

    figures = {}
    for stem, model, building in (("report-loops-isolators", "isolated_moat.toml", "isolated"),
                                  ("report-loops-columns", "paper_inelastic.toml", "left")):  # fmt: skip
        path = folder / f"{model.removesuffix('.toml')}.h5"
        result = pound.run_model(INPUTS / model, output=path)
        if not result.complete:
            sys.exit(f"{model}: {result.status}")
        figures[stem] = loop_figure(open_run(path), building)
    return [save_as(fig, IMAGES, stem, "png") for stem, fig in figures.items()]


def sweep_images(folder: Path) -> list[Path]:
    """Run :data:`SWEEP` and draw figure 8 (lines and polar) and the bars of the named cases."""
    from pounding_cli.report.style import save_as
    from pounding_cli.report.sweep_bars import cases_figure
    from pounding_cli.report.sweep_data import match_cases, open_sweep, select
    from pounding_cli.report.sweep_lines import parameter_figure
    from pounding_cli.sweep import run_sweep

    path = folder / "report.sweep.toml"
    path.write_text(f'base = "{(INPUTS / "paper_pounding.toml").as_posix()}"\n' + SWEEP, encoding="utf-8")
    outcome = run_sweep(path, folder / "sweep", jobs=2)
    if not outcome.ok:
        sys.exit(f"the sweep failed: {outcome.counts}")
    sweep = open_sweep(folder / "sweep")
    angle = select(sweep, ["angle"])
    figures = {
        "report-sweep-angle": parameter_figure(angle, "excitation.angle", column="left:C9"),
        "report-sweep-polar": parameter_figure(angle, "excitation.angle", column="left:C9", polar=True),
        "report-sweep-cases": cases_figure(sweep, match_cases(sweep, ["eccentricity/*"]), column="left:C9"),
    }
    return [save_as(fig, IMAGES, stem, "png") for stem, fig in figures.items()]


def main() -> None:
    IMAGES.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        runs = run_examples(Path(tmp))
        written = run_images(runs) + yielding_images(Path(tmp)) + sweep_images(Path(tmp))
    for path in written:
        print(f"wrote {path.relative_to(ROOT)} ({path.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
