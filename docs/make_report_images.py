#!/usr/bin/env python
"""Regenerate the images of docs/report.md from the shipped examples.

    python docs/make_report_images.py

Runs inputs/paper_pounding.toml (the paper's buildings 5 cm apart: one impact) and
inputs/paper_wide_gap.toml (0.5 m apart: none) into a temporary folder, then draws every
plot of ``pound report`` through the Python API into docs/images/ (report-*.png and the
animation report-plan.gif). Nothing is edited by hand.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"
IMAGES = ROOT / "docs" / "images"


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


def main() -> None:
    IMAGES.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        runs = run_examples(Path(tmp))
        written = run_images(runs)
    for path in written:
        print(f"wrote {path.relative_to(ROOT)} ({path.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
