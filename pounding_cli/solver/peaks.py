"""Running peaks of the response: column deflections, storey twists, floor displacements and
accelerations.

Peaks are taken at every state the integrator reaches (update_peaks). Where it reaches them
by exact propagation the steps are long (ω_max·H up to CREST_SPAN = 4: a whole record
interval in most scenes) and a peak falling between two states would be missed by up to
1 − cos(ω·H/2) of its size. There the motion between the states is smooth and the peaks
between them are exact:

1. Located by the quintic. Both ends carry exact values and their first two rates
   (displacements: u, v, a_rel; absolute accelerations: a, ȧ, ä), and the quintic Hermite
   interpolant through them is within (ω·H)⁶/46080 of a mode's share of the motion
   (h⁶·max|q⁽⁶⁾|/(6!·2⁶)). peaks_between lists every stationary point of the quintic of every
   deflection, displacement and acceleration whose value comes within CREST_MARGIN of that
   bound of its running peak (quintic_crests): the crests that may raise it.
2. Valued exactly. For a step with such crests, the exact motion's derivatives of every order
   at the step's end, u⁽ʲ⁾ (exact.state_series: u⁽ʲ⁺²⁾ = −M⁻¹(K·u⁽ʲ⁾ + C·u⁽ʲ⁺¹⁾), the
   ground's rate entering u‴ alone, as it is linear within the step), give each listed
   quantity's Taylor series about the end, exact to rounding over the step once its order
   passes ρ·H (crest_series_order; ρ the largest |λ| of the buildings' state matrices).
   Newton's steps on that series from the quintic's crest converge to the exact crest
   (settle_crests), and the running peak rises to the exact values they visit: never above
   the motion's own.

Random sums of one to four modes (a prototype of this search; docs/theory.md §6) put the
quintic's crest within Newton's reach of the exact one up to ω_max·H = 5 (3,000 cases each):
every crest exact to 5e-15. At ω·H = 6 a few fell into the wrong basin; CREST_SPAN = 4 keeps
a margin. tests/test_peaks.py holds one mode and nine coupled ones to 1e-12 and 1e-10 at
ω·H = 3.9.
"""

from __future__ import annotations

import math

import numpy as np

from .force_peaks import gauge_floor, gauge_linear, keep_offsets, update_gauge_peaks
from .jit import INTERNAL, kernel, phase
from .tunables import CREST_NEWTON_STEPS, SERIES_MAX_ORDER, SERIES_MIN_ORDER, SERIES_REMAINDER


HERMITE_ARM = 4.0 / 27.0
"""The largest value of the Hermite basis functions s(1 − s)² and s²(1 − s) on [0, 1]: the
cubic through (q₀, q̇₀) and (q₁, q̇₁) over a step h stays within max(|q₀|, |q₁|) +
HERMITE_ARM·h·(|q̇₀| + |q̇₁|); with QUINTIC_BEND's term, the quintic's bound, which lets most
steps skip the search for its maximum."""


@kernel(inline="always")
def storey_deflection(u, t, b, c, sn, centre):
    """Storey deflection (Ã_x, Ã_y, Δθ) in building axes (cos φ, sin φ) = (c, sn), between
    floor t and floor b (the ground row of u for the first storey), from the floor motion u
    (or from the floor velocities: the map is linear). See update_peaks."""
    ax = u[3 * t] + u[3 * t + 2] * centre[t, 1] - u[3 * b] - u[3 * b + 2] * centre[b, 1]
    ay = u[3 * t + 1] - u[3 * t + 2] * centre[t, 0] - u[3 * b + 1] + u[3 * b + 2] * centre[b, 0]
    return c * ax + sn * ay, c * ay - sn * ax, u[3 * t + 2] - u[3 * b + 2]


@phase
def update_peaks(u, acc_abs, structure, storey_work, peaks):
    """update_peaks_range over every building."""
    update_peaks_range(u, acc_abs, structure, storey_work, peaks, 0, structure.mass.size // 3, 0,
                       structure.column_storey.size, 0, peaks.gauges.storey.size)  # fmt: skip


@phase
def update_peaks_range(u, acc_abs, structure, storey_work, peaks, f0, f1, c0, c1, g0, g1):
    """Running maxima (peaks: records.Peaks) at the state u with absolute accelerations
    acc_abs: column deflections in building axes, storey twist, floor motion, of the buildings
    whose floors (and storeys) are f0 … f1 − 1, columns c0 … c1 − 1, gauges g0 … g1 − 1.

    A point P of a floor with mass centre G moves by u + θ·ẑ×(P − G), so a column at P of
    storey s deflects by A + Δθ·ẑ×P with A = (u_t + θ_t·ẑ×(−G_t)) − (u_b + θ_b·ẑ×(−G_b)).
    In building axes (cos φ, sin φ) the deflection is Ã + Δθ·(ξ, η) with
    ξ = −cos φ·P_y + sin φ·P_x and η = sin φ·P_y + cos φ·P_x (col_arm holds ξ, η).
    storey_work (n_storeys, 3) receives Ã_x, Ã_y, Δθ of each storey; the storey shears and
    column forces are gauges of them (force_peaks.py).
    """
    storey_bottom, storey_top, storey_axes, centre = structure.storey_bottom, structure.storey_top, \
        structure.storey_axes, structure.centre  # fmt: skip
    col_storey, col_arm = structure.column_storey, structure.column_arm
    peak_col, peak_rot, peak_disp, peak_acc = peaks.column, peaks.storey_rotation, peaks.displacement, peaks.acceleration
    for s in range(f0, f1):
        dx, dy, rot = storey_deflection(u, storey_top[s], storey_bottom[s], storey_axes[s, 0], storey_axes[s, 1],
                                        centre)  # fmt: skip
        storey_work[s, 0] = dx
        storey_work[s, 1] = dy
        storey_work[s, 2] = rot
        if abs(rot) > peak_rot[s]:
            peak_rot[s] = abs(rot)
    for k in range(c0, c1):
        s = col_storey[k]
        lx = abs(storey_work[s, 0] + storey_work[s, 2] * col_arm[k, 0])
        ly = abs(storey_work[s, 1] + storey_work[s, 2] * col_arm[k, 1])
        if lx > peak_col[k, 0]:
            peak_col[k, 0] = lx
        if ly > peak_col[k, 1]:
            peak_col[k, 1] = ly
    update_gauge_peaks(storey_work, peaks.gauges, g0, g1)
    for d in range(3 * f0, 3 * f1):
        if abs(u[d]) > peak_disp[d]:
            peak_disp[d] = abs(u[d])
        if abs(acc_abs[d]) > peak_acc[d]:
            peak_acc[d] = abs(acc_abs[d])


QUINTIC_BEND = 0.01728
"""The largest s²(1 − s)³/2 on [0, 1]: the quintic Hermite basis of a second derivative, the
most the quintic departs from the cubic per unit of their second derivatives' mismatch."""


@kernel(inline="always")
def bend_mismatch(q0, m0, c0, q1, m1, c1, h):
    """(E₀, E₁): the second derivatives c at the ends (scaled by h²) less the cubic Hermite's
    through (q, m). The quintic through (q, m, c) is that cubic plus E₀·s²(1 − s)³/2 +
    E₁·s³(1 − s)²/2 on s ∈ [0, 1]."""
    d = q1 - q0
    return h * h * c0 - 2.0 * (3.0 * d - 2.0 * h * m0 - h * m1), h * h * c1 + 6.0 * d - 2.0 * h * m0 - 4.0 * h * m1


@kernel(inline="always")
def _root_in(k0, k1, k2, k3, k4, lo, hi):
    """The root inside (lo, hi) of k0 + k1·s + … + k4·s⁴, monotonic there, or −1 where it
    keeps its sign: Newton's steps, bisection where one would leave the bracket."""
    if hi <= lo:
        return -1.0
    f_lo = k0 + lo * (k1 + lo * (k2 + lo * (k3 + lo * k4)))
    f_hi = k0 + hi * (k1 + hi * (k2 + hi * (k3 + hi * k4)))
    if not ((f_lo < 0.0 < f_hi) or (f_hi < 0.0 < f_lo)):
        return -1.0
    s = 0.5 * (lo + hi)
    for _ in range(60):
        f = k0 + s * (k1 + s * (k2 + s * (k3 + s * k4)))
        if f == 0.0:
            return s
        if (f < 0.0) == (f_lo < 0.0):
            lo = s
        else:
            hi = s
        slope = k1 + s * (2.0 * k2 + s * (3.0 * k3 + s * 4.0 * k4))
        nxt = s - f / slope if slope != 0.0 else lo
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - s) <= 1e-15:
            return nxt
        s = nxt
    return s


@kernel(inline="always")
def _crest_at(q0, c, a2, a3, a4, a5, lo, hi, floor, kind, index, crests, n):
    """Lists in crests[n] (kind, index, s) the root s of q' inside (lo, hi), q = q0 + c·s +
    a2·s² + … + a5·s⁵, where q' is monotonic there, if |q(s)| > floor; returns the new count."""
    s = _root_in(c, 2.0 * a2, 3.0 * a3, 4.0 * a4, 5.0 * a5, lo, hi)
    if s < 0.0 or abs(q0 + s * (c + s * (a2 + s * (a3 + s * (a4 + s * a5))))) <= floor:
        return n
    crests[n, 0] = kind
    crests[n, 1] = index
    crests[n, 2] = s
    return n + 1


@kernel("int64(float64, float64, float64, float64, float64, float64, float64, float64, int64, int64, float64[:, ::1], "
        "int64)", forceinline=True)  # fmt: skip
def quintic_crests(q0, m0, c0, q1, m1, c1, h, floor, kind, index, crests, n):
    """Lists the stationary points inside (0, h) of the quintic q(τ) through the values q,
    rates m and second derivatives c at both ends (one unit per derivative, h in s) where
    |q| passes `floor`: rows (kind, index, s = τ/h) of crests from row n on (four at most, the
    roots of a quartic q'); returns the new count. The ends themselves are update_peaks'
    business.

    The stationary points are isolated exactly: the roots of the third derivative (a
    quadratic) split [0, 1] into pieces where q'' is monotonic; the roots of q'' (one a piece
    at most) split it into pieces where q' is, each holding one stationary point at most,
    found by safeguarded Newton steps."""
    e0, e1 = bend_mismatch(q0, m0, c0, q1, m1, c1, h)
    if max(abs(q0), abs(q1)) + HERMITE_ARM * h * (abs(m0) + abs(m1)) + QUINTIC_BEND * (abs(e0) + abs(e1)) <= floor:
        return n
    # q(s·h) = q0 + c·s + a2·s² + a3·s³ + a4·s⁴ + a5·s⁵ on s ∈ [0, 1]: the cubic through
    # (q, m) plus bend_mismatch's terms
    c = h * m0
    a2 = 3.0 * (q1 - q0) - h * (2.0 * m0 + m1) + 0.5 * e0
    a3 = 2.0 * (q0 - q1) + h * (m0 + m1) + 0.5 * (e1 - 3.0 * e0)
    a4 = 1.5 * e0 - e1
    a5 = 0.5 * (e1 - e0)
    # the third derivative fc + fb·s + fa·s²: its roots inside (0, 1), t1 ≤ t2 (1 if none)
    fa, fb, fc = 60.0 * a5, 24.0 * a4, 6.0 * a3
    r1 = r2 = 1.0
    if fa != 0.0:
        disc = fb * fb - 4.0 * fa * fc
        if disc > 0.0:
            w = -0.5 * (fb + math.copysign(math.sqrt(disc), fb))
            r1 = w / fa
            r2 = fc / w if w != 0.0 else r1
    elif fb != 0.0:
        r1 = -fc / fb
    r1 = r1 if 0.0 < r1 < 1.0 else 1.0
    r2 = r2 if 0.0 < r2 < 1.0 else 1.0
    t1, t2 = min(r1, r2), max(r1, r2)
    # q'' monotonic on [0, t1], [t1, t2], [t2, 1]: its roots, ascending, split [0, 1] into
    # the pieces where q' is monotonic
    start = 0.0
    for piece in range(3):
        lo = 0.0 if piece == 0 else (t1 if piece == 1 else t2)
        hi = t1 if piece == 0 else (t2 if piece == 1 else 1.0)
        bend = _root_in(2.0 * a2, 6.0 * a3, 12.0 * a4, 20.0 * a5, 0.0, lo, hi)  # of q''
        if bend > 0.0:
            n = _crest_at(q0, c, a2, a3, a4, a5, start, bend, floor, kind, index, crests, n)
            start = bend
    return _crest_at(q0, c, a2, a3, a4, a5, start, 1.0, floor, kind, index, crests, n)


# the kinds of quantity a crest belongs to (column 0 of crests): a column's deflection
# (index 2·column + axis), a storey's twist, a floor displacement, a floor's absolute
# acceleration (index: the DOF), a force gauge (force_peaks.py; index: the gauge)
CREST_COLUMN, CREST_TWIST, CREST_DISPLACEMENT, CREST_ACCELERATION, CREST_GAUGE = 0, 1, 2, 3, 4


def crest_arrays(n_columns: int, n_storeys: int, n_dof: int, n_gauges: int = 0) -> np.ndarray:
    """peaks_between's list of crests (kind, index, s, and a force gauge's plastic part):
    room for four of every quantity it follows."""
    return np.zeros((4 * (2 * n_columns + n_storeys + 2 * n_dof + n_gauges), 4))


def crest_series_order(rho_h: float) -> int:
    """Rows of exact.state_series (u⁽ʲ⁾, j = 0 … R − 1) for exact steps of ρ·H ≤ rho_h: the
    Taylor series of an acceleration's second derivative, its shortest, keeps R − 4 terms, and
    its remainder (ρ·H)^(R−4)/(R−4)! of the motion is below SERIES_REMAINDER. A step so long
    that this takes more than SERIES_MAX_ORDER terms (or a rate that is not finite) is a
    ValueError: the crests' search holds to ρ·H = CREST_SPAN, and such a rate belongs to an
    overdamped mode far beyond the record's reach."""
    order, term = 0, 1.0
    while term > SERIES_REMAINDER or order < SERIES_MIN_ORDER:
        order += 1
        term *= rho_h / order
        if order > SERIES_MAX_ORDER or not term < float("inf"):
            raise ValueError(f"the exact steps span rho*H = {rho_h:.3g}: their peaks' Taylor series would need more "
                             f"than {SERIES_MAX_ORDER} terms")  # fmt: skip
    return order + 4


@kernel(inline="always")
def _series_at(b, n_c, sigma):
    """p(σ), p'(σ), p''(σ) of the polynomial p = Σ b[j]·σʲ, j < n_c (Horner's scheme)."""
    p = b[n_c - 1]
    d1 = d2 = 0.0
    for j in range(n_c - 2, -1, -1):
        d2 = d2 * sigma + d1
        d1 = d1 * sigma + p
        p = p * sigma + b[j]
    return p, d1, 2.0 * d2


@kernel(**INTERNAL)
def settle_crests(h, n, agx, agy, sx, sy, structure, crest, peaks):
    """The exact values of the n crests quintic_crests listed (crest.crests) over the step of
    h s that ends at the state of crest.series (exact.state_series: u⁽ʲ⁾ there, row j),
    raising their running peaks (records.Peaks). A quantity q, linear in u, has the Taylor
    series q(t₁ − σ) = Σ (−σ)ʲ/j!·q⁽ʲ⁾(t₁) about the end t₁; an absolute acceleration is ü +
    the ground's (agx, agy at t₁, rising at sx, sy m/s³ over the step). From the quintic's crest, Newton's steps on q' find the
    exact one; every value they visit is the motion's own, so the peak takes the largest.
    crest.coef: work, as long as a column of series."""
    crests, series, coef = crest.crests, crest.series, crest.coef
    storey_bottom, storey_top, storey_axes, centre = structure.storey_bottom, structure.storey_top, \
        structure.storey_axes, structure.centre  # fmt: skip
    col_storey, col_arm = structure.column_storey, structure.column_arm
    peak_col, peak_rot, peak_disp, peak_acc = peaks.column, peaks.storey_rotation, peaks.displacement, peaks.acceleration
    n_rows = series.shape[0]
    for i in range(n):
        kind = int(crests[i, 0])
        index = int(crests[i, 1])
        n_c = n_rows - 2 if kind == CREST_ACCELERATION else n_rows
        sign = 1.0
        for j in range(n_c):
            if kind == CREST_COLUMN or kind == CREST_TWIST:
                st = col_storey[index // 2] if kind == CREST_COLUMN else index
                dx, dy, rot = storey_deflection(series[j], storey_top[st], storey_bottom[st], storey_axes[st, 0],
                                                storey_axes[st, 1], centre)  # fmt: skip
                if kind == CREST_TWIST:
                    value = rot
                else:
                    axis = index % 2
                    value = (dx if axis == 0 else dy) + rot * col_arm[index // 2, axis]
            elif kind == CREST_GAUGE:
                st = peaks.gauges.storey[index]
                dx, dy, rot = storey_deflection(series[j], storey_top[st], storey_bottom[st], storey_axes[st, 0],
                                                storey_axes[st, 1], centre)  # fmt: skip
                value = gauge_linear(index, dx, dy, rot, peaks.gauges)
                if j == 0:
                    value += crests[i, 3]  # the plastic part over the step (_gauge_crests)
            elif kind == CREST_DISPLACEMENT:
                value = series[j, index]
            else:
                value = series[j + 2, index]
                if index % 3 < 2 and j < 2:
                    value += (agx if j == 0 else sx) if index % 3 == 0 else (agy if j == 0 else sy)
            coef[j] = sign * value
            sign *= -1.0 / (j + 1)  # the Taylor coefficient (−1)ʲ⁺¹/(j + 1)!
        sigma = (1.0 - crests[i, 2]) * h
        best = 0.0
        for _ in range(CREST_NEWTON_STEPS):
            p, dp, ddp = _series_at(coef, n_c, sigma)
            best = max(best, abs(p))
            if ddp == 0.0:
                break
            nxt = sigma - dp / ddp
            if not 0.0 <= nxt <= h or abs(nxt - sigma) <= 1e-15 * h:
                break
            sigma = nxt
        if kind == CREST_COLUMN:
            peak_col[index // 2, index % 2] = max(peak_col[index // 2, index % 2], best)
        elif kind == CREST_TWIST:
            peak_rot[index] = max(peak_rot[index], best)
        elif kind == CREST_GAUGE:
            peaks.gauges.peak[index] = max(peaks.gauges.peak[index], best)
        elif kind == CREST_DISPLACEMENT:
            peak_disp[index] = max(peak_disp[index], best)
        else:
            peak_acc[index] = max(peak_acc[index], best)


# columns of peaks_between's per-storey array `between`: the previous exact state's storey
# deflections (Ã_x, Ã_y, Δθ) and rates, the storey's largest column arms |ξ|, |η| (m) and a
# lower bound of its columns' running peaks along x, y (m)
BT_VALUE, BT_RATE, BT_ARM, BT_LOWEST, BT_BEND = 0, 3, 6, 8, 10
BT_COLUMNS = 13
KEPT_ROWS = 6  # peaks_between's `kept`: u, v, a_abs, ȧ_abs, a_rel, ä_abs less its ground part


@kernel(inline="always")
def _gauge_crests(s, h, between, storey_work, rx, ry, rt, bx, by, bt, floor_ratio, gauges, crests, n):
    """Lists the crests of storey s's force gauges over an exact step (quintic_crests): each
    is linear in the storey deflection, whose values, rates and second derivatives at the
    step's start `between` holds and at its end storey_work, (rx, ry, rt) and (bx, by, bt)
    give, plus its members' plastic part at the step's start (gauges.offset), constant over
    the step, which column 3 of its crests' rows keeps for settle_crests. Returns the new count."""
    for g in range(gauges.first[s], gauges.first[s + 1]):
        off = gauges.offset[g]  # the step's start's: constant over the step
        q0 = gauge_linear(g, between[s, BT_VALUE], between[s, BT_VALUE + 1], between[s, BT_VALUE + 2], gauges) + off
        m0 = gauge_linear(g, between[s, BT_RATE], between[s, BT_RATE + 1], between[s, BT_RATE + 2], gauges)
        c0 = gauge_linear(g, between[s, BT_BEND], between[s, BT_BEND + 1], between[s, BT_BEND + 2], gauges)
        q1 = gauge_linear(g, storey_work[s, 0], storey_work[s, 1], storey_work[s, 2], gauges) + off
        listed = quintic_crests(q0, m0, c0, q1, gauge_linear(g, rx, ry, rt, gauges),
                                gauge_linear(g, bx, by, bt, gauges), h, floor_ratio * gauge_floor(g, gauges), CREST_GAUGE,
                                g, crests, n)  # fmt: skip
        for row in range(n, listed):
            crests[row, 3] = off
        n = listed
    return n


def between_arrays(col_storey: np.ndarray, col_arm: np.ndarray, n_storeys: int) -> tuple[np.ndarray, np.ndarray]:
    """peaks_between's per-storey array (with the column arms filled in) and the storeys'
    first columns: storey s has columns first[s] … first[s + 1] − 1 (the assembly lists
    columns storey by storey)."""
    if np.any(np.diff(col_storey) < 0):
        raise ValueError("columns must be listed storey by storey")
    between = np.zeros((n_storeys, BT_COLUMNS))
    for axis in range(2):
        np.maximum.at(between[:, BT_ARM + axis], col_storey, np.abs(col_arm[:, axis]))
    first = np.searchsorted(col_storey, np.arange(n_storeys + 1)).astype(np.int64)
    return between, first


@kernel(**INTERNAL)
def peaks_between(h, smooth, u, a_abs, sx, sy, structure, exact, storey_work, peaks, f0, f1, g0, g1):
    """After update_peaks at an exact state (u, v = exact.v) with relative and absolute
    accelerations a_rel = exact.a_rel, a_abs: if `smooth`, the step of h s since the previous
    exact state was itself exact, and the crests over it of the column deflections, storey
    twists, floor displacements and absolute floor accelerations that may raise their running
    peaks are listed in `crests` (quintic_crests: the quintic through values, rates and second
    derivatives at both ends, where it passes floor_ratio × the running peak); then the state
    becomes the previous exact state. Returns the number of crests listed, for settle_crests to
    value exactly.

    rates: exact_point's (rates[2]: ȧ, rates[3]: ä less its ground part, rates[5], rates[6]:
    that part per unit ground-acceleration rate along X, Y); sx, sy: the ground acceleration's
    rate over the step, m/s³. storey_work holds the storey deflections at u (update_peaks has
    just filled it); kept (KEPT_ROWS, n_dof + 3) the previous state's u, v, a_abs, ȧ, a_rel and
    ä less its ground part; between (n_storeys, BT_COLUMNS) what the BT_ columns say; first the
    storeys' first columns (between_arrays). A storey's columns are looked at only where the
    bound for the whole storey (its deflection plus its largest arm times its twist) passes
    floor_ratio × the lowest of their peaks: most steps of most storeys are settled by that
    one comparison. (rates, kept, between, first, floor_ratio and crests: fields of exact,
    records.Exact.) Only the buildings whose floors (and storeys) are f0 … f1 − 1 and gauges
    g0 … g1 − 1 are looked at."""
    v, a_rel, rates, kept, between, first = exact.v, exact.a_rel, exact.rates, exact.kept, exact.between, exact.first
    floor_ratio, crests = exact.crest.floor_ratio, exact.crest.crests
    storey_bottom, storey_top, storey_axes, centre = structure.storey_bottom, structure.storey_top, \
        structure.storey_axes, structure.centre  # fmt: skip
    col_arm = structure.column_arm
    peak_col, peak_rot, peak_disp, peak_acc = peaks.column, peaks.storey_rotation, peaks.displacement, peaks.acceleration
    n = 0
    for s in range(f0, f1):
        rx, ry, rt = storey_deflection(v, storey_top[s], storey_bottom[s], storey_axes[s, 0], storey_axes[s, 1],
                                       centre)  # fmt: skip
        bx, by, bt = storey_deflection(a_rel, storey_top[s], storey_bottom[s], storey_axes[s, 0], storey_axes[s, 1],
                                       centre)  # fmt: skip
        if smooth:
            n = quintic_crests(between[s, BT_VALUE + 2], between[s, BT_RATE + 2], between[s, BT_BEND + 2],
                               storey_work[s, 2], rt, bt, h, floor_ratio * peak_rot[s], CREST_TWIST, s, crests,
                               n)  # fmt: skip
            twist = max(abs(between[s, BT_VALUE + 2]), abs(storey_work[s, 2]))
            twist_rate = abs(between[s, BT_RATE + 2]) + abs(rt)
            t0, t1 = bend_mismatch(between[s, BT_VALUE + 2], between[s, BT_RATE + 2], between[s, BT_BEND + 2],
                                   storey_work[s, 2], rt, bt, h)  # fmt: skip
            twist_bend = abs(t0) + abs(t1)
            for axis in range(2):
                r1 = rx if axis == 0 else ry
                b1 = bx if axis == 0 else by
                arm = between[s, BT_ARM + axis]
                q0 = between[s, BT_VALUE + axis]
                m0 = between[s, BT_RATE + axis]
                c0 = between[s, BT_BEND + axis]
                q1 = storey_work[s, axis]
                e0, e1 = bend_mismatch(q0, m0, c0, q1, r1, b1, h)
                reach = (max(abs(q0), abs(q1)) + arm * twist
                         + HERMITE_ARM * h * (abs(m0) + abs(r1) + arm * twist_rate)
                         + QUINTIC_BEND * (abs(e0) + abs(e1) + arm * twist_bend))  # fmt: skip
                if reach <= floor_ratio * between[s, BT_LOWEST + axis]:
                    continue
                lowest = np.inf
                for k in range(first[s], first[s + 1]):
                    a = col_arm[k, axis]
                    n = quintic_crests(q0 + between[s, BT_VALUE + 2] * a, m0 + between[s, BT_RATE + 2] * a,
                                       c0 + between[s, BT_BEND + 2] * a, q1 + storey_work[s, 2] * a, r1 + rt * a,
                                       b1 + bt * a, h, floor_ratio * peak_col[k, axis], CREST_COLUMN, 2 * k + axis,
                                       crests, n)  # fmt: skip
                    lowest = min(lowest, peak_col[k, axis])
                between[s, BT_LOWEST + axis] = lowest
            n = _gauge_crests(s, h, between, storey_work, rx, ry, rt, bx, by, bt, floor_ratio, peaks.gauges, crests, n)
        for j in range(3):
            between[s, BT_VALUE + j] = storey_work[s, j]
        between[s, BT_RATE] = rx
        between[s, BT_RATE + 1] = ry
        between[s, BT_RATE + 2] = rt
        between[s, BT_BEND] = bx
        between[s, BT_BEND + 1] = by
        between[s, BT_BEND + 2] = bt
    keep_offsets(peaks.gauges, g0, g1)
    if smooth:
        for d in range(3 * f0, 3 * f1):
            n = quintic_crests(kept[0, d], kept[1, d], kept[4, d], u[d], v[d], a_rel[d], h,
                               floor_ratio * peak_disp[d], CREST_DISPLACEMENT, d, crests, n)  # fmt: skip
            ground_part = sx * rates[5, d] + sy * rates[6, d]
            n = quintic_crests(kept[2, d], kept[3, d], kept[5, d] + ground_part, a_abs[d], rates[2, d],
                               rates[3, d] + ground_part, h, floor_ratio * peak_acc[d], CREST_ACCELERATION, d,
                               crests, n)  # fmt: skip
    for d in range(3 * f0, 3 * f1):
        kept[0, d] = u[d]
        kept[1, d] = v[d]
        kept[2, d] = a_abs[d]
        kept[3, d] = rates[2, d]
        kept[4, d] = a_rel[d]
        kept[5, d] = rates[3, d]
    return n
