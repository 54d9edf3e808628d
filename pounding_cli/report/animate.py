"""Animation: the plan view of one level or of all levels through time, as a GIF (or MP4
where ffmpeg is installed).

Each frame is a stored output sample: slabs displaced × a stated factor (as in
:mod:`.plan`), slabs in contact outlined in red (an impact-log episode overlapping the
frame's time span, so impacts shorter than the output interval still show), and below, the
ground acceleration with a moving time cursor. Kept short and small by default: a window of
:data:`DEFAULT_WINDOW_S` around the instant of peak impact force, at most
:data:`DEFAULT_MAX_FRAMES` frames (a frame stride of several samples if needed), 12 frames a
second, 80 dpi.
"""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..errors import InputError
from .document import G
from .geometry import nice_magnification, plan_geometry
from .load import Run
from .plan import LevelView, peak_instant, select_levels, touched
from .style import IMPACT_COLOUR, figure

DEFAULT_WINDOW_S = 6.0
"""Length of the default window, s of model time, centred on the instant of peak impact force."""
DEFAULT_MAX_FRAMES = 120
"""Most frames written by default (10 s at 12 frames a second)."""
DEFAULT_FPS = 12
"""Frames per second of the file."""
DPI = 80
"""Resolution: the default frame is 512 px wide."""
SUFFIXES = (".gif", ".mp4")


def frame_indices(
    run: Run, start: float | None = None, end: float | None = None, stride: int | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
) -> np.ndarray:  # fmt: skip
    """Indices of the stored samples drawn as frames: every `stride`-th sample from `start` to
    `end` (s; default the window around the peak instant), at most `max_frames` of them (the
    stride grows to fit when it is not given; a given stride keeps the first `max_frames`)."""
    time = run.result.time
    if time.size == 0:
        return np.zeros(0, dtype=int)
    if start is None and end is None:
        t = peak_instant(run, plan_geometry(run)).t
        start, end = t - DEFAULT_WINDOW_S / 2, t + DEFAULT_WINDOW_S / 2
        if start < time[0]:
            start, end = float(time[0]), float(time[0]) + DEFAULT_WINDOW_S
        if end > time[-1]:
            start, end = max(float(time[0]), float(time[-1]) - DEFAULT_WINDOW_S), float(time[-1])
    start = float(time[0]) if start is None else start
    end = float(time[-1]) if end is None else end
    if end < start:
        raise InputError(f"the window ends ({end:g} s) before it starts ({start:g} s)", field="--end")
    i0 = int(np.searchsorted(time, start - 1e-9))
    i1 = int(np.searchsorted(time, end + 1e-9, side="right")) - 1
    if i1 < i0:
        raise InputError(f"no stored sample between {start:g} and {end:g} s (the run spans 0 to {time[-1]:g} s)",
                         field="--start")  # fmt: skip
    count = i1 - i0 + 1
    step = stride or max(1, math.ceil(count / max_frames))
    return np.arange(i0, i1 + 1, step)[:max_frames]


def _check_target(path: Path) -> None:
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise InputError(f"cannot write a {path.suffix or 'suffix-less'} animation; name a .gif or .mp4 file", file=path)
    if not path.parent.is_dir():
        raise InputError(f"the folder {str(path.parent)!r} does not exist; create it first", file=path)
    if path.is_dir():
        raise InputError("is a folder; give a file name for the animation, e.g. plan.gif", file=path)
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InputError("writing .mp4 needs ffmpeg, which is not installed; write a .gif instead", file=path)


def animate_plan(
    run: Run, path: str | Path, level: int | None = None, magnify: float | None = None,
    start: float | None = None, end: float | None = None, stride: int | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES, fps: int = DEFAULT_FPS,
) -> int:  # fmt: skip
    """Write the plan-view animation of `run` to `path` (.gif or .mp4) and return the number
    of frames: one level (1-based) or all, displacements × `magnify` (default as the plan
    figure's), frames from :func:`frame_indices`."""
    path = Path(path)
    _check_target(path)
    frames = frame_indices(run, start, end, stride, max_frames)
    movie = PlanMovie(run, level, magnify, frames)
    images = movie.render()
    if path.suffix.lower() == ".gif":
        _write_gif(images, path, fps)
    else:
        _write_mp4(images, path, fps, movie.size)
    return int(frames.size)


class PlanMovie:
    """The animation's figure: level views, the ground-motion strip and its cursor; renders
    frames by redrawing only what moves over a saved background."""

    def __init__(self, run: Run, level: int | None, magnify: float | None, frames: np.ndarray):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        self.run, self.frames = run, frames
        geometry = plan_geometry(run)
        self.magnify = magnify or nice_magnification(run, geometry)
        chosen = select_levels(geometry, [level] if level else None)
        lo, hi = geometry.extent()
        size = float(np.max(hi - lo))
        ncols = 1 if len(chosen) == 1 else 2
        nrows = -(-len(chosen) // ncols)
        aspect = float((hi - lo)[1] + 0.2 * size) / float((hi - lo)[0] + 0.2 * size)
        self.fig = figure(6.4, min(9.0, (6.4 / ncols) * aspect * nrows + 2.2))
        self.fig.set_dpi(DPI)
        FigureCanvasAgg(self.fig)
        grid = self.fig.add_gridspec(nrows + 1, ncols, height_ratios=[*([1.0] * nrows), 0.45])
        self.views = []
        for i, (k, z) in enumerate(chosen):
            ax = self.fig.add_subplot(grid[i // ncols, i % ncols])
            self.views.append(LevelView(ax, run, geometry, z, self.magnify, margin=0.1 * size))
            ax.set_title(f"level {k}: {z:g} m", fontsize="small")
            if len(chosen) > 2:
                ax.set_xlabel("")
                ax.tick_params(labelsize="x-small")
        self._strip(grid[nrows, :])
        self.title = self.fig.suptitle("", fontsize="small")

    def _strip(self, cell) -> None:
        r = self.run.result
        strip = self.fig.add_subplot(cell)
        window = slice(int(self.frames[0]), int(self.frames[-1]) + 1) if self.frames.size else slice(0, 0)
        for k, name in enumerate("XY"):
            strip.plot(r.time[window], r.ground_acceleration[window, k] / G, lw=0.6, label=f"a_{name}")
        strip.set_xlabel("time (s)")
        strip.set_ylabel("ground (g)", fontsize="small")
        strip.legend(loc="upper right", fontsize="x-small", ncols=2)
        self.cursor = strip.axvline(r.time[self.frames[0]] if self.frames.size else 0.0, color="k", lw=1.2)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of a frame in pixels."""
        w, h = self.fig.canvas.get_width_height()
        return int(w), int(h)

    def _moving(self) -> list:
        out = [self.cursor, self.title]
        for view in self.views:
            out += [*view.patches, view.centres]
        return out

    def _update(self, i: int) -> None:
        r = self.run.result
        events = r.contact.events
        t = float(r.time[i])
        half = 0.5 * float(r.time[self.frames[1]] - r.time[self.frames[0]]) if self.frames.size > 1 else 0.0
        ends = np.where(np.isnan(events["t_end"]), np.inf, events["t_end"])
        active = events[(events["t_start"] <= t + half) & (ends >= t - half)]
        touching = set().union(*(touched((str(e["body_a"]), int(e["level"])), (str(e["body_b"]), int(e["floor_b"])),
                                         int(e["storey_b"])) for e in active))  # fmt: skip
        for view in self.views:
            view.update(t, touching)
        self.cursor.set_xdata([t, t])
        note = f"; in contact: {len(active)} pair" + ("s" if len(active) > 1 else "") if active.size else ""
        self.title.set_text(f"t = {t:6.2f} s; displacements × {self.magnify:g}{note}")
        self.title.set_color(IMPACT_COLOUR if active.size else "k")

    def render(self) -> list[np.ndarray]:
        """Every frame as an (h, w, 3) uint8 RGB image."""
        canvas = self.fig.canvas
        if self.frames.size:
            self._update(int(self.frames[0]))
        canvas.draw()  # lay out once, with the first frame's artists in place
        self.fig.set_layout_engine("none")
        moving = self._moving()
        for artist in moving:
            artist.set_animated(True)
        canvas.draw()
        background = canvas.copy_from_bbox(self.fig.bbox)
        images = []
        for i in self.frames:
            canvas.restore_region(background)
            self._update(int(i))
            for artist in moving:
                self.fig.draw_artist(artist)
            images.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
        return images


def _palette(images: list[np.ndarray], colours: int = 64):
    """One adaptive palette for every frame: from a mosaic of up to 24 frames spread over the
    animation, plus a swatch of the contact colour so that red outlines stay red."""
    from matplotlib.colors import to_rgb
    from PIL import Image

    picks = images[:: max(1, len(images) // 24)]
    swatch = np.zeros((8, images[0].shape[1], 3), dtype=np.uint8)
    swatch[:] = np.round(255 * np.array(to_rgb(IMPACT_COLOUR)))
    mosaic = np.concatenate([*picks, swatch])
    return Image.fromarray(mosaic).quantize(colors=colours, method=Image.Quantize.MEDIANCUT)


def _write_gif(images: list[np.ndarray], path: Path, fps: int) -> None:
    """A looping GIF whose frames share one adaptive palette of 64 colours."""
    from PIL import Image

    if not images:
        raise InputError("no frames to write", file=path)
    palette = _palette(images)
    frames = [Image.fromarray(a).quantize(palette=palette, dither=Image.Dither.NONE) for a in images]
    with atomic_path(path) as tmp:
        frames[0].save(tmp, format="GIF", save_all=True, append_images=frames[1:], duration=round(1000 / fps), loop=0)


def _write_mp4(images: list[np.ndarray], path: Path, fps: int, size: tuple[int, int]) -> None:
    """An H.264 MP4 by piping the raw frames through ffmpeg, which writes the temporary file
    (its container named by -f, as the temporary name has no .mp4 suffix)."""
    w, h = size
    with atomic_path(path) as tmp:
        command = [shutil.which("ffmpeg") or "ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo",
                   "-pix_fmt", "rgb24", "-s", f"{w}x{h}", "-r", str(fps), "-i", "-",
                   "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-vcodec", "libx264",
                   "-f", "mp4", str(tmp)]  # fmt: skip
        done = subprocess.run(command, input=b"".join(a.tobytes() for a in images), capture_output=True, check=False)
        if done.returncode != 0:
            raise InputError(f"ffmpeg failed: {done.stderr.decode(errors='replace').strip()[:300]}", file=path)
