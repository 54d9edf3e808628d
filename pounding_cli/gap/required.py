"""`pound gap`: the separation each contact candidate needs over the record, exactly.

1. The model runs once with contact off (the floors' motion does not depend on where the
   buildings stand: the ground motion is the same under all of them), its histories stored
   every SAMPLE s at most (the exact integrator's states: exact to rounding).
2. For each candidate pair (slab–slab, slab–obstacle, slab–storey; assembly/levels.py), the
   direction n is that of its clear distance at rest, from A's closest point to B's
   (gap.rest). Moving B by σ·n at rest moves it by σ·n at every instant, so the pair meets at
   time t exactly when σ ≤ σ*(t), the largest push along n at which the moving outlines still
   meet (approach.push_out, a ray cast on their Minkowski difference). The pair never meets
   over the record when the gap exceeds

       required = clear distance at rest + max_t σ*(t),

   reached at the time of closest approach t*; margin = clear distance − required (< 0:
   they meet at the given gap). σ* is taken at every stored sample, then the largest
   samples are refined between their neighbours on the quintic Hermite interpolant of the
   motion (motion.Motion.at), by bounded Brent search to REFINE_TOL s.
3. Beside it, the facing edges' peak advances u_A, u_B along n (approach.advance, torsion
   included), located the same way, and the code-style estimates ABS, SRSS, DDC
   (gap.codes) with the CQC ρ of the two buildings' fundamental modes along n.

A slab–storey pair is measured as the others (its storey's outline moving with s(ξ), as
the solver moves it: solver/storey_bodies.py); `simulated` says whether pound run simulates
the pair's contact (every kind does since issue 23's slice 2).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from .approach import advance, push_out
from .codes import cqc_correlation, estimates, fundamental_mode
from ..assembly.storey_contact import storey_shape
from .motion import Body, Motion, motion_of
from .rest import clearance

SAMPLE = 0.002
"""Longest interval (s) at which the contact-free run's motion is stored for pound gap: the
quintic between samples is then within (ω·h)⁶/46080 ≈ 1.6e-8 of a 160 rad/s mode's share."""

REFINE_TOL = 1e-9
"""Time tolerance (s) of the search for a crest between two samples."""

CRESTS = 3
"""Local maxima of σ*(t) (and of each edge's advance), largest first, refined between samples."""


@dataclass(frozen=True)
class PairGap:
    """One candidate pair's required separation and the code-style estimates beside it."""

    body_a: str
    floor_a: int  # 1-based floor of A's slab
    body_b: str
    floor_b: int  # 1-based floor of B's slab; 0 for an obstacle or a storey
    storey_b: int  # 1-based storey of B struck by A's slab; 0 for slab–slab and slab–obstacle
    kind: str  # "slab-slab", "slab-obstacle", "slab-storey"
    elevation: float  # m
    xi: float  # where in B's storey (slab–storey), else NaN
    clear_distance: float  # m, at rest
    direction: tuple[float, float]  # n, from A towards B, global
    required: float  # m: the smallest gap along n at which the pair never meets
    time: float  # s: time of closest approach
    margin: float  # m: clear_distance − required
    u_a: float  # m: peak advance of A's edge towards B
    u_b: float  # m: peak advance of B's edge towards A
    rho: float  # CQC correlation of the fundamental modes along n
    abs: float  # m
    srss: float  # m
    ddc: float  # m
    simulated: bool  # pound runs this pair's contact

    def as_dict(self) -> dict[str, Any]:
        out = asdict(self)
        out["direction"] = list(self.direction)
        out["xi"] = None if math.isnan(self.xi) else self.xi
        out.update({f"{k}_ratio": getattr(self, k) / self.required if self.required > 0 else None
                    for k in ("abs", "srss", "ddc")})  # fmt: skip
        return out


@dataclass(frozen=True)
class GapResult:
    """pound gap's answer: every candidate pair, the governing one, and the run behind it."""

    pairs: list[PairGap]
    time: np.ndarray  # (nt,) s, the samples
    approach: np.ndarray  # (nt, n_pairs): clear distance + σ*(t), m: the gap each pair needs at each sample
    sample: float  # s, the samples' interval
    run: Any  # the contact-free RunResult

    @property
    def governing(self) -> int | None:
        """Index of the pair with the least margin (None without pairs)."""
        return int(np.argmin([p.margin for p in self.pairs])) if self.pairs else None


def contact_free(loaded):  # type: ignore[no-untyped-def]
    """The model with contact off and histories every SAMPLE s at most."""
    m = contact_on(loaded, False).model
    interval = min(m.analysis.output_interval, SAMPLE)
    return replace(loaded, model=m.model_copy(update={"analysis": m.analysis.model_copy(update={"output_interval": interval})}))


def contact_on(loaded, enabled: bool = True):  # type: ignore[no-untyped-def]
    """The model with contact switched on (or off)."""
    m = loaded.model
    return replace(loaded, model=m.model_copy(update={"contact": m.contact.model_copy(update={"enabled": enabled})}))


def candidate_bodies(scene) -> list[tuple[dict[str, Any], Body, Body]]:  # type: ignore[no-untyped-def]
    """(identity, A, B) of every contact candidate of a prepared scene (contact on): its
    slab–slab and slab–obstacle pairs, then its slab–storey crossings."""
    system, contact = scene.system, scene.contact
    out = []
    for i, p in enumerate(contact.pairs):
        if p.storey:  # the crossings below
            continue
        ka, kb = int(contact.pair_a[i]), int(contact.pair_b[i])
        a, b = (_contact_body(contact, k) for k in (ka, kb))
        out.append((dict(body_a=p.body_a, floor_a=p.floor_a, body_b=p.body_b, floor_b=p.floor_b, storey_b=0, kind=p.kind,
                         elevation=p.elevation, xi=math.nan, simulated=True), a, b))  # fmt: skip
    for c in contact.crossings:
        slab_bld, struck = system.buildings[c.building], system.buildings[c.struck]
        f = int(system.floor_start[c.building]) + c.floor
        a = Body(slab_bld.slabs[c.floor], (f,), slab_bld.mass_centre[c.floor : c.floor + 1], (1.0,))
        top = int(system.floor_start[c.struck]) + c.storey - 1
        below = top - 1 if c.storey > 1 else -1
        centres = np.array([struck.mass_centre[max(c.storey - 2, 0)], struck.mass_centre[c.storey - 1]])
        s = storey_shape(c.xi)
        b = Body(struck.slabs[c.storey - 1], (below, top), centres, (1.0 - s, s))
        out.append((dict(body_a=slab_bld.name, floor_a=c.floor + 1, body_b=struck.name, floor_b=0, storey_b=c.storey,
                         kind="slab-storey", elevation=c.elevation, xi=c.xi, simulated=True), a, b))  # fmt: skip
    return out


def _contact_body(contact, k: int) -> Body:  # type: ignore[no-untyped-def]
    rest = contact.body_poly[k, : int(contact.body_nv[k])]
    f = int(contact.body_floor[k])
    if f < 0:
        return Body(rest, (), np.zeros((0, 2)), ())
    return Body(rest, (f,), contact.body_centre[k : k + 1], (1.0,))


def required_gaps(model, progress=None) -> GapResult:  # type: ignore[no-untyped-def]
    """pound gap's answer (module docstring) for a model: a path, a LoadedModel or a prepared
    Scene. A contact-free run that fails is AnalysisFailed (exit 1)."""
    from ..api import Scene, _loaded, execute, prepare
    from ..errors import AnalysisFailed

    scene = model if isinstance(model, Scene) else prepare(_loaded(model))
    if not scene.loaded.model.contact.enabled:  # the candidates are those contact on would check
        scene = prepare(contact_on(scene.loaded))
    free = prepare(contact_free(scene.loaded))
    run = execute(free, None, progress)
    if not run.complete:
        raise AnalysisFailed(f"{scene.loaded.source}: the run with contact off {run.status}")
    motion = motion_of(run, free.system)
    pairs, approach = [], []
    for ident, a, b in candidate_bodies(scene):
        rest = clearance(a.rest, b.rest)
        if rest.direction is None:
            continue  # touching at rest: no direction to open the gap along
        n = np.asarray(rest.direction)
        sigma = push_out(a.outlines(motion.u), b.outlines(motion.u), n)
        peak_sigma, t_star = _crest(sigma, motion, lambda u: push_out(a.outlines(u), b.outlines(u), n)[0])
        u_a = _peak_advance(a, motion, n)
        u_b = _peak_advance(b, motion, -n)
        rho = _correlation(scene, ident, n)
        required = rest.distance + peak_sigma
        approach.append(rest.distance + sigma)
        pairs.append(PairGap(**{k: v for k, v in ident.items() if k != "simulated"}, clear_distance=rest.distance,
                             direction=(float(n[0]), float(n[1])), required=required, time=t_star,
                             margin=rest.distance - required, u_a=u_a, u_b=u_b, rho=rho, **estimates(u_a, u_b, rho),
                             simulated=ident["simulated"]))  # fmt: skip
    table = np.column_stack(approach) if approach else np.zeros((motion.time.size, 0))
    return GapResult(pairs, motion.time, table, float(motion.time[1] - motion.time[0]), run)


def _crest(series: np.ndarray, motion: Motion, value) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """(largest value, its time) of a quantity sampled as `series` (nt,), refined between
    samples at its CRESTS largest local maxima; `value(u)` evaluates it at one motion u
    (1, n_floors, 3). −inf samples (never meeting) are never crests."""
    from scipy.optimize import minimize_scalar

    finite = np.where(np.isfinite(series), series, -np.inf)
    k_best = int(np.argmax(finite))
    best, t_best = float(finite[k_best]), float(motion.time[k_best])
    if not np.isfinite(best):
        return best, t_best
    left = np.concatenate([[-np.inf], finite[:-1]])
    right = np.concatenate([finite[1:], [-np.inf]])
    crests = np.flatnonzero((finite >= left) & (finite >= right) & np.isfinite(finite))
    for k in crests[np.argsort(finite[crests])[::-1][:CRESTS]]:
        lo, hi = motion.time[max(k - 1, 0)], motion.time[min(k + 1, motion.time.size - 1)]
        if hi <= lo:
            continue
        found = minimize_scalar(lambda t: -_finite(value(motion.at(t))), bounds=(lo, hi), method="bounded",
                                options={"xatol": REFINE_TOL})  # fmt: skip
        if -found.fun > best:
            best, t_best = float(-found.fun), float(found.x)
    return best, t_best


def _finite(x: float) -> float:
    return float(x) if np.isfinite(x) else -1e300


def _peak_advance(body: Body, motion: Motion, n: np.ndarray) -> float:
    """The peak |advance| along n of the body's edge facing along n (m), either way, refined
    between samples; 0 for a fixed body."""
    if not body.floors:
        return 0.0
    series = advance(body.outlines(motion.u), body.rest, n)
    return max(_crest(sign * series, motion, lambda u: sign * advance(body.outlines(u), body.rest, n)[0])[0]
               for sign in (1.0, -1.0))  # fmt: skip


def _correlation(scene, ident: dict[str, Any], n: np.ndarray) -> float:  # type: ignore[no-untyped-def]
    """ρ of the two buildings' fundamental modes along n (0 against an obstacle)."""
    by_name = {b.name: b for b in scene.system.buildings}
    if ident["body_b"] not in by_name:
        return 0.0
    a, b = by_name[ident["body_a"]], by_name[ident["body_b"]]
    (wa, za), (wb, zb) = (fundamental_mode(x.modes, x.mass, x.damping, n) for x in (a, b))
    return cqc_correlation(wa, za, wb, zb)
