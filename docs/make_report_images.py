#!/usr/bin/env python
"""Regenerate the images of docs/report.md from the shipped examples, or check them.

    python docs/make_report_images.py           # write docs/images/report-*.png, .gif
    python docs/make_report_images.py --check   # write nothing; exit 1 if a figure changed

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

**The check.** Each image's *content* — per visible axes its projection, title, axis labels,
legend entries and how many lines, patches, collections and arrows it draws; the figure's
title and legends; the animation's frame count and size — is written beside the images in
:data:`SIGNATURES`. ``--check`` draws every figure again from fresh runs and compares that
content with the file, naming each image and what differs. It cannot compare the image
files byte for byte: a PNG's bytes depend on the versions of matplotlib, FreeType, the fonts
and zlib (anti-aliasing, hinting, compression), and the GIF's on the palette quantiser, so
the same figure drawn on another machine, or after a library update, gives other bytes.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"
IMAGES = ROOT / "docs" / "images"
SIGNATURES = IMAGES / "report-images.json"
"""The content of every image this script writes (see the module's docstring)."""

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


def run_figures(runs: dict) -> dict:
    """The plots of one run (the pounding example) and the profiles of both: stem → Figure."""
    from pounding_cli.report.energy import energy_figure
    from pounding_cli.report.ground import ground_figure
    from pounding_cli.report.histories import displacement_figure
    from pounding_cli.report.impacts import impact_figure
    from pounding_cli.report.plan import plan_figure
    from pounding_cli.report.profiles import profile_figure
    from pounding_cli.report.shear_profiles import shear_figure

    run = runs["pounding"]
    return {
        "report-ground": ground_figure(run),
        "report-displacement": displacement_figure(run, [("left", 3), ("right", 3)]),
        "report-profiles": profile_figure([runs["pounding"], runs["wide gap"]], column="left:C9"),
        "report-storey-shear": shear_figure([runs["pounding"], runs["wide gap"]]),
        "report-impacts": impact_figure(run),
        "report-energy": energy_figure(run),
        "report-plan": plan_figure(run),
    }


def animation(runs: dict, path: Path) -> dict:
    """Write the plan-view animation of the pounding example to `path`; its content."""
    from PIL import Image

    from pounding_cli.report.animate import animate_plan

    frames = animate_plan(runs["pounding"], path, level=3, start=12.5, end=16.5, max_frames=80)
    with Image.open(path) as gif:
        return {"frames": int(frames), "stored_frames": int(gif.n_frames), "size": list(gif.size)}


def yielding_figures(folder: Path) -> dict:
    """The hysteresis loops of the isolators of isolated_moat.toml and of the most ductile
    column of each storey of paper_inelastic.toml's left building: stem → Figure."""
    import pounding_cli as pound
    from pounding_cli.report import open_run
    from pounding_cli.report.loops import loop_figure

    figures = {}
    for stem, model, building in (("report-loops-isolators", "isolated_moat.toml", "isolated"),
                                  ("report-loops-columns", "paper_inelastic.toml", "left")):  # fmt: skip
        path = folder / f"{model.removesuffix('.toml')}.h5"
        result = pound.run_model(INPUTS / model, output=path)
        if not result.complete:
            sys.exit(f"{model}: {result.status}")
        figures[stem] = loop_figure(open_run(path), building)
    return figures


def sweep_figures(folder: Path) -> dict:
    """Run :data:`SWEEP` and draw figure 8 (lines and polar) and the bars of the named cases:
    stem → Figure."""
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
    return {
        "report-sweep-angle": parameter_figure(angle, "excitation.angle", column="left:C9"),
        "report-sweep-polar": parameter_figure(angle, "excitation.angle", column="left:C9", polar=True),
        "report-sweep-cases": cases_figure(sweep, match_cases(sweep, ["eccentricity/*"]), column="left:C9"),
    }


def signature(fig) -> dict:
    """What a figure shows, without its pixels: per visible axes its projection, title, axis
    labels, legend entries and how many lines, patches, collections and arrows it draws; the
    figure's title and legend entries."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()  # lay out and draw: tick labels and titles as saved

    def legend(box) -> list[str]:
        return [t.get_text() for t in box.get_texts()] if box is not None else []

    axes = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        axes.append({
            "projection": ax.name, "title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
            "lines": len(ax.get_lines()), "patches": len(ax.patches), "collections": len(ax.collections),
            "arrows": sum(getattr(t, "arrow_patch", None) is not None for t in ax.texts),
            "legend": legend(ax.get_legend()),
        })  # fmt: skip
    suptitle = fig._suptitle.get_text() if fig._suptitle is not None else ""
    return {"suptitle": suptitle, "legends": [legend(box) for box in fig.legends], "axes": axes}


def save_signed(fig, path: Path, signed: dict) -> None:
    """Write a figure (110 dpi) and keep what it shows (signature) in signed[path.name], for the
    pages' image files (docs/inelastic_examples.py, docs/floors_example.py)."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110)
    signed[path.name] = signature(fig)
    plt.close(fig)


def differences(expected: dict, found: dict) -> list[str]:
    """What differs between two {image: content} documents, one line per difference."""
    out = []
    for image in sorted(set(expected) | set(found)):
        if image not in found:
            out.append(f"{image}: no longer drawn")
        elif image not in expected:
            out.append(f"{image}: new, not in {SIGNATURES.name}")
        else:
            out += [f"{image}: {line}" for line in _compare(expected[image], found[image], "")]
    return out


def _compare(a, b, where: str) -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        return [line for key in sorted(set(a) | set(b), key=str)
                for line in _compare(a.get(key), b.get(key), f"{where}.{key}" if where else str(key))]  # fmt: skip
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b) and any(isinstance(x, dict) for x in a):
        return [line for k, (x, y) in enumerate(zip(a, b)) for line in _compare(x, y, f"{where}[{k}]")]
    return [] if a == b else [f"{where}: {a!r} in the docs, {b!r} now"]


def main(argv: list[str]) -> int:
    check = "--check" in argv
    unknown = [a for a in argv if a != "--check"]
    if unknown:
        sys.exit(f"usage: python docs/make_report_images.py [--check]; unknown {' '.join(unknown)}")
    from pounding_cli.report.style import save_as

    found: dict = {}
    written = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        runs = run_examples(folder)
        figures = {**run_figures(runs), **yielding_figures(folder), **sweep_figures(folder)}
        if not check:
            IMAGES.mkdir(exist_ok=True)
        gif = (folder if check else IMAGES) / "report-plan.gif"
        found["report-plan.gif"] = animation(runs, gif)
        for stem, fig in figures.items():
            if not check:  # saved before the signature draws it: a second layout pass moves pixels
                written.append(save_as(fig, IMAGES, stem, "png"))
            found[f"{stem}.png"] = signature(fig)
    if check:
        expected = json.loads(SIGNATURES.read_text(encoding="utf-8")) if SIGNATURES.exists() else {}
        missing = [name for name in found if not (IMAGES / name).exists()]
        problems = [f"{name}: the image file is missing" for name in missing] + differences(expected, found)
        for line in problems:
            print(f"docs/images/{line}")
        print(f"{len(found)} images: " + ("up to date" if not problems else
              f"{len(problems)} differences; run python docs/make_report_images.py"))  # fmt: skip
        return 1 if problems else 0
    SIGNATURES.write_text(json.dumps(found, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    for path in [*written, IMAGES / "report-plan.gif", SIGNATURES]:
        print(f"wrote {path.relative_to(ROOT)} ({path.stat().st_size / 1e3:.0f} kB)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
