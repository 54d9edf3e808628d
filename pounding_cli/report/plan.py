"""Plot: a plan view of every diaphragm at the instant of peak impact force.

One panel per level (distinct floor elevation). Each slab is drawn at rest (dashed) and
displaced (filled), its displacement relative to the ground multiplied by a stated factor so
that millimetres show on a plan of metres; obstacles are hatched. Slabs in contact are
outlined in red; at the contact, the action point (the overlap's centroid) and arrows of the
normal force F_N and tangential force F_T on body B.

Which instant, and where the numbers come from:

1. if some output sample caught a contact, the sample with the largest total normal force:
   positions, action points, F_N and F_T are that sample's stored values;
2. otherwise (impacts shorter than the output interval) the peak of the impact log's largest
   episode: its t_peak, action point, peak F_N, the tangential force F_T and the normal n at
   that step are exact (the solver's own values); the positions are interpolated linearly
   between samples. A file written before the log kept F_T and n draws no F_T and
   recomputes the normal from the interpolated outlines (perpendicular to the line through
   the two points where they cross, or along the shortest segment between them if they no
   longer overlap);
3. without impacts, the instant of the largest floor displacement.

The drawn action point moves with the magnified slabs (by the mean of the two bodies'
displacements there). Lengths in m, forces in MN.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..assembly.levels import LEVEL_TOLERANCE
from ..results.sparse import held
from .geometry import (
    PlanGeometry, displacement_at, moved, nice_magnification, plan_geometry, point_displacement, storey_displacement_at,
)  # fmt: skip
from .load import Run
from .style import IMPACT_COLOUR, colour, figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

ARROW_FRACTION = 0.18
"""Length of the largest force arrow, as a fraction of the plan's size."""


@dataclass
class ContactMark:
    """A contact drawn at the instant: where, which way, how strong (on body B)."""

    pair: int
    a: tuple[str, int]  # (body, floor) of A
    b: tuple[str, int]  # (body, floor) of B; floor 0 for an obstacle
    point: np.ndarray  # action point, global, m (true position)
    normal: np.ndarray  # unit normal from A into B
    f_normal: float  # N
    f_tangential: float | None  # N along t = ẑ × n; None if not known at the instant


@dataclass
class Instant:
    """The instant a plan view shows, why, and the contacts at it."""

    t: float  # s
    source: str  # "histories", "log" or "response"
    description: str
    contacts: list[ContactMark] = field(default_factory=list)


def _pair_bodies(pair: np.void) -> tuple[tuple[str, int], tuple[str, int]]:
    return (str(pair["body_a"]), int(pair["floor_a"])), (str(pair["body_b"]), int(pair["floor_b"]))


def touched(a: tuple[str, int], b: tuple[str, int], storey: int) -> set[tuple[str, int]]:
    """What a contact touches, as LevelView.update takes it: (building, floor) of each slab, and
    for a storey struck between two floors (storey > 0) (building, −storey) instead of B's."""
    return {a, (b[0], -storey) if storey else b}


def _outline(run: Run, geometry: PlanGeometry, body: tuple[str, int], t: float) -> np.ndarray:
    """True (unmagnified) outline of a slab or an obstacle at time t."""
    name, floor = body
    if floor == 0:
        return next(o.outline for o in geometry.obstacles if o.name == name)
    slab = geometry.slab(name, floor)
    return moved(slab, displacement_at(run, name, floor, t))


def contact_normal(poly_a: np.ndarray, poly_b: np.ndarray) -> np.ndarray:
    """Unit normal from A into B: perpendicular to the line through the two points where the
    outlines cross (paper 4.2; where they run together, the middle of that stretch), or
    along the shortest segment from A to B if they are apart."""
    import shapely
    from shapely.ops import nearest_points

    a, b = shapely.Polygon(poly_a), shapely.Polygon(poly_b)
    towards = np.asarray(b.centroid.coords[0]) - np.asarray(a.centroid.coords[0])
    n = towards
    if a.intersection(b).area > 0:
        # each crossing is a point, or a stretch where the outlines run together: its midpoint
        parts = shapely.get_parts(a.exterior.intersection(b.exterior))
        crossing = np.array([p.interpolate(0.5, normalized=True).coords[0] if p.length > 0 else p.coords[0]
                             for p in parts if not p.is_empty]).reshape(-1, 2)  # fmt: skip
        if len(crossing) >= 2:
            d = crossing[:, None, :] - crossing[None, :, :]
            i, j = np.unravel_index(np.argmax((d**2).sum(axis=2)), d.shape[:2])
            p = crossing[j] - crossing[i]
            n = np.array([-p[1], p[0]])
    else:
        pa, pb = nearest_points(a, b)
        gap = np.array(pb.coords[0]) - np.array(pa.coords[0])
        if np.hypot(*gap) > 0:
            n = gap
    n = n / (np.hypot(*n) or 1.0)
    return n if n @ towards >= 0 else -n


def peak_instant(run: Run, geometry: PlanGeometry) -> Instant:
    """The instant of peak impact force (see the module's docstring for the three cases)."""
    r, c = run.result, run.result.contact
    f_n = held(c.normal_force)  # the pairs that touched: a few columns of a district's thousands
    if f_n.values.size and (f_n.values > 0).any():
        k = int(np.argmax(f_n.values.sum(axis=1)))
        t = float(r.time[k])
        marks = []
        point, f_t = held(c.action_point).row(k), held(c.tangential_force).row(k)
        for p in f_n.columns[f_n.values[k] > 0]:
            a, b = _pair_bodies(c.pairs[p])
            normal = contact_normal(_outline(run, geometry, a, t), _outline(run, geometry, b, t))
            marks.append(ContactMark(int(p), a, b, point[p], normal, float(f_n.column(p)[k]), float(f_t[p])))
        total = sum(m.f_normal for m in marks)
        text = f"largest sampled impact force {total / 1e6:.3g} MN"
        if c.events.size and c.peak_force > 1.001 * total:
            text += f" (the log's peak, between samples: {c.peak_force / 1e6:.3g} MN)"
        return Instant(t, "histories", text, marks)
    if c.events.size:
        e = c.events[int(np.argmax(c.events["peak_normal_force"]))]
        t = float(e["t_peak"])
        a, b = _pair_bodies(c.pairs[int(e["pair"])])
        point = np.array([float(e["x"]), float(e["y"])])
        logged = bool(np.isfinite(e["tangential_force_at_peak"]))  # files of older versions lack F_T and n
        if logged:
            normal, f_t = np.array([float(e["normal_x"]), float(e["normal_y"])]), float(e["tangential_force_at_peak"])
        else:
            normal, f_t = contact_normal(_outline(run, geometry, a, t), _outline(run, geometry, b, t)), None
        mark = ContactMark(int(e["pair"]), a, b, point, normal, float(e["peak_normal_force"]), f_t)
        source = "impact log" if logged else "impact log; F_T not logged"
        return Instant(t, "log", f"peak impact force {mark.f_normal / 1e6:.3g} MN ({source})", [mark])
    best, t = -1.0, float(r.time[0]) if r.time.size else 0.0
    for b in r.buildings.values():
        amp = np.hypot(b.displacement[:, :, 0], b.displacement[:, :, 1]).max(axis=1)
        if amp.size and amp.max() > best:
            best, t = float(amp.max()), float(r.time[int(np.argmax(amp))])
    return Instant(t, "response", f"no impacts: largest floor displacement {1e3 * max(best, 0):.3g} mm")


class LevelView:
    """The slabs and obstacles of one level on one axes, movable to any time (used by the
    plan figure once and by the animation every frame)."""

    def __init__(self, ax: Axes, run: Run, geometry: PlanGeometry, z: float, magnify: float, margin: float):
        """Draw level `z` (m) of `geometry` on `ax`, limits: the whole plan's extent ± `margin` (m)."""
        from matplotlib.colors import to_rgba
        from matplotlib.patches import Polygon

        self.run, self.magnify = run, magnify
        self.slabs, obstacles = geometry.at_level(z)
        names = list(run.result.buildings)
        for o in obstacles:
            ax.add_patch(Polygon(o.outline, closed=True, facecolor="0.85", edgecolor="0.4", hatch="///", lw=0.8))
        self.patches, self.edges = [], []
        for s in self.slabs:
            ax.plot(*np.vstack([s.outline, s.outline[:1]]).T, ls="--", lw=0.6, color="0.5")
            edge = colour(names.index(s.building))
            patch = Polygon(s.outline, closed=True, facecolor=to_rgba(edge, 0.35), edgecolor=edge, lw=1.2)
            ax.add_patch(patch)
            self.patches.append(patch)
            self.edges.append(edge)
        # the storeys that this level's slabs strike between a neighbour's floors: the outline of
        # the floor above, moving with the storey at ξ (dotted)
        self.storeys = []
        for pair in run.result.contact.pairs:
            if int(pair["storey_b"]) and abs(float(pair["elevation"]) - z) < LEVEL_TOLERANCE:
                key = (str(pair["body_b"]), int(pair["storey_b"]), float(pair["xi"]))
                if key in [k for k, _ in self.storeys]:
                    continue
                slab = geometry.slab(key[0], key[1])
                edge = colour(names.index(key[0]))
                patch = Polygon(slab.outline, closed=True, fill=False, edgecolor=edge, lw=1.2, ls=":")
                ax.add_patch(patch)
                ax.annotate(f"{key[0]} storey {key[1]} (ξ {key[2]:.2f})", xy=slab.outline.mean(axis=0), ha="center",
                            va="center", fontsize="x-small", color=edge)  # fmt: skip
                self.storeys.append((key, patch))
        self.geometry = geometry
        (self.centres,) = ax.plot([], [], "k.", ms=4)
        lo, hi = geometry.extent()
        lo, hi = lo - margin, hi + margin
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_title(f"level at {z:g} m", fontsize="small")
        ax.set_xlabel("X (m)")
        ax.set_ylabel("Y (m)")

    def update(self, t: float, touching: set[tuple[str, int]] = frozenset()) -> None:
        """Move every slab to time t (s); outline in red the (building, floor)s in `touching`."""
        centres = []
        for s, patch, edge in zip(self.slabs, self.patches, self.edges):
            u = displacement_at(self.run, s.building, s.floor, t)
            patch.set_xy(moved(s, u, self.magnify))
            hit = (s.building, s.floor) in touching
            patch.set_edgecolor(IMPACT_COLOUR if hit else edge)
            patch.set_linewidth(2.2 if hit else 1.2)
            centres.append(s.centre + self.magnify * u[:2])
        for (building, storey, xi), patch in self.storeys:
            slab = self.geometry.slab(building, storey)
            patch.set_xy(moved(slab, storey_displacement_at(self.run, self.geometry, building, storey, xi, t), self.magnify))
            hit = (building, -storey) in touching
            patch.set_edgecolor(IMPACT_COLOUR if hit else colour(list(self.run.result.buildings).index(building)))
        if centres:
            self.centres.set_data(*np.array(centres).T)


def drawn_point(run: Run, geometry: PlanGeometry, mark: ContactMark, t: float, magnify: float) -> np.ndarray:
    """Where the action point is drawn: carried by the mean magnified motion of A and B there."""
    shift = np.zeros(2)
    for name, floor in (mark.a, mark.b):
        if floor:
            shift += point_displacement(geometry.slab(name, floor), displacement_at(run, name, floor, t), mark.point)
    return mark.point + (magnify - 1) * shift / 2


def draw_contacts(ax: Axes, run: Run, geometry: PlanGeometry, instant: Instant, marks: Sequence[ContactMark],
                  magnify: float, scale: float) -> None:  # fmt: skip
    """Action points and force arrows (on body B; `scale` m per N)."""
    for mark in marks:
        p = drawn_point(run, geometry, mark, instant.t, magnify)
        ax.plot(*p, marker="*", color="k", ms=11, ls="none", label="action point", zorder=5)
        n = mark.normal
        arrows = [(n * mark.f_normal, IMPACT_COLOUR, f"F_N = {mark.f_normal / 1e6:.3g} MN")]
        if mark.f_tangential is not None:
            t_dir = np.array([-n[1], n[0]])
            arrows.append((t_dir * mark.f_tangential, "tab:purple", f"F_T = {mark.f_tangential / 1e6:.3g} MN"))
        for force, col, label in arrows:
            d = force * scale
            if np.hypot(*d) > 0:
                ax.annotate("", xy=p + d, xytext=p, zorder=6,
                            arrowprops=dict(arrowstyle="-|>", color=col, lw=2.0, mutation_scale=14))  # fmt: skip
            ax.plot([], [], color=col, lw=2.0, label=label)


def plan_figure(
    run: Run, magnify: float | None = None, levels: Sequence[int] | None = None, geometry: PlanGeometry | None = None
) -> Figure:
    """Plan views of the levels (1-based; default all) at the instant of peak impact force,
    displacements × `magnify` (default: a round factor drawing the largest displacement at
    about 5 % of the plan)."""
    geometry = geometry or plan_geometry(run)
    magnify = magnify or nice_magnification(run, geometry)
    instant = peak_instant(run, geometry)
    chosen = select_levels(geometry, levels)
    lo, hi = geometry.extent()
    size = float(np.max(hi - lo))
    ncols = 1 if len(chosen) == 1 else 2
    nrows = -(-len(chosen) // ncols)
    aspect = float((hi - lo)[1] + 0.2 * size) / float((hi - lo)[0] + 0.2 * size)
    fig = figure(5.0 * ncols, max(2.5, 5.0 * aspect + 0.8) * nrows + 0.6)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    pairs = run.result.contact.pairs
    touching = set().union(*(touched(m.a, m.b, int(pairs[m.pair]["storey_b"])) for m in instant.contacts))
    fmax = max((max(abs(m.f_normal), abs(m.f_tangential or 0.0)) for m in instant.contacts), default=0.0)
    scale = ARROW_FRACTION * size / fmax if fmax > 0 else 0.0
    for ax, (k, z) in zip(axes, chosen):
        view = LevelView(ax, run, geometry, z, magnify, margin=0.1 * size)
        view.update(instant.t, touching)
        here = [m for m in instant.contacts if any(s.building == m.a[0] and s.floor == m.a[1] for s in view.slabs)]
        draw_contacts(ax, run, geometry, instant, here, magnify, scale)
        ax.set_title(f"level {k}: {z:g} m" + (" (contact)" if here else ""), fontsize="small",
                     color=IMPACT_COLOUR if here else "k")  # fmt: skip
    for ax in axes[len(chosen):]:
        ax.set_visible(False)
    handles = {label: h for ax in axes for h, label in zip(*ax.get_legend_handles_labels())}
    if handles:
        fig.legend(handles.values(), handles.keys(), loc="outside lower center", ncols=len(handles), fontsize="small")
    fig.suptitle(f"Plan at t = {instant.t:.4f} s: {instant.description}; displacements × {magnify:g}",
                 fontsize="medium")  # fmt: skip
    return fig


def select_levels(geometry: PlanGeometry, levels: Sequence[int] | None) -> list[tuple[int, float]]:
    """(level number, elevation m) of the chosen levels (1-based), all by default."""
    from ..errors import InputError

    all_levels = geometry.levels
    if not levels:
        return list(enumerate(all_levels, start=1))
    bad = [k for k in levels if not 1 <= k <= len(all_levels)]
    if bad:
        raise InputError(f"level {bad[0]} does not exist: the run has levels 1 to {len(all_levels)} "
                         f"(elevations {', '.join(f'{z:g}' for z in all_levels)} m)", field="--level")  # fmt: skip
    return [(k, all_levels[k - 1]) for k in levels]


