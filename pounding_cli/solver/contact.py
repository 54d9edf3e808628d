"""Contact forces of the overlap-area impact model (paper section 4), compiled.

For every candidate pair (two floors at one level, or a floor and a fixed obstacle) whose
bounding boxes overlap (broad_phase.py: sweep and prune, or every pair tested), each step:
bounding circles; the deformed outlines; their overlap polygon
(clip_overlap) and contact frame (contact_frame: area A_c, centroid c, normal n from A into
B, tangent t = ẑ × n); then the impact law acting at c:

    F_N = k_N·A_c + c_N·s            s = −(v_B(c) − v_A(c))·n, the closing speed; F_N ≥ 0
    F_T ← F_T − k_T·Δu_T             Δu_T = Δt·(v_B(c) − v_A(c))·t, B's slip on A since the last
                                     step (velocities, c, the mass centres and t at t_{n−½}:
                                     _slip_over_step); the dashpots use v ≈ v_n
    F_T,total = F_T − c_T·(v_B(c) − v_A(c))·t
    stick while |F_T,total| ≤ μ_s·F_N; on exceeding it the contact slips with |F_T| = μ_k·F_N
    and keeps slipping (limit μ_k·F_N) until the trial force falls within μ_k·F_N again.

The dashpot switches on at the touch, a share s of the last step ago (share_since_crossing),
so the force jumps there from 0 to c_N·s. The CDM applies a step's force over the cell
[t_n − Δt/2, t_n + Δt/2]; at an episode's first step the dashpot term is weighted by s + ½,
its impulse from the touch to the cell's end (including the part in the cell before, which
had no force). Unweighted, the impulse was off by up to c_N·s·Δt/2 at every touch, and the
rebound converged to its restitution at first order in Δt; weighted, at second.

Each point of the contact line presses with k_N·depth, and its force has a kink where it
touches and where it parts. The midpoint rule of the cells misses J·Δt²·(σ − ½)²/2 of the
impulse of a force whose slope changes by J a share σ of a step before the nearest grid point
(kink_impulse): second order, but with a size set by where the kink falls in its step, which
made impacts' results jump about as the grid moved. Every step adds it for the points that
touched within the last step or part within the next (_shallow_impulse, over the overlap's
depth profile), and the first step after an episode for what parted after all (_add_parting);
where the dashpot's pull ends the force first, _add_end_impulse. Friction's events inside a
step are placed there too: stick's give (_kinetic_shortfall), sticking again
(_stick_shortfall), the first step's slip then stick (_stick_since_touch), and a stuck
contact's end (_fading_friction) (docs/theory.md §10, "The kinks").

The force on B is F_N·n + F_T·t, on A its opposite; on a floor it becomes (F_x, F_y, r × F)
with r = c − G (G the floor's displaced mass centre). The tangential state resets when the
overlap vanishes. Outlines move rigidly, P ↦ G + u + R(θ)·(P − G): the moment (c − G) × F
and the contact velocities v + θ̇·ẑ × (c − G) are then the work-conjugate forces and
velocities of that motion, so that a corner pushed into a face stores and gives back energy
at any turn (docs/theory.md §10). (The small-rotation map P + u + θ·ẑ × (P − G), used for the
structure, turns and stretches by √(1 + θ²): on the outlines it made turned contacts gain
energy.)

Each contact episode (first step with overlap to first step without) is one row of the
impact log. At the step of its peak normal force the row keeps, besides F_N, the action
point, the tangential force F_T on B along t and the normal n: the whole contact force at
that instant, whatever the output interval.
"""

from __future__ import annotations

import numpy as np
from .broad_phase import (
    boxes_may_meet_within,
    pairs_may_meet_within,
    _sort_ascending,
    pairs_to_visit,
    phase_pairs_to_visit,
    reach,
    reach_over,
)
from .jit import INTERNAL, kernel, phase
from .layout import (  # noqa: F401 (the layout is read through this module too)
    EV_COLUMNS,
    EV_FT_PEAK,
    EV_IMPULSE,
    EV_NX,
    EV_NY,
    EV_PAIR,
    EV_PEAK_AREA,
    EV_PEAK_DEPTH,
    EV_PEAK_FN,
    EV_PEAK_LENGTH,
    EV_SLID,
    EV_SLIPS,
    EV_T_END,
    EV_T_PEAK,
    EV_T_SLIP,
    EV_T_START,
    EV_T_STICK,
    EV_X,
    EV_Y,
    NOW_AREA,
    NOW_DEPTH,
    NOW_FN,
    NOW_FT,
    NOW_X,
    NOW_Y,
)
from .records import ClipWork
from .tunables import CLOSING_SAFETY

from .contact_geometry import (
    AREA,
    CX,
    CY,
    DEPTH,
    LENGTH,
    NX,
    NY,
    RESULT_SIZE,
    TX,
    TY,
    clip_overlap,
    contact_frame_xy,
    depth_profile,
    kink_impulse,
    shallow_moments,
)

# pair state columns, of the episode's last step: ST_FX, ST_FY, the force on B, N; ST_NX, ST_NY, the
# normal; ST_DEEPEST, the overlap's largest depth, m; ST_REST…+6, moments of the part of the
# overlap not expected to part within the next step (contact_geometry.shallow_moments: rest);
# ST_FN1, ST_FN2: the normal force one and two steps back, N (0 before the episode)
ST_ACTIVE, ST_FT, ST_SLIP, ST_EVENT, ST_FX, ST_FY, ST_NX, ST_NY, ST_DEEPEST, ST_REST = range(10)
ST_FN1, ST_FN2 = ST_REST + 6, ST_REST + 7
# ST_EXCESS: the trial |F_T| over μ_k·F_N, N, and ST_VT: B's tangential velocity on A at c, m/s,
# at the last step (where a slip ends between two steps: _tangential_force)
ST_EXCESS, ST_VT = ST_REST + 8, ST_REST + 9
# ST_RATE: the closing acceleration at c one step back, m/s² (cell_correction); ST_LAW_FN, ST_LAW_FT:
# the law's normal and tangential force then, N (the law's own values, which contact.now's
# reported ones differ from by half the hat's correction: cell_correction)
ST_RATE, ST_LAW_FN, ST_LAW_FT = ST_REST + 10, ST_REST + 11, ST_REST + 12
N_STATE = ST_REST + 13
FRAME_VERTICES = RESULT_SIZE
"""Where narrow_phase leaves the overlap polygon's vertex count in the frame vector."""


@kernel(inline="always")
def _deform(body, u, body_poly, body_nv, body_floor, body_centre, out):
    """Write body's displaced outline into out, turned rigidly by θ about its mass centre;
    returns its displaced reference point."""
    return _deform_before(body, u, u, 0.0, body_poly, body_nv, body_floor, body_centre, out)


@kernel(inline="always")
def _deform_before(body, u, v, back, body_poly, body_nv, body_floor, body_centre, out):
    """_deform at the displacements u − back·v (back s before, at velocity v)."""
    f = body_floor[body]
    gx = body_centre[body, 0]
    gy = body_centre[body, 1]
    if f < 0:
        for k in range(body_nv[body]):
            out[k, 0] = body_poly[body, k, 0]
            out[k, 1] = body_poly[body, k, 1]
        return gx, gy
    ux = u[3 * f] - back * v[3 * f]
    uy = u[3 * f + 1] - back * v[3 * f + 1]
    turn = u[3 * f + 2] - back * v[3 * f + 2]
    c = np.cos(turn)
    s = np.sin(turn)
    for k in range(body_nv[body]):
        dx = body_poly[body, k, 0] - gx
        dy = body_poly[body, k, 1] - gy
        out[k, 0] = gx + ux + c * dx - s * dy
        out[k, 1] = gy + uy + s * dx + c * dy
    return gx + ux, gy + uy


@kernel(inline="always")
def _point_velocity(f, cx, cy, gx, gy, v):
    """Velocity (m/s) of the material point of floor f at (cx, cy); zero for an obstacle."""
    if f < 0:
        return 0.0, 0.0
    w = v[3 * f + 2]
    return v[3 * f] - w * (cy - gy), v[3 * f + 1] + w * (cx - gx)


@kernel(inline="always")
def _slip_over_step(p, fa, fb, dt, cx, cy, tx, ty, gax, gay, gbx, gby, rel_x, rel_y, v_half, state, now):
    """B's slip on A along the contact's tangent over the last step, m: Δt·(v_B − v_A)·t at the
    step's midpoint, where v_{n−½} holds: the action point, the mass centres and the tangent
    halfway between the last step's and this one's. Taken at t_n instead, a turning contact's
    point and tangent are half a step ahead of the velocities: O(Δt²) a step, which the stuck
    spring sums into a first-order error. At an episode's first step there is no last frame:
    t_n's, with (rel_x, rel_y) = v_B − v_A at c by v_{n−½}."""
    if state[p, ST_ACTIVE] == 0:
        return dt * (rel_x * tx + rel_y * ty)
    mx = 0.5 * (cx + now[p, NOW_X])
    my = 0.5 * (cy + now[p, NOW_Y])
    mtx = tx - state[p, ST_NY]  # the last tangent: ẑ × n = (−n_y, n_x)
    mty = ty + state[p, ST_NX]
    size = np.sqrt(mtx * mtx + mty * mty)
    mtx /= size
    mty /= size
    half = 0.5 * dt
    ga_x = gax - half * v_half[3 * fa] if fa >= 0 else gax
    ga_y = gay - half * v_half[3 * fa + 1] if fa >= 0 else gay
    gb_x = gbx - half * v_half[3 * fb] if fb >= 0 else gbx
    gb_y = gby - half * v_half[3 * fb + 1] if fb >= 0 else gby
    vax, vay = _point_velocity(fa, mx, my, ga_x, ga_y, v_half)
    vbx, vby = _point_velocity(fb, mx, my, gb_x, gb_y, v_half)
    return dt * ((vbx - vax) * mtx + (vby - vay) * mty)


@kernel(inline="always")
def _apply(f, fx, fy, cx, cy, gx, gy, out):
    """Add the force (fx, fy) acting at (cx, cy) to floor f's generalized forces."""
    if f >= 0:
        out[3 * f] += fx
        out[3 * f + 1] += fy
        out[3 * f + 2] += (cx - gx) * fy - (cy - gy) * fx


@kernel(inline="always")
def _boxes_meet(a, b, u, body_floor, body_radius, body_box):
    """Broad phase: the displaced outlines' bounding boxes (rest box moved by u and widened
    by |θ|·r) overlap. Rejects neighbours whose gap is open in a few operations."""
    ax, ay, ar = reach(a, u, body_floor, body_radius)
    bx, by, br = reach(b, u, body_floor, body_radius)
    if body_box[a, 2] + ax + ar < body_box[b, 0] + bx - br:
        return False
    if body_box[b, 2] + bx + br < body_box[a, 0] + ax - ar:
        return False
    if body_box[a, 3] + ay + ar < body_box[b, 1] + by - br:
        return False
    if body_box[b, 3] + by + br < body_box[a, 1] + ay - ar:
        return False
    return True


@kernel(inline="always")
def _circles_meet(ax, ay, bx, by, radius_sum):
    """Broad phase: bounding circles about the displaced mass centres meet."""
    return (bx - ax) ** 2 + (by - ay) ** 2 <= radius_sum * radius_sum


@kernel(**INTERNAL)
def narrow_phase(a, b, u, body_poly, body_nv, body_floor, body_centre, gax, gay, gbx, gby, poly_a, poly_b,
                 clip, clip_label, tmp, tmp_label, frame):  # fmt: skip
    """Overlap of the displaced outlines of bodies a and b and its contact frame (into frame);
    True when they overlap. Kept out of line: the hot loop stays small when nothing touches."""
    _deform(a, u, body_poly, body_nv, body_floor, body_centre, poly_a)
    _deform(b, u, body_poly, body_nv, body_floor, body_centre, poly_b)
    m = clip_overlap(poly_a, body_nv[a], poly_b, body_nv[b], clip, clip_label, tmp, tmp_label)
    if m == 0:
        return False
    frame[FRAME_VERTICES] = m
    return contact_frame_xy(clip, clip_label, m, poly_a, body_nv[a], poly_b, body_nv[b], gax, gay, gbx, gby, frame)


@kernel(inline="always")
def _add_end_impulse(fall, held, p, fa, fb, gax, gay, gbx, gby, dt, state, now, events, forces):
    """Where the dashpot's pull cancelled pair p's spring `held` of a step after its last step,
    the normal force falling by `fall` N over a step, add what its last step missed
    (kink_impulse), at its action point and in the direction of its last force (friction fades
    with the normal force)."""
    if not (held > 0.0 and state[p, ST_LAW_FN] > 0.0):
        return
    missed = kink_impulse(fall, held)
    scale = missed / state[p, ST_LAW_FN]
    _apply(fb, scale * state[p, ST_FX], scale * state[p, ST_FY], now[p, NOW_X], now[p, NOW_Y], gbx, gby, forces)
    _apply(fa, -scale * state[p, ST_FX], -scale * state[p, ST_FY], now[p, NOW_X], now[p, NOW_Y], gax, gay, forces)
    e = int(state[p, ST_EVENT])
    if e < events.shape[0]:
        events[e, EV_IMPULSE] += missed * dt


@kernel(inline="always")
def _shallow_impulse(profile, n, k_n, closing, turning, whole, rest):
    """What the midpoint rule misses (N, over Δt) of the spring force k_N·depth of the points
    of the overlap's depth profile (contact_geometry.depth_profile: profile[:n]) no deeper than
    the depth they gained over the last step (so they touched within it), or lose over the next
    (so they part within it): `closing` at the action point, m, changing by `turning` per
    metre along t (the bodies' relative turning). Each such point's force has a kink a share
    σ = depth/closing of a step from this grid point, where the midpoint rule misses
    k_N·closing/2·(σ − ½)² per unit length (kink_impulse); summed by
    contact_geometry.shallow_moments (whole: at an episode's first step, every point is new).
    For faces meeting parallel this is the whole line at once; for a corner, the sliver at each
    tip, which makes the step's impulse that of the quadratically growing area; for faces
    turned by a small angle, the taper, whose couple k_N·L³·θ/12 would otherwise switch on and
    off a whole cell at a time (docs/theory.md §10, "The kinks"). Returns the impulse and its
    offset from the action point along t (m); leaves in rest the moments of the deeper part
    (_add_parting)."""
    i0, i1 = shallow_moments(profile, n, closing, turning, whole, rest)
    if not i0 > 0.0:
        return 0.0, 0.0
    return k_n * i0, i1 / i0


@kernel(inline="always")
def _slip_ratio(spring, force, f_n, mu_k, c_t):
    """F_T/F_N of a slipping contact (along t): the spring's force over F_N without a tangential
    dashpot (there it is ±μ_k·F_N); beside a dashpot the spring lags, and the slider's ±μ_k,
    with the sign of the friction `force`, is the ratio."""
    if c_t == 0.0:
        return spring / f_n
    return mu_k if force > 0.0 else -mu_k


@kernel(inline="always")
def _add_parting(p, opened, k_n, mu_s, mu_k, c_t, fa, fb, gax, gay, gbx, gby, dt, state, now, events, forces):
    """At the first step after an episode (without a dashpot), what the midpoint rule missed of
    the part of its last overlap that was expected to stay but parted, having opened by
    `opened` (m) over the step: Σ k_N·r/2·(σ − ½)², σ = depth/r, from the moments ∫1, ∫e, ∫e²
    (and with y) kept of that part, since r/2·(σ − ½)² = e²/(2r) − e/2 + r/8; along the last
    normal, at the offset along t they give, with a slipping contact's friction (±μ_k: the
    spring's force, or the slider's where a dashpot c_T > 0 stands beside it). Where the
    contact was still stuck, the friction's end too (_fading_friction)."""
    if not (opened > 0.0 and state[p, ST_LAW_FN] > 0.0):
        return
    r = opened
    i0 = state[p, ST_REST + 2] / (2.0 * r) - 0.5 * state[p, ST_REST + 1] + 0.125 * r * state[p, ST_REST]
    i1 = state[p, ST_REST + 5] / (2.0 * r) - 0.5 * state[p, ST_REST + 4] + 0.125 * r * state[p, ST_REST + 3]
    nx = state[p, ST_NX]
    ny = state[p, ST_NY]
    tx = -ny
    ty = nx
    cx = now[p, NOW_X]
    cy = now[p, NOW_Y]
    missed = k_n * i0
    if missed > 0.0:
        slipped = state[p, ST_SLIP] > 0
        along = _slip_ratio(state[p, ST_FT], state[p, ST_LAW_FT], state[p, ST_LAW_FN], mu_k, c_t) if slipped \
            else 0.0
        px = cx + i1 / i0 * tx
        py = cy + i1 / i0 * ty
        _apply(fb, missed * (nx + along * tx), missed * (ny + along * ty), px, py, gbx, gby, forces)
        _apply(fa, -missed * (nx + along * tx), -missed * (ny + along * ty), px, py, gax, gay, forces)
        e = int(state[p, ST_EVENT])
        if e < events.shape[0]:
            events[e, EV_IMPULSE] += missed * dt
    f_t = state[p, ST_LAW_FT]
    if state[p, ST_SLIP] == 0 and f_t != 0.0 and state[p, ST_DEEPEST] > 0.0:
        fade = _fading_friction(f_t, state[p, ST_LAW_FN], mu_s, mu_k, min(1.0, state[p, ST_DEEPEST] / r))
        _apply(fb, fade * tx, fade * ty, cx, cy, gbx, gby, forces)
        _apply(fa, -fade * tx, -fade * ty, cx, cy, gax, gay, forces)


@kernel(inline="always")
def _stick_since_touch(spring, f_n, mu_k, growth):
    """The tangential spring at an episode's first step, given `spring`, the stick force of the
    slip since the touch (−k_T·slip). The normal force grows from the touch as the power
    `growth` of time (the overlap's depth·length/area: 1 for a face, whose force grows
    linearly; 2 for a corner, whose area grows as depth²): faster than linearly, μ_s·F_N starts
    below any stick force, so the contact slips from the touch, and sticks again once μ_k·Ḟ_N
    has caught up with the spring's rate k_T·v_T, a share s of the time since the touch:
    μ_k·F_N·s^growth + |spring|·(1 − s) by now, stuck. Taking the spring from the step's end
    instead (stuck throughout, or slipping at μ_k·F_N) offsets it by up to k_T·v_T·Δt for the
    whole stick that follows: an error of first order in Δt, its size set by where the touch
    fell in its step. Returns (the spring, N; s, or −1 where it did not stick again)."""
    if not growth > 1.0 + 1e-6 or spring == 0.0:
        return spring, -1.0
    ratio = abs(spring) / (mu_k * f_n * growth) if mu_k > 0.0 else np.inf
    if ratio >= 1.0:  # still slipping (the slip law takes it from here)
        return spring, -1.0
    share = ratio ** (1.0 / (growth - 1.0))
    held = mu_k * f_n * share**growth + abs(spring) * (1.0 - share)
    return (held if spring > 0.0 else -held), share


@kernel(inline="always")
def _stick_shortfall(increment, mu_k, f_before, f_n, rise):
    """Where a slipping contact sticks again within the last step, the tangential spring, held
    at μ_k·F_N while slipping, grows by k_T·v_T from the instant t_s at which μ_k·Ḟ_N fell to
    k_T·v_T; counting the whole step's increment (k_T·v_T·Δt, N) from the last step's μ_k·F_N
    overstates it by −g(t_s) = min over the step of k_T·v_T·(t − t_{n−1}) − μ_k·(F_N(t) − F_N,n−1).
    F_N is taken quadratic over the step through the last step's and this step's values and
    this step's rise per step, k_N·length·(closing speed)·Δt (N). Returns (g(t_s) ≤ 0, N: second
    order in Δt, but with F_N's curvature, which at a corner's touch is F_N/τ², the error was
    as large as first order's, its size set by where the touch fell; (t_n − t_s)/Δt)."""
    curvature = 2.0 * (f_before - f_n + rise)  # F̈_N·Δt²
    if not (curvature > 0.0 and mu_k > 0.0):
        return 0.0, 0.0
    back = (rise - increment / mu_k) / curvature  # (t_n − t_s)/Δt, where μ_k·Ḟ_N = k_T·v_T
    if not 0.0 < back < 1.0:
        return 0.0, 0.0
    s = 1.0 - back  # (t_s − t_{n−1})/Δt
    f_s = f_n - rise * back + 0.5 * curvature * back * back
    return min(0.0, mu_k * (f_s - f_before) - increment * s), back


@kernel(inline="always")
def _slipping_spring(start, force_start, target, span, dt, k_t, c_t):
    """The tangential spring at the end of a step in which the contact slips (N), for friction
    whose spring k_T and dashpot c_T act side by side, in series with Coulomb's slider: while it
    slips, the pair carries the slider's force F = ±μ_k·F_N, so that the spring's force
    S = −k_T·e obeys k_T·e + c_T·ė = F, Ṡ = −(S − F)/τ with τ = c_T/k_T: it relaxes towards F
    and never jumps. The slider moves at v_T − ė and stops where the force S − c_T·v_T the pair
    would carry stuck falls within μ_k·F_N (the stick test of _tangential_force); there
    Ṡ = −k_T·v_T on either side, so the switch leaves S smooth. With F linear over the slip's
    span of the step, from `force_start` to `target` (F_N linear, the slip's sign fixed), and S
    `start` where the slip began, span·Δt before t_n (the last step, the touch, or where stick
    gave way within the step), exactly: with x = span·Δt/τ and r = (F_n − F₀)/x,
    S_n = F_n + (S₀ − F₀)·e^(−x) − r·(1 − e^(−x)). Holding F at its end value over the step, or
    relaxing over the whole step where the slip began within it, errs at first order in Δt
    (measured: the Kobe example with c_T = 2·10⁵ N·s/m converged at first order, 5.9 % off at the
    automatic step). Without a dashpot (τ = 0) S is F at once: the spring is held at ±μ_k·F_N.
    Holding it there with a dashpot beside it (the spring taking the sign of the slip whenever
    the dashpot's force outweighed it) made energy at every switch: that Kobe run failed its
    energy check at steps below 1/16 of the automatic one."""
    if c_t == 0.0:
        return target
    x = span * dt * k_t / c_t
    if not x > 0.0:
        return start
    decay = np.exp(-x)
    return target + (start - force_start) * decay - (target - force_start) * (-np.expm1(-x)) / x


@kernel(inline="always")
def _undamped(c_n, zeta):
    """The pair has no normal dashpot: its force ends where the overlap does (with one, where
    the dashpot's pull cancels the spring)."""
    return c_n == 0.0 and zeta == 0.0


@kernel(inline="always")
def _fading_friction(f_t, f_n, mu_s, mu_k, end):
    """What the CDM's tangential impulse misses, over Δt (N, along t), where a contact still
    stuck at a step parts `end` (0–1) of a step later: the normal force falls from f_n to zero
    (linearly), the stick gives way where μ_s·F_N falls to |f_t|, a share end·(1 − |f_t|/(μ_s·f_n))
    of the step on, and the friction μ_k·F_N then fades with it. The cell applies f_t over the
    whole step. Left alone, the friction's end, a jump to zero in the limit, falls up to half a
    step off: an error of first order in Δt whose sign follows where the break-away falls."""
    ratio = min(1.0, abs(f_t) / (mu_s * f_n)) if mu_s > 0.0 else 1.0
    give = end * (1.0 - ratio)
    sign = 1.0 if f_t > 0.0 else -1.0
    return f_t * (give - 0.5) + sign * mu_k * f_n * end * ratio * ratio / 2.0


@kernel(inline="always")
def _kinetic_shortfall(excess_before, excess_now, f_before, f_n, mu_s, mu_k):
    """Where stick gives way, the force drops from μ_s·F_N to μ_k·F_N at an instant t* inside
    the last step, located by the excess |F_T| − μ_s·F_N going from excess_before < 0 at the
    last step to excess_now > 0 now: φ = (t_n − t*)/Δt of the step was spent slipping. The
    CDM's force at t_n acts over [t_n − Δt/2, t_n + Δt/2]: for that window, or the one before
    it, to carry the impulse of the drop at t*, the step's friction is μ_k·F_N plus (½ − φ)
    times the stick force held before t* less μ_k·F_N over the same span, with F_N linear
    between f_before (the last step's) and f_n: (½ − φ)·(μ_s·F_N(t*) − μ_k·F_N over it)
    (this return value, N, along the slip). Switching at t_n instead misplaces the drop's
    impulse by (μ_s − μ_k)·F_N·Δt·(½ − φ), an error of first order in Δt, which dominated the
    Kobe run's convergence with μ_s > μ_k; sizing the drop with F_N at t_n was off by a quarter
    of it where F_N falls fast, at an impact's end."""
    if not excess_before < 0.0:  # (the state came from a slip: no better estimate than the step's end)
        return -0.5 * (mu_s - mu_k) * f_n
    give = excess_now / (excess_now - excess_before)  # φ
    fall = f_before - f_n
    return (0.5 - give) * (mu_s * (f_n + give * fall) - mu_k * (f_n + fall * (0.5 + give) / 2.0))


@kernel(inline="always")
def crest(f0, f1, f2):
    """The top of the parabola through three values a step apart, f1 ≥ f0 and f1 ≥ f2 (a
    sampled crest; it lies within half a step of the middle one). For a force smooth about
    its crest the error is third order in the step, where the largest sample itself misses by
    up to (ω·Δt)²/8 of the crest, as its place in the step falls."""
    curvature = 0.5 * (f0 + f2) - f1
    if curvature >= 0.0:
        return f1
    slope = 0.5 * (f2 - f0)
    return f1 - 0.25 * slope * slope / curvature


@phase
def _pair_frame(p, u, bodies, law, clip):
    """Narrow phase of pair p at u: (touching, displaced mass centres of A and B), with the
    overlap and its contact frame in clip.frame when they touch. Boxes first, then bounding
    circles about the displaced mass centres, then the clipped outlines (narrow_phase)."""
    a = law.a[p]
    b = law.b[p]
    fa = bodies.floor[a]
    fb = bodies.floor[b]
    gax = bodies.centre[a, 0] + (u[3 * fa] if fa >= 0 else 0.0)
    gay = bodies.centre[a, 1] + (u[3 * fa + 1] if fa >= 0 else 0.0)
    gbx = bodies.centre[b, 0] + (u[3 * fb] if fb >= 0 else 0.0)
    gby = bodies.centre[b, 1] + (u[3 * fb + 1] if fb >= 0 else 0.0)
    touching = False
    if _boxes_meet(a, b, u, bodies.floor, bodies.radius, bodies.box) and _circles_meet(
        gax, gay, gbx, gby, bodies.radius[a] + bodies.radius[b]
    ):
        touching = narrow_phase(a, b, u, bodies.poly, bodies.nv, bodies.floor, bodies.centre, gax, gay, gbx, gby,
                                clip.poly_a, clip.poly_b, clip.clip, clip.clip_label, clip.tmp, clip.tmp_label,
                                clip.frame)  # fmt: skip
    return touching, gax, gay, gbx, gby


@phase
def _end_episode(p, t_now, dt, u, v_half, gax, gay, gbx, gby, contact):
    """Pair p no longer touches: close its episode (if one was open) where the outlines parted
    within the step (share_since_crossing), with what the midpoint rule missed of its parting
    (_add_parting, without a dashpot), and reset its state."""
    state, now, events, law = contact.state, contact.now, contact.events, contact.law
    if not state[p, ST_ACTIVE] > 0:
        return
    a = law.a[p]
    b = law.b[p]
    fa = contact.bodies.floor[a]
    fb = contact.bodies.floor[b]
    g_now, g_before = gaps_along_step(a, b, dt, u, v_half, contact.bodies, contact.clip.poly_a, contact.clip.poly_b)
    if _undamped(law.c_n[p], law.zeta[p]):  # (with a dashpot the force ends where its pull cancels)
        _add_parting(p, g_now - g_before, law.k_n[p], law.mu_s[p], law.mu_k[p], law.c_t[p], fa, fb, gax, gay, gbx,
                     gby, dt, state, now, events, contact.force)  # fmt: skip
    e = int(state[p, ST_EVENT])
    if e < events.shape[0]:
        events[e, EV_T_END] = t_now - share_since_crossing(g_now, g_before) * dt
    state[p, ST_ACTIVE] = 0.0
    state[p, ST_FT] = 0.0
    state[p, ST_SLIP] = 0.0
    state[p, ST_FX] = 0.0
    state[p, ST_FY] = 0.0
    state[p, ST_LAW_FN] = 0.0
    state[p, ST_LAW_FT] = 0.0
    for k in range(now.shape[1]):
        now[p, k] = 0.0


@kernel(inline="always")
def cell_correction(k_n, length, damping, closing_rate, closing_jerk, dt):
    """What the central difference's step adds to the law's normal force at t_n, N, so that it
    applies the force's average over the step's hat rather than its value at t_n.

    The CDM's second difference weighs the force over t_n ± Δt by the hat 1 − |t − t_n|/Δt:
    u_{n+1} − 2u_n + u_{n−1} = Δt²·M⁻¹·(F + (Δt²/12)·F̈ + O(Δt⁴)). Applying F(t_n) alone
    leaves the contact's own vibration (ω² = k_N·ℓ/m) fast by (ω·Δt)²/24 of its frequency:
    the contact ends early by that share of its duration, the leading error of the contact
    phase (theory §10, "The force the step applies"). Each point of the contact line presses
    with k_N times its depth, so between the points' kinks (where they touch or part: the
    kink impulses) the spring's F̈ = k_N·ℓ·δ̈, ℓ the contact line (m), δ̈ the closing
    acceleration at the action point (m/s²): the last step's, from its Δv, less the change of
    this pair's normal force since over the pair's mass m (its own share of δ̈, which makes the
    contact's vibration; the rest, the structure's, taken a step late). With the last step's
    δ̈ alone the correction lags a step, an odd error of third order that breaks the leapfrog's
    symmetry (an elastic rebound lost (ω·Δt)³/12 of its speed); extrapolated from the last two
    steps' Δv it doubled the kink impulses those carry. The dashpot c·δ̇ reads the closing speed
    from v_{n−½} + Δv_{n−1}/2, which falls short of δ̇(t_n) by Δt²·δ⃛/3: with the hat's
    Δt²/12·δ⃛, (5/12)·Δt²·c·δ⃛, δ⃛ from the last two steps' δ̈ (m/s³; taken as −Ḟ/m from the
    change of force, the peak force with e = 0.8 was 9e-6 off at 4e-5 s against 8e-7)."""
    return dt * dt * (k_n * length * closing_rate / 12.0 + 5.0 / 12.0 * damping * closing_jerk)


@kernel(inline="always")
def _dashpot(p, law, length):
    """The normal dashpot of pair p, N·s/m: c_N, or 2ζ√(k_N·L·m) with the contact line L (m)."""
    damping = law.c_n[p]
    if law.zeta[p] > 0.0:
        damping += 2.0 * law.zeta[p] * np.sqrt(law.k_n[p] * length * law.m_eff[p])
    return damping


@phase
def _normal_force(p, share, v_n, gax, gay, gbx, gby, dt, contact):
    """F_N = k_N·A_c + c_N·s of pair p, never pulling (N): the dashpot (c_N, or 2ζ√(k_N·L·m))
    weighted by share + ½ at an episode's first step (module docstring); where its pull
    cancels the spring, the force ends within the step (_add_end_impulse)."""
    law, state, now, frame = contact.law, contact.state, contact.now, contact.clip.frame
    damping = _dashpot(p, law, frame[LENGTH])
    if share < 1.0:
        damping *= share + 0.5  # its impulse since the touch (module docstring)
    f_n = law.k_n[p] * frame[AREA] - damping * v_n
    if f_n < 0.0:  # the dashpot's pull cancels the spring: the force fell to zero within the step
        if state[p, ST_ACTIVE] > 0:
            fa = contact.bodies.floor[law.a[p]]
            fb = contact.bodies.floor[law.b[p]]
            last = state[p, ST_LAW_FN]
            _add_end_impulse(last - f_n, last / (last - f_n), p, fa, fb, gax, gay, gbx, gby, dt, state, now,
                             contact.events, contact.force)  # fmt: skip
        f_n = 0.0
    return f_n


@phase
def _tangential_force(p, share, f_n, slip_t, v_t, v_n, dt, contact):
    """Pair p's friction: the incremental spring F_T − k_T·Δu_T (from where stick began at an
    episode's first step, a share `share` of the step ago: _stick_since_touch), its dashpot,
    and Coulomb's stick/slip with the switches placed inside the step (_stick_shortfall,
    _kinetic_shortfall). Returns (the spring's new force, the total tangential force on B along
    t, N; slipping; where in the step the last switch fell, as (t_n − t_switch)/Δt, −1 for none:
    the impact log's friction times, _log_friction)."""
    law, state, now, frame = contact.law, contact.state, contact.now, contact.clip.frame
    k_n, mu_s, mu_k = law.k_n[p], law.mu_s[p], law.mu_k[p]
    area = frame[AREA]
    back = -1.0
    spring = state[p, ST_FT] - law.k_t[p] * slip_t
    if state[p, ST_ACTIVE] == 0 and f_n > 0.0 and area > 0.0:  # where stick began (_stick_since_touch)
        spring, stuck = _stick_since_touch(spring, f_n, mu_k, state[p, ST_DEEPEST] * frame[LENGTH] / area)
        if stuck >= 0.0:  # slipped from the touch and stuck again a share `stuck` of the time since
            back = (1.0 - stuck) * share
    trial = spring - law.c_t[p] * v_t
    slipping = state[p, ST_SLIP] > 0
    if slipping:  # it sticks again where μ_k·Ḟ_N fell to k_T·v_T (_stick_shortfall)
        held, held_back = _stick_shortfall(abs(spring - state[p, ST_FT]), mu_k, state[p, ST_LAW_FN], f_n,
                                           -k_n * frame[LENGTH] * v_n * dt)  # fmt: skip
        if held < 0.0 and abs(trial) + held <= mu_k * f_n:
            sign = 1.0 if trial > 0 else -1.0
            spring += sign * held
            trial += sign * held
            slipping = False
            back = held_back
    limit = mu_k * f_n if slipping else mu_s * f_n
    excess = abs(trial) - mu_k * f_n
    if abs(trial) > limit:
        sign = 1.0 if trial > 0 else -1.0
        target = sign * mu_k * f_n
        if not slipping and state[p, ST_ACTIVE] > 0:  # stick gave way within the last step
            before = abs(state[p, ST_LAW_FT]) - mu_s * state[p, ST_LAW_FN]
            after = abs(trial) - limit
            back = crossing_share(after, before) if before < 0.0 else 1.0
            # the slip began there: the spring followed the stuck path until then
            start = state[p, ST_FT] + (spring - state[p, ST_FT]) * (1.0 - back)
            spring = _slipping_spring(start, sign * mu_k * (f_n + back * (state[p, ST_LAW_FN] - f_n)), target, back,
                                      dt, law.k_t[p], law.c_t[p])  # fmt: skip
            trial = target + sign * _kinetic_shortfall(before, after, state[p, ST_LAW_FN], f_n, mu_s, mu_k)
        else:  # slipping since the touch (the spring unloaded there) or since the last step
            if state[p, ST_ACTIVE] == 0:
                spring = _slipping_spring(0.0, 0.0, target, share, dt, law.k_t[p], law.c_t[p])
            else:
                spring = _slipping_spring(state[p, ST_FT], sign * mu_k * state[p, ST_LAW_FN], target, 1.0, dt,
                                          law.k_t[p], law.c_t[p])  # fmt: skip
            trial = target
        slipping = True
    elif slipping and abs(trial) <= mu_k * f_n:
        slipping = False  # it stuck where the slider stopped (_slipping_spring)
        if law.c_t[p] == 0.0 and v_t * state[p, ST_VT] < 0.0:
            back = crossing_share(v_t, state[p, ST_VT])
        elif state[p, ST_EXCESS] > 0.0:
            back = crossing_share(excess, state[p, ST_EXCESS])
        else:
            back = 0.0
    state[p, ST_EXCESS] = excess
    state[p, ST_VT] = v_t
    return spring, trial, slipping, back


@phase
def _log_impact(p, t_now, dt, share, f_n, f_cell, f_t, missed, was_slipping, slipping, switched, contact):
    """Pair p's row of the impact log: opened at an episode's first step, where the outlines
    met a share `share` of the step ago (share_since_crossing); its impulse (of f_cell, the
    force the step applies), its peak normal force f_n (the crest through the last three steps,
    crest) with the action point, friction and normal there, its largest area, depth and
    contact line, and where it slipped and stuck
    (`switched`: (t_n − t_switch)/Δt of the last switch in the step, −1 for none)."""
    state, events, n_events, frame = contact.state, contact.events, contact.n_events, contact.clip.frame
    opened = state[p, ST_ACTIVE] == 0
    if opened:
        state[p, ST_ACTIVE] = 1.0
        state[p, ST_FN1] = 0.0
        state[p, ST_FN2] = 0.0
        state[p, ST_EVENT] = n_events[0]
        if n_events[0] < events.shape[0]:
            row = n_events[0]
            for k in range(EV_COLUMNS):
                events[row, k] = 0.0
            events[row, EV_PAIR] = p
            events[row, EV_T_START] = max(0.0, t_now - share * dt)
            events[row, EV_T_END] = np.nan
            events[row, EV_PEAK_FN] = -1.0  # below any F_N: the first step sets the peak's values
            events[row, EV_T_SLIP] = np.nan
            events[row, EV_T_STICK] = np.nan
        n_events[0] += 1
    e = int(state[p, ST_EVENT])
    if e < events.shape[0]:
        t_switch = t_now - switched * dt if switched >= 0.0 else t_now
        if opened and (slipping or switched >= 0.0):  # it slipped from the touch (and may have stuck since)
            events[e, EV_T_SLIP] = events[e, EV_T_START]
            events[e, EV_SLIPS] = 1.0
            events[e, EV_SLID] = 1.0
        elif slipping and not was_slipping:  # stick gave way
            if np.isnan(events[e, EV_T_SLIP]):
                events[e, EV_T_SLIP] = t_switch
            events[e, EV_SLIPS] += 1.0
            events[e, EV_T_STICK] = np.nan
        if not slipping and (was_slipping or opened and switched >= 0.0):  # it stuck again
            events[e, EV_T_STICK] = t_switch
        events[e, EV_IMPULSE] += (f_cell + missed) * dt
        if f_n > events[e, EV_PEAK_FN]:
            events[e, EV_PEAK_FN] = f_n
            events[e, EV_X] = frame[CX]
            events[e, EV_Y] = frame[CY]
            events[e, EV_T_PEAK] = t_now
            events[e, EV_FT_PEAK] = f_t
            events[e, EV_NX] = frame[NX]
            events[e, EV_NY] = frame[NY]
        f_last = state[p, ST_FN1]
        if state[p, ST_FN2] > 0.0 and state[p, ST_FN2] <= f_last >= f_n:  # the last step was a crest
            events[e, EV_PEAK_FN] = max(events[e, EV_PEAK_FN], crest(state[p, ST_FN2], f_last, f_n))
        if frame[AREA] > events[e, EV_PEAK_AREA]:
            events[e, EV_PEAK_AREA] = frame[AREA]
        if frame[DEPTH] > events[e, EV_PEAK_DEPTH]:
            events[e, EV_PEAK_DEPTH] = frame[DEPTH]
        if frame[LENGTH] > events[e, EV_PEAK_LENGTH]:
            events[e, EV_PEAK_LENGTH] = frame[LENGTH]
        if slipping:
            events[e, EV_SLID] = 1.0
    state[p, ST_FN2] = state[p, ST_FN1]
    state[p, ST_FN1] = f_n


@kernel
def contact_forces(n, dt, u, v_half, v_est, contact):
    """Contact forces at step n: adds them to contact.force (n_dof + 3), N and N·m.

    u = u_n; v_half = v_{n−½} (so Δt·v_half is the displacement since the last step, which
    drives the tangential spring); v_est ≈ v_n = v_{n−½} + ½Δv_{n−1}, a second-order
    estimate of the velocity for the dashpots. contact: records.Contact.

    Phases, pair by pair: broad phase (with sweep and prune, only the pairs whose boxes
    overlap and those in contact at the last step are visited; without, every pair: either
    way in ascending order, so forces add up in the same order, bit for bit), narrow phase
    (the overlap and its frame), and for a pair in contact the impact law: relative motion at
    the action point, normal force, the kinks of the touch, tangential force, the forces on
    both bodies, the kinks of the parting, the impact log. Returns the number of pairs in
    contact, also left in the broad phase's n_live.
    """
    bodies, law, broad, state, now, forces = contact.bodies, contact.law, contact.broad, contact.state, \
        contact.now, contact.force  # fmt: skip
    frame = contact.clip.frame
    sweeping = broad.group_axis.size > 0
    # broad phase: the pairs whose displaced boxes may overlap (while buildings sleep: the
    # pairs that may touch before the next substep boundary, sleep.py)
    listed = sweeping or broad.n_phase[0] >= 0
    if broad.n_phase[0] >= 0:
        visits = phase_pairs_to_visit(broad)
    else:
        visits = pairs_to_visit(u, bodies, broad) if sweeping else law.a.size
    t_now = n * dt
    in_contact = 0
    for i in range(visits):
        p = broad.hits[i] if listed else i
        # narrow phase: boxes, circles, the clipped overlap and its frame
        touching, gax, gay, gbx, gby = _pair_frame(p, u, bodies, law, contact.clip)
        if not touching:
            _end_episode(p, t_now, dt, u, v_half, gax, gay, gbx, gby, contact)
            continue
        if listed:
            broad.live[in_contact] = p
        in_contact += 1
        a = law.a[p]
        b = law.b[p]
        fa = bodies.floor[a]
        fb = bodies.floor[b]
        cx = frame[CX]
        cy = frame[CY]
        nx = frame[NX]
        ny = frame[NY]
        tx = frame[TX]
        ty = frame[TY]
        # relative motion of B's material point at c with respect to A's: slip since the
        # last step (half-step velocities) and velocity now (for the dashpots)
        vax, vay = _point_velocity(fa, cx, cy, gax, gay, v_half)
        vbx, vby = _point_velocity(fb, cx, cy, gbx, gby, v_half)
        rel_x = vbx - vax
        rel_y = vby - vay
        slip_t = _slip_over_step(p, fa, fb, dt, cx, cy, tx, ty, gax, gay, gbx, gby, rel_x, rel_y, v_half, state,
                                 now)  # fmt: skip
        closed = -dt * (rel_x * nx + rel_y * ny)  # over the last step at c, m
        # and its change along t, per metre: B's turning relative to A's
        closed_turn = dt * ((v_half[3 * fb + 2] if fb >= 0 else 0.0) - (v_half[3 * fa + 2] if fa >= 0 else 0.0))
        share = 1.0  # of the last step spent in contact; below 1 only at an episode's first step
        if state[p, ST_ACTIVE] == 0:
            g_now, g_before = gaps_along_step(a, b, dt, u, v_half, bodies, contact.clip.poly_a, contact.clip.poly_b)
            share = share_since_crossing(g_now, g_before)
            slip_t *= share
        vax, vay = _point_velocity(fa, cx, cy, gax, gay, v_est)
        vbx, vby = _point_velocity(fb, cx, cy, gbx, gby, v_est)
        v_n = (vbx - vax) * nx + (vby - vay) * ny
        v_t = (vbx - vax) * tx + (vby - vay) * ty
        turn = (v_est[3 * fb + 2] if fb >= 0 else 0.0) - (v_est[3 * fa + 2] if fa >= 0 else 0.0)
        # normal force: overlap-area spring and dashpot, never pulling
        f_n = _normal_force(p, share, v_n, gax, gay, gbx, gby, dt, contact)
        # what the step applies: the spring's average over the step's hat (cell_correction)
        f_cell = f_n
        if f_n > 0.0:
            # the closing acceleration at c at t_{n−1} (Δv_{n−1} = 2·(v_est − v_{n−½})), at t_n with
            # this force's change since over the pair's mass, and its rate over the last two steps
            rate = -2.0 / dt * ((vbx - vax - rel_x) * nx + (vby - vay - rel_y) * ny)
            if state[p, ST_ACTIVE] == 0:
                correction = cell_correction(law.k_n[p], frame[LENGTH], 0.0, rate, 0.0, dt)
            else:
                change = (f_n - state[p, ST_LAW_FN]) / law.m_eff[p]
                correction = cell_correction(law.k_n[p], frame[LENGTH], _dashpot(p, law, frame[LENGTH]),
                                             rate - change, (rate - state[p, ST_RATE]) / dt, dt)  # fmt: skip
            state[p, ST_RATE] = rate
            f_cell = max(0.0, f_n + correction)
        undamped = _undamped(law.c_n[p], law.zeta[p])
        # the overlap's depth along the contact line, and the points that touched within the last
        # step (their impulse is added below)
        missed = 0.0
        arm = 0.0
        rest = state[p, ST_REST:]
        n_profile = 0
        tmp = contact.clip.tmp
        if f_n > 0.0:
            n_profile, state[p, ST_DEEPEST] = depth_profile(contact.clip.clip, int(frame[FRAME_VERTICES]), nx, ny,
                                                            tx, ty, cx, cy, tmp)  # fmt: skip
            missed, arm = _shallow_impulse(tmp, n_profile, law.k_n[p], closed, closed_turn, state[p, ST_ACTIVE] == 0,
                                           rest)  # fmt: skip
        # tangential force: incremental spring, dashpot, Coulomb stick/slip
        was_slipping = state[p, ST_SLIP] > 0
        spring, f_t, slipping, switched = _tangential_force(p, share, f_n, slip_t, v_t, v_n, dt, contact)
        state[p, ST_FT] = spring
        state[p, ST_SLIP] = 1.0 if slipping else 0.0
        # forces on B (+) and A (−) at the action point: the law's, and what the step applies (a
        # slipping contact's friction follows the normal force)
        fx = f_n * nx + f_t * tx
        fy = f_n * ny + f_t * ty
        state[p, ST_FX] = fx
        state[p, ST_FY] = fy
        if f_cell != f_n:
            applied_t = f_t * f_cell / f_n if slipping else f_t
            fx = f_cell * nx + applied_t * tx
            fy = f_cell * ny + applied_t * ty
        _apply(fb, fx, fy, cx, cy, gbx, gby, forces)
        _apply(fa, -fx, -fy, cx, cy, gax, gay, forces)
        # the spring's kinks where points of the overlap touched within the last step or part
        # within the next (without a dashpot: with one, the force ends where its pull cancels)
        if f_n > 0.0:
            if undamped:  # parting within the next step, its closing speed grown by this force's push
                opening = dt * (v_n + 0.5 * dt * f_n / law.m_eff[p])
                out, arm_out = _shallow_impulse(tmp, n_profile, law.k_n[p], opening, -dt * turn, False, rest)
                if out > 0.0:
                    arm = (missed * arm + out * arm_out) / (missed + out)
                    missed += out
            if missed > 0.0:
                # a slipping contact's friction follows
                along = _slip_ratio(spring, f_t, f_n, law.mu_k[p], law.c_t[p]) if slipping else 0.0
                px = cx + arm * tx
                py = cy + arm * ty
                mx = missed * (nx + along * tx)
                my = missed * (ny + along * ty)
                _apply(fb, mx, my, px, py, gbx, gby, forces)
                _apply(fa, -mx, -my, px, py, gax, gay, forces)
        state[p, ST_NX] = nx
        state[p, ST_NY] = ny
        # the forces at t_n: the steps run ahead of the law by half the hat's correction (a sliding
        # contact's friction follows the normal force)
        state[p, ST_LAW_FN] = f_n
        state[p, ST_LAW_FT] = f_t
        now[p, NOW_FN] = 0.5 * (f_n + f_cell)
        now[p, NOW_FT] = f_t * now[p, NOW_FN] / f_n if slipping and f_cell != f_n else f_t
        now[p, NOW_AREA] = frame[AREA]
        now[p, NOW_X] = cx
        now[p, NOW_Y] = cy
        now[p, NOW_DEPTH] = frame[DEPTH]
        _log_impact(p, t_now, dt, share, now[p, NOW_FN], f_cell, now[p, NOW_FT], missed, was_slipping, slipping,
                    switched, contact)  # fmt: skip
    broad.n_live[0] = in_contact
    return in_contact


def buffers(n_vertices: int) -> ClipWork:
    """Work buffers of contact_forces for bodies of at most n_vertices vertices."""
    clip_rows = 2 * n_vertices + 2
    return ClipWork(
        np.zeros((n_vertices, 2)),
        np.zeros((n_vertices, 2)),
        np.zeros((clip_rows, 2)),
        np.zeros(clip_rows, dtype=np.int64),
        np.zeros((clip_rows, 2)),
        np.zeros(clip_rows, dtype=np.int64),
        np.zeros(16),
    )


@kernel(inline="always")
def _widened_boxes_meet(a, b, u, v, acc, horizon, body_floor, body_radius, body_box):
    """The rest boxes of bodies a and b, displaced and each widened by how far its body can
    move within `horizon` s (reach_over), overlap."""
    ax, ay, agx, agy, ar = reach_over(a, u, v, acc, horizon, body_floor, body_radius)
    bx, by, bgx, bgy, br = reach_over(b, u, v, acc, horizon, body_floor, body_radius)
    return not (body_box[a, 2] + ax + agx + ar < body_box[b, 0] + bx - bgx - br
                or body_box[b, 2] + bx + bgx + br < body_box[a, 0] + ax - agx - ar
                or body_box[a, 3] + ay + agy + ar < body_box[b, 1] + by - bgy - br
                or body_box[b, 3] + by + bgy + br < body_box[a, 1] + ay - agy - ar)  # fmt: skip


@kernel
def contact_possible_within(horizon, u, v, acc, contact):
    """True when some pair's bounding boxes, each widened by how far its body can move within
    `horizon` s (velocity and acceleration now), overlap: a contact may begin that soon.
    With broad's groups by sweep and prune, else by testing every pair (the same answer)."""
    bodies, broad = contact.bodies, contact.broad
    if broad.group_axis.size > 0:
        return boxes_may_meet_within(horizon, u, v, acc, bodies, broad)
    body_floor, body_radius, body_box = bodies.floor, bodies.radius, bodies.box
    pair_a = contact.law.a
    pair_b = contact.law.b
    for p in range(pair_a.size):
        if _widened_boxes_meet(pair_a[p], pair_b[p], u, v, acc, horizon, body_floor, body_radius, body_box):
            return True
    return False


@kernel(inline="always")
def _turn_reach(body, v, acc, horizon, body_floor, body_radius):
    """How far turning can move a point of a body's outline within `horizon` s, beyond its mass
    centre's motion: |θ̇|·ρ·H + ½·(|θ̈| + θ̇²)·ρ·H² at its bounding radius ρ, m."""
    f = body_floor[body]
    if f < 0:
        return 0.0
    w = v[3 * f + 2]
    return body_radius[body] * (abs(w) * horizon + 0.5 * (abs(acc[3 * f + 2]) + w * w) * horizon * horizon)


@kernel(inline="always")
def _centre_relative(a, b, x, body_floor):
    """x_B − x_A in plan (x, y) for the mass-centre entries of a floor vector x (velocity,
    acceleration); an obstacle's are zero (it moves with the ground)."""
    fa = body_floor[a]
    fb = body_floor[b]
    dx = (x[3 * fb] if fb >= 0 else 0.0) - (x[3 * fa] if fa >= 0 else 0.0)
    dy = (x[3 * fb + 1] if fb >= 0 else 0.0) - (x[3 * fa + 1] if fa >= 0 else 0.0)
    return dx, dy


@kernel(inline="always")
def _centre_difference(a, b, x, body_floor):
    """|x_B − x_A| in plan (_centre_relative)."""
    dx, dy = _centre_relative(a, b, x, body_floor)
    return np.sqrt(dx * dx + dy * dy)


@kernel(inline="always")
def _pair_closing_along(a, b, dx, dy, v, acc, horizon, body_floor, body_radius):
    """How much the outlines of bodies a and b can close within `horizon` s along the fixed
    direction (dx, dy) from a towards b, m: B's mass centre approaching A's along it (nothing
    while they move apart), their relative acceleration whichever way it points (it can turn
    an opening into a closing within the horizon), and what each one's turning adds
    (_turn_reach). The gap of the two outlines' projections on that axis bounds their distance
    from below at every instant, so this bounds its fall."""
    vx, vy = _centre_relative(a, b, v, body_floor)
    approach = max(0.0, -(vx * dx + vy * dy))
    da = _centre_difference(a, b, acc, body_floor)
    move = approach * horizon + 0.5 * da * horizon * horizon
    return move + _turn_reach(a, v, acc, horizon, body_floor, body_radius) + _turn_reach(
        b, v, acc, horizon, body_floor, body_radius)


@kernel(inline="always")
def _separating_direction(p, n_p, q, n_q):
    """The largest gap between the projections of outlines p and q on the normals of p's edges
    (≤ 0 when none separates them), m, and the unit direction along that normal from p
    towards q."""
    best = -np.inf
    bx = 0.0
    by = 0.0
    for i in range(n_p):
        j = i + 1 if i + 1 < n_p else 0
        ex = p[j, 0] - p[i, 0]
        ey = p[j, 1] - p[i, 1]
        length = np.sqrt(ex * ex + ey * ey)
        if length == 0.0:
            continue
        nx = ey / length
        ny = -ex / length
        lo_p = np.inf
        hi_p = -np.inf
        for k in range(n_p):
            d = p[k, 0] * nx + p[k, 1] * ny
            lo_p = min(lo_p, d)
            hi_p = max(hi_p, d)
        lo_q = np.inf
        hi_q = -np.inf
        for k in range(n_q):
            d = q[k, 0] * nx + q[k, 1] * ny
            lo_q = min(lo_q, d)
            hi_q = max(hi_q, d)
        if lo_q - hi_p > best:
            best = lo_q - hi_p
            bx = nx
            by = ny
        if lo_p - hi_q > best:
            best = lo_p - hi_q
            bx = -nx
            by = -ny
    return best, bx, by


@kernel(inline="always")
def _signed_gap(p, n_p, q, n_q):
    """Separating-axis gap of outlines p and q over both outlines' edge normals, m: a lower
    bound of their distance when > 0; minus their penetration depth when they overlap. Also
    the unit direction of that axis from p towards q."""
    gap, dx, dy = _separating_direction(p, n_p, q, n_q)
    gap_q, dx_q, dy_q = _separating_direction(q, n_q, p, n_p)
    if gap_q > gap:  # one of q's edge normals: its direction from q to p, turned
        return gap_q, -dx_q, -dy_q
    return gap, dx, dy


@kernel(inline="always")
def _outline_gap(a, b, u, v, back, bodies, poly_a, poly_b):
    """_signed_gap of bodies a and b displaced to u − back·v (back s before, at velocity v),
    m, and its axis from a towards b; their outlines are left in poly_a, poly_b."""
    body_poly, body_nv, body_floor, body_centre = bodies.poly, bodies.nv, bodies.floor, bodies.centre
    _deform_before(a, u, v, back, body_poly, body_nv, body_floor, body_centre, poly_a)
    _deform_before(b, u, v, back, body_poly, body_nv, body_floor, body_centre, poly_b)
    return _signed_gap(poly_a, body_nv[a], poly_b, body_nv[b])


@kernel(**INTERNAL)
def gaps_along_step(a, b, dt, u, v_half, bodies, poly_a, poly_b):
    """The signed gaps of bodies a and b now and a step ago along the CDM's straight path
    (u − Δt·v_{n−½}), m (_signed_gap: minus the depth where they overlap)."""
    now = _outline_gap(a, b, u, v_half, 0.0, bodies, poly_a, poly_b)[0]
    before = _outline_gap(a, b, u, v_half, dt, bodies, poly_a, poly_b)[0]
    return now, before


@kernel(inline="always")
def crossing_share(now, before):
    """(t_n − t*)/Δt: where a quantity taken linear over the last step, `before` at its start
    and `now` at its end (of opposite signs), crosses zero."""
    return now / (now - before)


@kernel(inline="always")
def share_since_crossing(now, before):
    """Share of the last step (0–1) since the signed gap changed sign, from `before` a step
    ago to `now` (gaps_along_step): at a touch, from g₀ ≥ 0 to −depth, the bodies met
    depth/(g₀ + depth) of a step ago; at a break-away, from −depth to g ≥ 0, they parted
    g/(g + depth) of a step ago; 1 without a crossing (overlapping a step ago too, as when a
    run starts in contact). The tangential spring starts from the touch: counting the whole
    step's slip would offset its anchor by up to Δt·v_T, an error that does not shrink with Δt
    on nested grids (the last grid point before the touch is shared by every finer grid) and
    that made friction runs converge erratically."""
    if not (before > 0.0) == (now <= 0.0) or before == now:
        return 1.0
    return min(1.0, now / (now - before))


@kernel(inline="always")
def contact_ruled_out_within(horizon, u, v, acc, contact):
    """True when no pair can touch within `horizon` s: for every pair whose widened bounding
    boxes may meet (as contact_possible_within finds them), the gap between the displaced
    outlines (a lower bound by separating axes: the largest gap between their projections on
    any edge normal) exceeds CLOSING_SAFETY × what they can close in that time along that
    axis (_pair_closing_along: nothing for their velocities where they move apart, so that a
    pair that just parted is ruled out as soon as its gap outgrows what the accelerations can
    close; counting their relative speed whichever way it pointed, the Kobe example took
    20,902 CDM steps outside contact, a third of its CDM steps; now 9,937).
    Tighter than the boxes, which widen by |θ|·ρ for a turned outline: the
    hybrid's approach levels use it to step exactly up to a few CDM steps before an impact."""
    return _finest_level_within(horizon, u, v, acc, contact, None, 1) == 1


@kernel(inline="always")
def contact_finest_level_within(horizon, u, v, acc, contact, pair_level, coarsest):
    """The finest (least) pair_level[p] of the pairs that contact_ruled_out_within cannot rule
    out within `horizon` s (a pair in contact among them), `coarsest` where it rules out every
    pair whose level is finer; 0 for a state gone bad (step_levels.py)."""
    return _finest_level_within(horizon, u, v, acc, contact, pair_level, coarsest)


@kernel(**INTERNAL)
def _finest_level_within(horizon, u, v, acc, contact, pair_level, coarsest):
    """The body of both (which numba inlines, so that a check costs the one call it always
    did: a call passes the contact record's arrays one by one): pair_level None counts every
    pair as level 0 (numba compiles the branch away for a None argument), so that the first
    pair not ruled out ends the search, as it always did."""
    bodies, broad = contact.bodies, contact.broad
    body_floor, body_radius, body_box = bodies.floor, bodies.radius, bodies.box
    pair_a = contact.law.a
    pair_b = contact.law.b
    poly_a, poly_b = contact.clip.poly_a, contact.clip.poly_b
    sweeping = broad.group_axis.size > 0
    if sweeping:
        candidates = pairs_may_meet_within(horizon, u, v, acc, bodies, broad)
        if candidates < 0:
            return 0  # a state gone bad: the CDM takes over at its finest and stops the run
    else:
        candidates = pair_a.size
    hits = broad.hits
    level = coarsest
    for i in range(candidates):
        p = hits[i] if sweeping else i
        if pair_level is None:
            this = 0
        else:
            this = pair_level[p]
        if this >= level:
            continue  # it could not make the answer finer
        a = pair_a[p]
        b = pair_b[p]
        if not sweeping and not _widened_boxes_meet(a, b, u, v, acc, horizon, body_floor, body_radius, body_box):
            continue
        gap, dx, dy = _outline_gap(a, b, u, v, 0.0, bodies, poly_a, poly_b)
        closing = CLOSING_SAFETY * _pair_closing_along(a, b, dx, dy, v, acc, horizon, body_floor, body_radius)
        if not gap > closing:  # (NaN: possible)
            level = this
            if level == 0:
                return 0
    return level


@kernel(**INTERNAL)
def contact_pairs_needed(horizon, u, v, acc, contact, body_building, flag, need, keep):
    """The buildings that the CDM must carry: need[b] = 1 for both buildings of every pair
    that contact_ruled_out_within cannot rule out within `horizon` s (a pair in contact among
    them), 0 for the rest. Pairs with a building whose flag is 0 are passed over (flag all
    ones: every pair). With `keep`, those pairs become the broad phase's `phase` list, which
    the contact step visits alone (with every pair where the state has gone bad). Bodies of
    building −1 (obstacles) count as awake. Returns how many pairs those are (−1 for a state
    gone bad, when every building is needed)."""
    bodies, broad = contact.bodies, contact.broad
    body_floor, body_radius, body_box = bodies.floor, bodies.radius, bodies.box
    pair_a = contact.law.a
    pair_b = contact.law.b
    poly_a, poly_b = contact.clip.poly_a, contact.clip.poly_b
    need[:] = 0
    sweeping = broad.group_axis.size > 0
    if sweeping:
        candidates = pairs_may_meet_within(horizon, u, v, acc, bodies, broad)
        if candidates < 0:
            need[:] = 1
            if keep:
                broad.n_phase[0] = -1
            return -1
    else:
        candidates = pair_a.size
    hits = broad.hits
    count = 0
    for i in range(candidates):
        p = hits[i] if sweeping else i
        a = pair_a[p]
        b = pair_b[p]
        building_a = body_building[a]
        building_b = body_building[b]
        if (building_a >= 0 and flag[building_a] == 0) or (building_b >= 0 and flag[building_b] == 0):
            continue
        if not sweeping and not _widened_boxes_meet(a, b, u, v, acc, horizon, body_floor, body_radius, body_box):
            continue
        gap, dx, dy = _outline_gap(a, b, u, v, 0.0, bodies, poly_a, poly_b)
        closing = CLOSING_SAFETY * _pair_closing_along(a, b, dx, dy, v, acc, horizon, body_floor, body_radius)
        if not gap > closing:  # (NaN: possible)
            if building_a >= 0:
                need[building_a] = 1
            if building_b >= 0:
                need[building_b] = 1
            if keep:
                broad.phase[count] = p
            count += 1
    if keep:
        _sort_ascending(broad.phase, count)
        broad.n_phase[0] = count
    return count
