"""The files a ``pound report`` writes besides what it prints: plots, the animation, the
HTML report — for result files or for a sweep folder. The CLI passes its options through."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from ..errors import InputError
from .histories import Floor
from .load import Run
from .sweep_data import Sweep


@dataclass
class Animation:
    """What ``--animate`` asked for (see :func:`pounding_cli.report.animate.animate_plan`)."""

    path: Path
    level: int | None = None
    start: float | None = None
    end: float | None = None
    stride: int | None = None
    max_frames: int = 120
    fps: int = 12


@dataclass
class Written:
    """The files written, and the animation's frame count."""

    files: list[Path] = field(default_factory=list)
    frames: int | None = None


def run_outputs(
    runs: Sequence[Run], plots: Path | None = None, fmt: str = "png", column: str | None = None,
    floors: Sequence[Floor] = (), magnify: float | None = None, animation: Animation | None = None,
    html: Path | None = None,
) -> Written:  # fmt: skip
    """Write the plots into `plots`, the animation of the first run, and the HTML report
    (embedding the plots already written and a GIF animation)."""
    out = Written()
    if plots is not None:
        from .plots import write_plots

        out.files += write_plots(runs, plots, fmt, column, floors, magnify)
    if animation is not None:
        from .animate import animate_plan

        a = animation
        out.frames = animate_plan(runs[0], a.path, a.level, magnify, a.start, a.end, a.stride, a.max_frames, a.fps)
        out.files.append(a.path)
    if html is not None:
        from .html import write_html

        embedded = "svg" if fmt == "svg" else "png"
        images = {p.stem: p for p in out.files if p.suffix == f".{embedded}"}
        gif = animation.path if animation is not None else None
        out.files.append(write_html(runs, html, column=column, floors=floors, magnify=magnify, fmt=embedded,
                                    animation=gif, images=images))  # fmt: skip
    return out


def sweep_outputs(
    sweep: Sweep, plots: Path | None = None, fmt: str = "png", column: str | None = None, x: str | None = None,
    ys: Sequence[str] | None = None, cases: Sequence[str] | None = None, html: Path | None = None,
) -> Written:  # fmt: skip
    """Write a sweep's plots into `plots` and its HTML report."""
    out = Written()
    options = dict(x=x, ys=ys or None, cases=cases or None)
    if plots is not None:
        from .sweep_plots import write_sweep_plots

        out.files += write_sweep_plots(sweep, plots, fmt, column=column, **options)
    if html is not None:
        from .html import write_sweep_html

        embedded = "svg" if fmt == "svg" else "png"
        images = {p.stem: p for p in out.files if p.suffix == f".{embedded}"}
        out.files.append(write_sweep_html(sweep, html, column=column, fmt=embedded, images=images, **options))
    return out


RUN_ONLY = ("--floor", "--magnify", "--animate", "--level", "--start", "--end", "--stride", "--max-frames", "--fps")
SWEEP_ONLY = ("--x", "--y", "--case", "--study")


def check_options(sweep: bool, given: dict[str, bool]) -> None:
    """InputError for an option given that does not apply to a sweep folder (or to runs)."""
    wrong = [name for name in (RUN_ONLY if sweep else SWEEP_ONLY) if given.get(name)]
    if wrong:
        what = ("applies to result files, not to a sweep folder (its cases' files are DIR/cases/<hash>.h5)"
                if sweep else "applies to a sweep folder, not to result files")  # fmt: skip
        raise InputError(f"{what}", field=wrong[0])
