"""The self-contained HTML report (``pound report ... --html report.html``, of runs or of a
sweep folder): the tables and every plot of the report in one file, images embedded as base64 (PNG, or SVG), no external
style sheet, script or font, so it can be mailed or archived as it is.
"""

from __future__ import annotations

import base64
import html
import io
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from .. import __version__
from ..atomic import write_text as write_atomically
from ..errors import InputError
from .document import summary
from .histories import Floor
from .load import Run
from .sweep_data import Sweep
from .plots import all_figures
from .tables import TableSpec, run_tables, status_line

if TYPE_CHECKING:
    from matplotlib.figure import Figure

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 72em; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.25em; margin-top: 2em; } h3 { font-size: 1.05em; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }
caption { text-align: left; font-weight: bold; padding: 0.3em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; vertical-align: top; }
th { background: #f3f3f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.failed { background: #fde8e8; border: 2px solid #c62828; color: #8e0000; padding: 0.8em; font-weight: bold; }
figure { margin: 1em 0 2em; } figure img { max-width: 100%; } figcaption { color: #555; font-size: 0.9em; }
"""


def table_html(spec: TableSpec) -> str:
    """`spec` as an HTML table (a key-value table has no header row)."""
    key_value = all(h == "" for h in spec.headers)
    out = [f"<table><caption>{html.escape(spec.title)}</caption>"]
    if not key_value:
        out.append("<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in spec.headers) + "</tr>")
    for row in spec.rows:
        cells = []
        for i, cell in enumerate(row):
            tag = "th" if key_value and i == 0 else "td"
            cls = ' class="num"' if i in spec.right else ""
            cells.append(f"<{tag}{cls}>{html.escape(cell)}</{tag}>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def figure_html(fig: Figure, caption: str, fmt: str = "png") -> str:
    """`fig` embedded as a base64 PNG (120 dpi) or SVG image with a caption."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format=fmt, dpi=120)
    return image_html(buffer.getvalue(), caption, fmt)


def image_html(image: bytes, caption: str, fmt: str = "png") -> str:
    """An image file's bytes (png, svg or gif) embedded as base64 with a caption."""
    mime = {"svg": "image/svg+xml", "gif": "image/gif"}.get(fmt, "image/png")
    data = base64.b64encode(image).decode("ascii")
    return (f'<figure><img alt="{html.escape(caption)}" src="data:{mime};base64,{data}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")  # fmt: skip


CAPTIONS = {
    "ground": "Ground acceleration along global X and Y, with the impacts of the log.",
    "displacement": "Floor displacements at the mass centres, relative to the ground.",
    "profiles": "Peak interstorey deflection per storey (the paper's figures 6 and 7).",
    "storey_shear": "Peak storey shear and torque per storey; storey 1's is the base shear.",
    "impacts": "Impact force and overlap area: histories at the output interval and each episode's peak from the log.",
    "energy": "Energy balance: the energies stacked under the input energy, and the balance error.",
    "plan": "Plan view of every level at the instant of peak impact force.",
    "loops": "Hysteresis loops of the yielding members (isolators, the most ductile or the chosen columns): "
             "force against deflection along each member's local axes, the yield forces dashed.",
}


def report_html(
    runs: Sequence[Run], column: str | None = None, floors: Sequence[Floor] | None = None,
    magnify: float | None = None, fmt: str = "png", animation: Path | None = None,
    images: dict[str, Path] | None = None,
) -> str:  # fmt: skip
    """The whole report as one HTML document. `images`: figures already written (file stem of
    :func:`~pounding_cli.report.plots.all_figures` → file, in `fmt`), embedded instead of
    drawn again; `animation`: a GIF to embed."""
    if fmt not in ("png", "svg"):
        raise InputError(f"the HTML report embeds png or svg images, not {fmt}", field="--format")
    title = runs[0].title if len(runs) == 1 else f"{len(runs)} runs"
    parts = [_head(title)]
    docs = [summary(run, column=column) for run in runs]
    for doc in docs:  # a failed run says so at the very top
        warning = status_line(doc)
        if warning:
            parts.append(f'<p class="failed">{html.escape(doc["file"])}: {html.escape(warning)}</p>')
    for run, doc in zip(runs, docs):
        parts.append(f"<h2>{html.escape(run.label)}: {html.escape(run.title)}</h2>")
        warning = status_line(doc)
        if warning:
            parts.append(f'<p class="failed">{html.escape(warning)}</p>')
        parts += [table_html(spec) for spec in run_tables(doc)]
    parts.append("<h2>Plots</h2>")
    for stem, draw in all_figures(runs, column, floors, magnify).items():
        kind = stem.rsplit("-", 1)[-1]
        caption = (f"{stem.rsplit('-', 1)[0]}: " if "-" in stem else "") + CAPTIONS.get(kind, stem)
        done = (images or {}).get(stem)
        parts.append(image_html(done.read_bytes(), caption, fmt) if done else figure_html(draw(), caption, fmt))
    if animation is not None and animation.suffix.lower() == ".gif":
        parts.append(image_html(animation.read_bytes(), "Plan-view animation.", "gif"))
    parts.append(_foot(", ".join(str(r.path) for r in runs)))
    return "\n".join(parts) + "\n"


def sweep_html(
    sweep: Sweep, column: str | None = None, fmt: str = "png", images: dict[str, Path] | None = None,
    studies: Sequence[str] | None = None, **plot_options,
) -> str:  # fmt: skip
    """A sweep's report as one HTML document: its tables and every sweep plot."""
    from .sweep_data import select
    from .sweep_document import status_line as sweep_status, sweep_summary, sweep_tables
    from .sweep_plots import sweep_figures

    if fmt not in ("png", "svg"):
        raise InputError(f"the HTML report embeds png or svg images, not {fmt}", field="--format")
    sweep = select(sweep, studies)
    doc = sweep_summary(sweep)
    parts = [_head(f"sweep {sweep.title}")]
    warning = sweep_status(doc)
    if warning:
        parts.append(f'<p class="failed">{html.escape(warning)}</p>')
    parts += [table_html(spec) for spec in sweep_tables(doc, column)]
    parts.append("<h2>Plots</h2>")
    for stem, draw in sweep_figures(sweep, column=column, **plot_options).items():
        done = (images or {}).get(stem)
        caption = sweep_caption(stem)
        parts.append(image_html(done.read_bytes(), caption, fmt) if done else figure_html(draw(), caption, fmt))
    parts.append(_foot(str(sweep.folder)))
    return "\n".join(parts) + "\n"


def sweep_caption(stem: str) -> str:
    """The caption of a sweep figure, from its file stem (see :mod:`.sweep_plots`)."""
    if stem.startswith("sweep-cases"):
        return "Peak interstorey deflections of the cases, side by side (the paper's figures 6 and 7)" + (
            f": study {stem.removeprefix('sweep-cases-')}." if stem != "sweep-cases" else ".")
    kind = {"polar": "around a circle, against the angle", "impacts": "impacts and peak impact force",
            "columns": "the chosen summary columns"}.get(stem.rsplit("-", 1)[-1])  # fmt: skip
    return f"{stem}: " + (kind or "peak interstorey deflections against the swept parameter (the paper's figure 8)") + "."


def _head(title: str) -> str:
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>pound report: "
            f"{html.escape(title)}</title><style>{STYLE}</style></head><body>\n"
            f"<h1>pound report: {html.escape(title)}</h1>")  # fmt: skip


def _foot(sources: str) -> str:
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return f"<p><small>Written by pound {__version__} on {stamp} from {html.escape(sources)}.</small></p></body></html>"


def write_html(runs: Sequence[Run], path: str | Path, **options) -> Path:
    """Write :func:`report_html` of `runs` to `path` (its folder must exist); returns the path."""
    return write_text(path, lambda: report_html(runs, **options))


def write_sweep_html(sweep: Sweep, path: str | Path, **options) -> Path:
    """Write :func:`sweep_html` to `path` (its folder must exist); returns the path."""
    return write_text(path, lambda: sweep_html(sweep, **options))


def write_text(path: str | Path, text: Callable[[], str]) -> Path:
    """Check `path`, then write `text()` to it atomically."""
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"the folder {str(path.parent)!r} does not exist; create it first", file=path)
    if path.is_dir():
        raise InputError("is a folder; give a file name for the report, e.g. report.html", file=path)
    return write_atomically(path, text())
