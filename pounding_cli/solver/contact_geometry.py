"""Contact geometry of two floors at one level: overlap polygon, area, centroid, contact frame.

The narrow phase of the overlap-area impact model (Polycarpou & Komodromos 2013, section 4):
the overlap of two convex floor outlines (Sutherland–Hodgman clipping), its area A_c and
centroid C (where the impact forces act, 4.1), and the contact line through C parallel to
P1P2, the two points where the boundaries cross (4.2). Compiled with numba; plain float64
arrays in, everything written into buffers the caller owns, nothing allocated, no
exceptions, no NaN or inf for finite input. Lengths in m, areas in m².
"""

# Conventions
# -----------
# Plan view, z out of the page. Polygons are (n, 2) arrays of vertices, counter-clockwise,
# convex (collinear vertices allowed), n ≥ 3. Edge j runs from vertex j to vertex j+1 (mod n).
# A is the first polygon (the clipper), B the second (the subject being clipped).
#
#     a3 +---------------------------------+ a2
#        |                              P2 |
#        |                 b3 +------------+-----------------+ b2
#        |                    |::::::::::::|                 |
#        |       A            |:::: C :::::| --> n    B      |
#        |                    |::::::::::::|                 |
#        |                 b0 +------------+-----------------+ b1
#        |                              P1 |
#     a0 +---------------------------------+ a1
#
# The overlap (:::) is B clipped by the half-planes left of A's edges, written
# counter-clockwise. Overlap edge k runs from vertex k-1 to vertex k and carries a label:
#     label[k] = -(j+1)   the edge lies along A's edge j   (here P1 -> P2:  -2, A edge 1)
#     label[k] = +(i+1)   the edge is part of B's edge i   (b0 -> P1: +1, P2 -> b3: +3, b3 -> b0: +4)
# An edge is "A-owned" (label < 0) or "B-owned" (label > 0); contact_frame also calls it
# "both" when it lies on a boundary line of each polygon (collinear shared boundaries).
# P1, P2 are the crossings: overlap vertices where ownership switches between A and B. The
# A-owned chain of the overlap boundary is A's boundary inside B; it faces B. A run of "both"
# edges between an A edge and a B edge crosses at its arc-length midpoint (two equal-width
# slabs face to face: P1P2 runs across the middle of the strip). An edge nearly along the
# other's boundary (within about 6°, and closer to it than the overlap is thick) counts as
# partly shared, so a crossing slides continuously between the two rules as slabs move.
#
#     n   unit normal, perpendicular to P1P2, pointing from A into B: n·(ref_b − ref_a) > 0
#     t   unit tangent, t = ẑ × n = (−n_y, n_x); P1, P2 are ordered so (P2 − P1)·t ≥ 0
#
# Tolerance: tol = 1e-12·L + 4·ε·X, L the larger bounding-box side of A and B, X the largest
# coordinate magnitude, ε = 2.2e-16 (the second term is the rounding of coordinate
# differences, which dominates for small slabs far from the origin). A point is inside an
# edge's half-plane when its signed distance is ≥ −tol; vertices closer than tol merge; an
# overlap thinner than tol (2·A_c ≤ tol·perimeter) is no contact.

from __future__ import annotations

import numpy as np
from .jit import kernel
from .tunables import NEAR_SLOPE, SHALLOW_MARGIN

# contact_frame's result vector
AREA, CX, CY, P1X, P1Y, P2X, P2Y, NX, NY, TX, TY, DEPTH, LENGTH, N_CROSSINGS = range(14)
RESULT_SIZE = 14
RESULT_NAMES = ("area", "cx", "cy", "p1x", "p1y", "p2x", "p2y", "nx", "ny", "tx", "ty",
                "depth", "length", "n_crossings")  # fmt: skip

REL_TOL = 1e-12
"""Geometric tolerance relative to the polygons' size (see tolerance)."""
ROUNDING = 4 * 2.220446049250313e-16
"""Rounding floor of a coordinate difference, relative to the coordinates' magnitude."""


def clip_rows(na: int, nb: int) -> int:
    """Rows needed by each clip buffer (out, tmp, and their labels) for an na-gon and an nb-gon.

    Clipping a convex polygon by one half-plane adds at most one vertex, so the overlap has at
    most na + nb vertices; two rows spare absorb tolerance decisions on near-degenerate input.
    """
    return na + nb + 2


# Every kernel here is compiled by solver.jit.kernel (no reference counting, divisions that
# never raise); without reference counting, passing arrays to the small helpers costs no
# atomic operations, which were two thirds of overlap_frame's time (3.0 µs → 0.8 µs).
@kernel
def tolerance(a, na, b, nb):
    """Length tolerance tol = 1e-12·L + 4ε·X for polygons a[:na], b[:nb], m (see the header)."""
    size_a, big_a = _extent(a, na)
    size_b, big_b = _extent(b, nb)
    return REL_TOL * max(size_a, size_b) + ROUNDING * max(big_a, big_b)


@kernel
def _extent(poly, n):
    """(larger bounding-box side, largest |coordinate|) of poly[:n], m."""
    x0 = x1 = poly[0, 0]
    y0 = y1 = poly[0, 1]
    big = 0.0
    for k in range(n):
        x = poly[k, 0]
        y = poly[k, 1]
        x0 = min(x0, x)
        x1 = max(x1, x)
        y0 = min(y0, y)
        y1 = max(y1, y)
        big = max(big, abs(x), abs(y))
    return max(x1 - x0, y1 - y0), big


@kernel
def circles_apart(ca, ra, cb, rb):
    """Broad phase: True when the circles (centre ca, radius ra) and (cb, rb) cannot overlap.

    ca, cb are (2,) arrays in m, ra, rb radii in m. Touching circles are not apart.
    """
    dx = cb[0] - ca[0]
    dy = cb[1] - ca[1]
    r = ra + rb
    return dx * dx + dy * dy > r * r


@kernel
def bounding_circle(poly, n, centre):
    """Write the bounding-box centre of poly[:n] into centre (2,) and return the radius, m."""
    x0 = x1 = poly[0, 0]
    y0 = y1 = poly[0, 1]
    for k in range(n):
        x0 = min(x0, poly[k, 0])
        x1 = max(x1, poly[k, 0])
        y0 = min(y0, poly[k, 1])
        y1 = max(y1, poly[k, 1])
    cx = 0.5 * (x0 + x1)
    cy = 0.5 * (y0 + y1)
    r2 = 0.0
    for k in range(n):
        dx = poly[k, 0] - cx
        dy = poly[k, 1] - cy
        r2 = max(r2, dx * dx + dy * dy)
    centre[0] = cx
    centre[1] = cy
    return np.sqrt(r2)


# --- clipping ---------------------------------------------------------------------------


@kernel
def _append(dst, dst_label, k, cap, x, y, label, tol):
    """Append vertex (x, y) ending an edge labelled `label`, unless it repeats the last one."""
    if k > 0 and abs(x - dst[k - 1, 0]) <= tol and abs(y - dst[k - 1, 1]) <= tol:
        return k  # a zero-length edge: keep the earlier vertex and its edge's label
    if k >= cap:
        return k  # only reachable on input far from convex; never write past the buffer
    dst[k, 0] = x
    dst[k, 1] = y
    dst_label[k] = label
    return k + 1


@kernel
def _close(dst, dst_label, k, tol):
    """Drop closing vertices that repeat vertex 0; the edge into vertex 0 keeps a real label."""
    while k > 1 and abs(dst[k - 1, 0] - dst[0, 0]) <= tol and abs(dst[k - 1, 1] - dst[0, 1]) <= tol:
        dst_label[0] = dst_label[k - 1]
        k -= 1
    return k


@kernel
def _load(b, nb, dst, dst_label, cap, tol):
    """Copy B into dst; the edge ending at vertex i is B's edge i−1, label +i (+nb for i = 0)."""
    k = 0
    for i in range(nb):
        k = _append(dst, dst_label, k, cap, b[i, 0], b[i, 1], i if i > 0 else nb, tol)
    return _close(dst, dst_label, k, tol)


@kernel
def _cut(sx, sy, ds, x, y, de, ax, ay, ex, ey):
    """Where segment s→e crosses the line (ax, ay) + u·(ex, ey); ds, de: their cross products.

    Interpolated from the nearer endpoint, so the rounding is that of one short step; on an
    axis-parallel line the fixed coordinate is copied, so axis-aligned slabs clip exactly.
    """
    den = ds - de
    if abs(ds) <= abs(de):
        f = min(max(ds / den, 0.0), 1.0) if den != 0.0 else 0.0
        ix = sx + f * (x - sx)
        iy = sy + f * (y - sy)
    else:
        f = min(max(de / den, -1.0), 0.0) if den != 0.0 else 0.0
        ix = x + f * (x - sx)
        iy = y + f * (y - sy)
    if ex == 0.0:
        ix = ax
    if ey == 0.0:
        iy = ay
    return ix, iy


@kernel
def _clip_pass(src, src_label, n, dst, dst_label, cap, ax, ay, ex, ey, j, tol):
    """One Sutherland–Hodgman pass: keep src[:n] left of the line (ax, ay) + s·(ex, ey).

    A vertex is inside when its signed distance from the line is ≥ −tol. Subject edge s→e
    with label ℓ: in→in emits e (ℓ); in→out emits the crossing I (ℓ); out→in emits I with
    label −(j+1) (the new edge runs along A's edge j) and then e (ℓ); out→out emits nothing.
    Returns the number of vertices written to dst.
    """
    elen = np.sqrt(ex * ex + ey * ey)
    k = 0
    if elen <= tol:  # a repeated vertex of A: no half-plane, copy through
        for i in range(n):
            k = _append(dst, dst_label, k, cap, src[i, 0], src[i, 1], src_label[i], tol)
        return _close(dst, dst_label, k, tol)
    limit = -tol * elen  # cross products are distances times elen
    sx = src[n - 1, 0]
    sy = src[n - 1, 1]
    ds = ex * (sy - ay) - ey * (sx - ax)
    for i in range(n):
        x = src[i, 0]
        y = src[i, 1]
        de = ex * (y - ay) - ey * (x - ax)
        if de >= limit:
            if ds < limit:  # entering: the new edge I→e follows A's edge j up to I
                ix, iy = _cut(sx, sy, ds, x, y, de, ax, ay, ex, ey)
                k = _append(dst, dst_label, k, cap, ix, iy, -(j + 1), tol)
            k = _append(dst, dst_label, k, cap, x, y, src_label[i], tol)
        elif ds >= limit:  # leaving: the subject edge ends on the clipping line
            ix, iy = _cut(sx, sy, ds, x, y, de, ax, ay, ex, ey)
            k = _append(dst, dst_label, k, cap, ix, iy, src_label[i], tol)
        sx = x
        sy = y
        ds = de
    return _close(dst, dst_label, k, tol)


@kernel
def _area_perimeter(poly, m):
    """(area, perimeter) of poly[:m], m², m; the shoelace taken relative to vertex 0."""
    x0 = poly[0, 0]
    y0 = poly[0, 1]
    twice = 0.0
    perim = 0.0
    for k in range(m):
        p = k - 1 if k > 0 else m - 1
        px = poly[p, 0] - x0
        py = poly[p, 1] - y0
        qx = poly[k, 0] - x0
        qy = poly[k, 1] - y0
        twice += px * qy - qx * py
        perim += np.sqrt((qx - px) ** 2 + (qy - py) ** 2)
    return 0.5 * twice, perim


@kernel
def clip_overlap(a, na, b, nb, out, out_label, tmp, tmp_label):
    """Overlap polygon of convex polygons A = a[:na] and B = b[:nb], counter-clockwise, m.

    Sutherland–Hodgman with B as the subject, clipped by the half-plane of each of A's edges
    in turn. Writes the m overlap vertices into out[:m] and the label of the edge ending at
    each (−(j+1): along A's edge j, +(i+1): part of B's edge i) into out_label[:m]; returns m,
    0 when the overlap is empty or thinner than tol (2·area ≤ tol·perimeter: touching), and
    when A bounds no area (degenerate, or clockwise against the convention).
    out, tmp: float64 (≥ clip_rows(na, nb), 2); out_label, tmp_label: int64 (same rows). tmp
    and tmp_label are scratch. Consecutive vertices closer than tol are merged, so no edge
    has zero length; so are consecutive edges of one owner along one line (collinear input
    vertices), whose merged edge keeps one of their labels.
    """
    na = min(na, a.shape[0])
    nb = min(nb, b.shape[0])
    cap = min(out.shape[0], tmp.shape[0], out_label.shape[0], tmp_label.shape[0])
    if na < 3 or nb < 3 or cap < 3:
        return 0
    tol = tolerance(a, na, b, nb)
    area_a, perim_a = _area_perimeter(a, na)
    if not 2.0 * area_a > tol * perim_a:  # A degenerate (or clockwise): it bounds no area
        return 0
    # B goes into whichever buffer makes the last of the na passes land in out
    if na % 2 == 0:
        m = _load(b, nb, out, out_label, cap, tol)
    else:
        m = _load(b, nb, tmp, tmp_label, cap, tol)
    for j in range(na):
        if m < 3:
            return 0
        jn = j + 1 if j + 1 < na else 0
        ax = a[j, 0]
        ay = a[j, 1]
        ex = a[jn, 0] - ax
        ey = a[jn, 1] - ay
        if (na - j) % 2 == 1:  # this pass reads tmp, writes out (so does the last)
            m = _clip_pass(tmp, tmp_label, m, out, out_label, cap, ax, ay, ex, ey, j, tol)
        else:
            m = _clip_pass(out, out_label, m, tmp, tmp_label, cap, ax, ay, ex, ey, j, tol)
    m = _merge_collinear(out, out_label, m, tol)
    if m < 3:
        return 0
    area, perim = _area_perimeter(out, m)
    if not 2.0 * area > tol * perim:
        return 0
    return m


@kernel
def _merge_collinear(poly, label, m, tol):
    """Drop vertices between two edges of one owner that continue each other (the vertex within
    tol of the chord of its neighbours): collinear input vertices then make no difference.

    The merged edge keeps the label of its second part. Returns the new vertex count.
    """
    k = 0
    while k < m and m > 3:
        p = k - 1 if k > 0 else m - 1
        n = k + 1 if k + 1 < m else 0
        cx = poly[n, 0] - poly[p, 0]
        cy = poly[n, 1] - poly[p, 1]
        chord = np.sqrt(cx * cx + cy * cy)
        off = abs(cx * (poly[k, 1] - poly[p, 1]) - cy * (poly[k, 0] - poly[p, 0]))
        if (label[k] > 0) == (label[n] > 0) and chord > tol and off <= tol * chord:
            for i in range(k, m - 1):
                poly[i, 0] = poly[i + 1, 0]
                poly[i, 1] = poly[i + 1, 1]
                label[i] = label[i + 1]
            m -= 1
            k = max(k - 1, 0)  # the previous vertex has a new neighbour
        else:
            k += 1
    return m


# --- contact frame ----------------------------------------------------------------------


@kernel
def _edge_length(poly, m, k):
    """Length of overlap edge k (from vertex k−1 to vertex k), m."""
    p = k - 1 if k > 0 else m - 1
    return np.sqrt((poly[k, 0] - poly[p, 0]) ** 2 + (poly[k, 1] - poly[p, 1]) ** 2)


@kernel
def _line_gap(px, py, qx, qy, c, nc, tol):
    """How far segment pq lies from polygon c's boundary lines, m.

    The smallest, over c's edges running the same way as pq, of the larger distance of p and
    q from the edge's line; inf when no edge of c runs the same way.
    """
    dx = qx - px
    dy = qy - py
    best = np.inf  # squared distance
    for i in range(nc):
        i1 = i + 1 if i + 1 < nc else 0
        x0 = c[i, 0]
        y0 = c[i, 1]
        ex = c[i1, 0] - x0
        ey = c[i1, 1] - y0
        if ex * dx + ey * dy <= 0.0:
            continue
        el2 = ex * ex + ey * ey
        if el2 <= tol * tol:
            continue
        d = max(abs(ex * (py - y0) - ey * (px - x0)), abs(ex * (qy - y0) - ey * (qx - x0)))
        best = min(best, d * d / el2)
    return np.sqrt(best)


@kernel
def _share(poly, label, m, k, a, na, b, nb, tol, h):
    """Owner of overlap edge k, −1 (A), +1 (B) or 0 (both), and how nearly it is shared, β.

    d: how far the edge's endpoints lie from the nearest line of the other polygon's edges.
    d ≤ tol: the edge is on both boundaries, owner 0, β = 1. Otherwise it keeps its owner
    and β = (r − d)/(r − tol) falls linearly to 0 at d = r = min(h, NEAR_SLOPE·ℓ), with h the
    overlap's mean thickness and ℓ the edge's length: only an edge nearly along (within
    about 6°) and nearly on the other's boundary is partly shared. β lets the crossings next
    to it move continuously as it comes to lie along the other's boundary (see _crossing).
    Label 0 (never written by clip_overlap) is read as both.
    """
    p = k - 1 if k > 0 else m - 1
    px = poly[p, 0]
    py = poly[p, 1]
    qx = poly[k, 0]
    qy = poly[k, 1]
    if label[k] < 0:
        own = -1
        d = _line_gap(px, py, qx, qy, b, nb, tol)
    elif label[k] > 0:
        own = 1
        d = _line_gap(px, py, qx, qy, a, na, tol)
    else:
        return 0, 1.0
    if d <= tol:
        return 0, 1.0
    near = min(h, NEAR_SLOPE * np.sqrt((qx - px) ** 2 + (qy - py) ** 2))
    if d >= near:
        return own, 0.0
    return own, (near - d) / (near - tol)


@kernel
def _point_at(poly, m, k, s):
    """The boundary point at arc length s from vertex k (forward, counter-clockwise, if s ≥ 0)."""
    j = k
    if s >= 0.0:
        for _ in range(m):
            jn = j + 1 if j + 1 < m else 0
            ell = _edge_length(poly, m, jn)
            if s <= ell:
                f = s / ell if ell > 0.0 else 0.0
                return poly[j, 0] + f * (poly[jn, 0] - poly[j, 0]), poly[j, 1] + f * (poly[jn, 1] - poly[j, 1])
            s -= ell
            j = jn
    else:
        s = -s
        for _ in range(m):
            jp = j - 1 if j > 0 else m - 1
            ell = _edge_length(poly, m, j)
            if s <= ell:
                f = s / ell if ell > 0.0 else 0.0
                return poly[j, 0] + f * (poly[jp, 0] - poly[j, 0]), poly[j, 1] + f * (poly[jp, 1] - poly[j, 1])
            s -= ell
            j = jp
    return poly[k, 0], poly[k, 1]


@kernel
def _crossing(poly, label, m, k1, o1, k2, a, na, b, nb, tol, h):
    """Where the crossing between owned edge k1 (owner o1) and the next owned edge k2 lies.

    Between them lies a run of "both" edges (maybe none). The crossing is the arc-length
    midpoint of that run, extended backwards into k1's chain and forwards into k2's by the
    nearly-shared lengths Σ (Π β) ℓ (product of β along the walk), so it slides continuously
    from the vertex (β = 0) to the midpoint of the run an edge joins when its β reaches 1.
    Returns its arc length from vertex k1 (negative: behind it), m.
    """
    run = 0.0
    j = k1 + 1 if k1 + 1 < m else 0
    for _ in range(m):
        if j == k2:
            break
        run += _edge_length(poly, m, j)
        j = j + 1 if j + 1 < m else 0
    back = 0.0
    w = 1.0
    j = k1
    for _ in range(m):
        own, beta = _share(poly, label, m, j, a, na, b, nb, tol, h)
        w *= beta
        if own == -o1 or w <= 0.0:
            break
        back += w * _edge_length(poly, m, j)
        j = j - 1 if j > 0 else m - 1
    fwd = 0.0
    w = 1.0
    j = k2
    for _ in range(m):
        own, beta = _share(poly, label, m, j, a, na, b, nb, tol, h)
        w *= beta
        if own == o1 or w <= 0.0:
            break
        fwd += w * _edge_length(poly, m, j)
        j = j + 1 if j + 1 < m else 0
    return 0.5 * (run + fwd - back)


@kernel
def _gap(s0, s1, perim):
    """Arc length from boundary position s0 forward to s1 on a boundary of length perim, m."""
    g = s1 - s0
    if g < 0.0:
        g += perim
    return min(max(g, 0.0), perim)


@kernel
def _scan_crossings(poly, label, m, a, na, b, nb, tol, h, perim, tx, ty):
    """Walk the overlap boundary once and gather its crossings, coordinates relative to vertex 0.

    Returns (count, sums, start, end, lo, hi). sums = (Σw, Σw·x, Σw·y, Σw·x², Σw·x·y, Σw·y²)
    feed the weighted least-squares line, each crossing weighted by the shorter of the two
    boundary chains it joins, so a crossing pair born (or dying) with a vanishing chain
    enters (or leaves) the fit continuously. start: a crossing where an A chain begins
    (B → A); end: one where it ends (A → B); lo, hi: the crossings with the least and the
    greatest projection on (tx, ty). Points are (x, y) tuples.
    """
    x0 = poly[0, 0]
    y0 = poly[0, 1]
    count = 0
    sw = swx = swy = swxx = swxy = swyy = 0.0
    start = end = lo = hi = first = prev = (0.0, 0.0)
    t_lo = np.inf
    t_hi = -np.inf
    s_first = s_second = s_prev = s_prev2 = 0.0
    k0 = -1
    o0 = 0
    arc = 0.0  # arc length from vertex 0 to vertex k0
    for k in range(m):
        own, _ = _share(poly, label, m, k, a, na, b, nb, tol, h)
        if k > 0:
            arc += _edge_length(poly, m, k)
        if own != 0:
            k0 = k
            o0 = own
            break
    if k0 < 0:
        return count, (sw, swx, swy, swxx, swxy, swyy), start, end, lo, hi
    k1 = k0
    o1 = o0
    for _ in range(m):
        k2 = k1
        o2 = 0
        arc_k2 = arc  # arc length to the start of edge k2, i.e. to vertex k2 − 1
        for _ in range(m):
            k2 = k2 + 1 if k2 + 1 < m else 0
            o2, _ = _share(poly, label, m, k2, a, na, b, nb, tol, h)
            if o2 != 0:
                break
            arc_k2 += _edge_length(poly, m, k2)
        if o2 == -o1:
            off = _crossing(poly, label, m, k1, o1, k2, a, na, b, nb, tol, h)
            x, y = _point_at(poly, m, k1, off)
            x -= x0
            y -= y0
            s = (arc + off) % perim if perim > 0.0 else 0.0
            if count == 0:
                first = (x, y)
                s_first = s
            elif count == 1:
                s_second = s
            if count >= 2:  # the previous crossing's two chains are known now
                w = min(_gap(s_prev2, s_prev, perim), _gap(s_prev, s, perim))
                sw, swx, swy, swxx, swxy, swyy = _accumulate(
                    sw, swx, swy, swxx, swxy, swyy, w, prev[0], prev[1])  # fmt: skip
            s_prev2 = s_prev
            s_prev = s
            prev = (x, y)
            count += 1
            if o1 > 0:
                start = (x, y)
            else:
                end = (x, y)
            proj = x * tx + y * ty
            if proj < t_lo:
                t_lo = proj
                lo = (x, y)
            if proj > t_hi:
                t_hi = proj
                hi = (x, y)
        arc = arc_k2 + _edge_length(poly, m, k2)
        k1 = k2
        o1 = o2
        if k1 == k0:
            break
    if count >= 2:  # close the loop: the last crossing, then the first
        w = min(_gap(s_prev2, s_prev, perim), _gap(s_prev, s_first, perim))
        sw, swx, swy, swxx, swxy, swyy = _accumulate(sw, swx, swy, swxx, swxy, swyy, w, prev[0], prev[1])
        w = min(_gap(s_prev, s_first, perim), _gap(s_first, s_second, perim))
        sw, swx, swy, swxx, swxy, swyy = _accumulate(sw, swx, swy, swxx, swxy, swyy, w, first[0], first[1])
    return count, (sw, swx, swy, swxx, swxy, swyy), start, end, lo, hi


@kernel
def _accumulate(sw, swx, swy, swxx, swxy, swyy, w, x, y):
    """Add point (x, y) with weight w to the sums of a weighted scatter."""
    return sw + w, swx + w * x, swy + w * y, swxx + w * x * x, swxy + w * x * y, swyy + w * y * y


@kernel
def _owned_means(poly, label, m, a, na, b, nb, tol, h):
    """Length-weighted mean of the A-owned minus that of the B-owned boundary, relative, m.

    Returns (gx, gy, ok); ok is False when either part is empty.
    """
    ax = ay = al = bx = by = bl = 0.0
    for k in range(m):
        own, beta = _share(poly, label, m, k, a, na, b, nb, tol, h)
        if own == 0:
            continue
        p = k - 1 if k > 0 else m - 1
        ell = _edge_length(poly, m, k)
        mx = 0.5 * (poly[p, 0] + poly[k, 0]) - poly[0, 0]
        my = 0.5 * (poly[p, 1] + poly[k, 1]) - poly[0, 1]
        if own < 0:
            ax += ell * mx
            ay += ell * my
            al += ell
        else:
            bx += ell * mx
            by += ell * my
            bl += ell
    if al > 0.0 and bl > 0.0:
        return ax / al - bx / bl, ay / al - by / bl, True
    return 0.0, 0.0, False


@kernel
def _moments(poly, m):
    """Area, centroid and second moments about it, of poly[:m] relative to vertex 0.

    Returns (area, perimeter, cx, cy, Ixx, Ixy, Iyy) with (cx, cy) relative to vertex 0 and
    Ixx = ∫(x − cx)² dA etc. Relative coordinates keep tiny slivers far from the origin exact.
    """
    x0 = poly[0, 0]
    y0 = poly[0, 1]
    tw = s_x = s_y = s_xx = s_xy = s_yy = perim = 0.0
    for k in range(m):
        p = k - 1 if k > 0 else m - 1
        px = poly[p, 0] - x0
        py = poly[p, 1] - y0
        qx = poly[k, 0] - x0
        qy = poly[k, 1] - y0
        c = px * qy - qx * py
        tw += c
        s_x += (px + qx) * c
        s_y += (py + qy) * c
        s_xx += (px * px + px * qx + qx * qx) * c
        s_yy += (py * py + py * qy + qy * qy) * c
        s_xy += (px * qy + 2.0 * px * py + 2.0 * qx * qy + qx * py) * c
        perim += np.sqrt((qx - px) ** 2 + (qy - py) ** 2)
    area = 0.5 * tw
    if not (area > 0.0 and perim > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    cx = s_x / (3.0 * tw)
    cy = s_y / (3.0 * tw)
    ixx = s_xx / 12.0 - area * cx * cx
    iyy = s_yy / 12.0 - area * cy * cy
    ixy = s_xy / 24.0 - area * cx * cy
    return area, perim, cx, cy, ixx, ixy, iyy


@kernel
def _crossing_normal(count, sums, start, end, tol):
    """Normal from the crossings (relative coordinates): (nx, ny, found).

    Two: perpendicular to P1P2, turned clockwise from the A chain's direction start → end,
    which points from A into B. More: perpendicular to the weighted total-least-squares line
    (the principal axis of the crossings' scatter). found is False with fewer than two, or
    when they coincide within tol.
    """
    if count == 2:
        dx = end[0] - start[0]
        dy = end[1] - start[1]
        ell = np.sqrt(dx * dx + dy * dy)
        if ell > tol:
            return dy / ell, -dx / ell, True
    elif count > 2 and sums[0] > 0.0:
        sw, swx, swy, swxx, swxy, swyy = sums
        mx = swx / sw
        my = swy / sw
        sxx = swxx / sw - mx * mx
        syy = swyy / sw - my * my
        sxy = swxy / sw - mx * my
        if sxx + syy > tol * tol:
            theta = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)  # the line's direction
            return -np.sin(theta), np.cos(theta), True
    return 0.0, 0.0, False


@kernel
def _fallback_normal(rx, ry, ixx, ixy, iyy, tol):
    """Normal without crossings: along r = ref_b − ref_a; if |r| ≤ tol, along the minor
    principal axis of the overlap (second moments ixx, ixy, iyy: across its least width);
    if the overlap is isotropic, (1, 0)."""
    rl = np.sqrt(rx * rx + ry * ry)
    if rl > tol:
        return rx / rl, ry / rl
    if abs(ixx - iyy) + abs(ixy) > 1e-9 * (ixx + iyy):
        theta = 0.5 * np.arctan2(2.0 * ixy, ixx - iyy)  # the major axis
        return -np.sin(theta), np.cos(theta)
    return 1.0, 0.0


@kernel
def _extent_along(poly, m, nx, ny):
    """max − min of vertex·n over poly[:m] (taken relative to vertex 0), m."""
    lo = hi = 0.0
    for k in range(m):
        d = (poly[k, 0] - poly[0, 0]) * nx + (poly[k, 1] - poly[0, 1]) * ny
        lo = min(lo, d)
        hi = max(hi, d)
    return hi - lo


@kernel
def _chord(poly, m, y, nx, ny, tx, ty, ox, oy):
    """Length along n (m) of the convex polygon poly[:m]'s section at abscissa y along t
    (measured from (ox, oy)): the overlap's depth there."""
    lo = np.inf
    hi = -np.inf
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        yi = (poly[i, 0] - ox) * tx + (poly[i, 1] - oy) * ty
        yj = (poly[j, 0] - ox) * tx + (poly[j, 1] - oy) * ty
        if (yi - y) * (yj - y) > 0.0:
            continue
        zi = (poly[i, 0] - ox) * nx + (poly[i, 1] - oy) * ny
        zj = (poly[j, 0] - ox) * nx + (poly[j, 1] - oy) * ny
        if yi == yj:
            lo = min(lo, zi, zj)
            hi = max(hi, zi, zj)
        else:
            z = zi + (zj - zi) * (y - yi) / (yj - yi)
            lo = min(lo, z)
            hi = max(hi, z)
    return hi - lo if hi >= lo else 0.0


@kernel(inline="always")
def _cut_piece(y0, e0, r0, y1, e1, r1, g0, g1):
    """The part of the piece [y0, y1] (depth e and rate r linear along it) where the linear g,
    g0 at y0 and g1 at y1, is ≤ 0: (y0, e0, r0, y1, e1, r1), empty when y1 ≤ y0."""
    if g0 > 0.0 and g1 > 0.0:
        return y0, e0, r0, y0, e0, r0
    if g0 > 0.0 or g1 > 0.0:
        s = g0 / (g0 - g1)
        y = y0 + s * (y1 - y0)
        e = e0 + s * (e1 - e0)
        r = r0 + s * (r1 - r0)
        if g0 > 0.0:
            return y, e, r, y1, e1, r1
        return y0, e0, r0, y, e, r
    return y0, e0, r0, y1, e1, r1


@kernel(inline="always")
def kink_impulse(fall, share):
    """What the CDM's cells miss of the impulse, over Δt (N), of a force whose slope changes by
    fall/Δt (N/s) at a kink `share` of a step from the nearest grid point on the force's side
    (a point touching, share = depth/closing; a force ending): the midpoint rule integrates a
    kinked force with an error fall·Δt·(share − ½)²/2 (the integral from the kink to the
    cell's far end, against the cells' value; docs/theory.md §10, "The kinks")."""
    return 0.5 * fall * (share - 0.5) ** 2


@kernel(inline="always")
def _kinked(e, r):
    """kink_impulse of a point of depth e whose depth changes by r over a step, per k·Δt."""
    return kink_impulse(r, e / r) if r > 0.0 else 0.0


@kernel
def depth_profile(poly, m, nx, ny, tx, ty, ox, oy, work):
    """The depth along n of the convex overlap poly[:m] at its vertices' abscissae along t
    (from (ox, oy)), sorted: work[k] = (y, depth), k < the count returned with the largest
    depth (m); between them the depth is linear in y, and concave. work: (≥ m, 2)."""
    if m < 3:
        return 0, 0.0
    n = 0
    for k in range(m):  # insertion sort of the abscissae
        y = (poly[k, 0] - ox) * tx + (poly[k, 1] - oy) * ty
        i = n
        while i > 0 and work[i - 1, 0] > y:
            work[i, 0] = work[i - 1, 0]
            i -= 1
        work[i, 0] = y
        n += 1
    deepest = 0.0
    for k in range(n):
        work[k, 1] = _chord(poly, m, work[k, 0], nx, ny, tx, ty, ox, oy)
        deepest = max(deepest, work[k, 1])
    return n, deepest


@kernel
def shallow_moments(profile, n, r0, dr, whole, rest):
    """Moments over a depth profile (depth_profile: profile[:n] = (y, depth e)) of its part no
    deeper than the rate r = r0 + dr·y, the depth the bodies gain (or lose) along n over a step
    there, m (the bodies' relative turning makes it vary along the line): I0 = ∫h dy and
    I1 = ∫h·y dy with h = r/2·(σ − ½)², σ = e/r.

    These are the points that touched within the last step (or part within the next): the
    CDM's midpoint rule misses k·r/2·(σ − ½)² of each one's impulse per unit length, over Δt
    (kink_impulse). Simpson's rule (over four panels on the shallow part, where a rate varying
    along the line makes the integrand rational) is exact where r is uniform. whole: the
    overlap is new (an episode's first step), so every point counts, the deeper than r as
    σ = 1 (they came closer than the tolerance a step ago). rest (6,): ∫1, ∫e, ∫e², ∫y, ∫e·y,
    ∫e²·y dy over the deeper part, for when it parts after all; zero when both ends (the
    shallowest points: the depth is concave) are deeper than SHALLOW_MARGIN·r."""
    for k in range(6):
        rest[k] = 0.0
    if n < 2:
        return 0.0, 0.0
    if not whole and (profile[0, 1] > SHALLOW_MARGIN * (r0 + dr * profile[0, 0])
                      and profile[n - 1, 1] > SHALLOW_MARGIN * (r0 + dr * profile[n - 1, 0])):  # fmt: skip
        return 0.0, 0.0
    i0 = 0.0
    i1 = 0.0
    for k in range(n - 1):
        ya = profile[k, 0]
        yb = profile[k + 1, 0]
        if not yb > ya:
            continue
        ea = profile[k, 1]
        eb = profile[k + 1, 1]
        ra = r0 + dr * ya
        rb = r0 + dr * yb
        # the shallow part: e ≤ r and r > 0
        y0, e0, q0, y1, e1, q1 = _cut_piece(ya, ea, ra, yb, eb, rb, ea - ra, eb - rb)
        y0, e0, q0, y1, e1, q1 = _cut_piece(y0, e0, q0, y1, e1, q1, -q0, -q1)
        if y1 > y0:  # composite Simpson over four panels (exact for a uniform rate)
            w = (y1 - y0) / 12.0
            for j in range(5):
                f = j / 4.0
                c = 1.0 if j == 0 or j == 4 else (4.0 if j % 2 else 2.0)
                y = y0 + f * (y1 - y0)
                h = _kinked(e0 + f * (e1 - e0), q0 + f * (q1 - q0))
                i0 += w * c * h
                i1 += w * c * h * y
        # the deeper part: e > r
        y0, e0, q0, y1, e1, q1 = _cut_piece(ya, ea, ra, yb, eb, rb, ra - ea, rb - eb)
        if y1 > y0 and whole:  # σ = 1: h = r/8
            w = (y1 - y0) / 6.0
            ym = 0.5 * (y0 + y1)
            qm = 0.5 * (q0 + q1)
            i0 += w * (q0 + 4.0 * qm + q1) / 8.0
            i1 += w * (q0 * y0 + 4.0 * qm * ym + q1 * y1) / 8.0
        elif y1 > y0:
            w = (y1 - y0) / 6.0
            ym = 0.5 * (y0 + y1)
            em = 0.5 * (e0 + e1)
            rest[0] += y1 - y0
            rest[1] += w * (e0 + 4.0 * em + e1)
            rest[2] += w * (e0 * e0 + 4.0 * em * em + e1 * e1)
            rest[3] += w * (y0 + 4.0 * ym + y1)
            rest[4] += w * (e0 * y0 + 4.0 * em * ym + e1 * y1)
            rest[5] += w * (e0 * e0 * y0 + 4.0 * em * em * ym + e1 * e1 * y1)
    return i0, i1


@kernel
def contact_frame_xy(poly, label, m, a, na, b, nb, rax, ray, rbx, rby, result):
    """contact_frame with the reference points as scalars (rax, ray), (rbx, rby), m: for callers
    that hold them in locals (the time loop), so no (2,) array need exist."""
    if result.shape[0] < RESULT_SIZE:
        return False
    for i in range(RESULT_SIZE):
        result[i] = 0.0
    m = min(m, poly.shape[0], label.shape[0])
    na = min(na, a.shape[0])
    nb = min(nb, b.shape[0])
    if m < 3 or na < 3 or nb < 3:
        return False
    tol = tolerance(a, na, b, nb)
    area, perim, cx, cy, ixx, ixy, iyy = _moments(poly, m)
    if not area > 0.0:
        return False
    h = 2.0 * area / perim  # mean thickness: the penetration of a long thin strip
    x0 = poly[0, 0]
    y0 = poly[0, 1]
    rx = rbx - rax
    ry = rby - ray
    # crossings, and the normal they define; without them, a fallback; then the sign
    count, sums, start, end, _, _ = _scan_crossings(poly, label, m, a, na, b, nb, tol, h, perim, 0.0, 0.0)
    nx, ny, found = _crossing_normal(count, sums, start, end, tol)
    if not found:
        nx, ny = _fallback_normal(rx, ry, ixx, ixy, iyy, tol)
    s = nx * rx + ny * ry
    if abs(s) > tol:  # from A into B by the reference points
        flip = s < 0.0
    else:  # by the boundaries: A's part of the overlap boundary lies on B's side
        gx, gy, ok = _owned_means(poly, label, m, a, na, b, nb, tol, h)
        flip = ok and nx * gx + ny * gy < -tol
    if flip:
        nx = -nx
        ny = -ny
    tx = -ny
    ty = nx
    # P1, P2 ordered along t, and the contact length
    if count == 2:
        p1, p2 = (start, end) if (end[0] - start[0]) * tx + (end[1] - start[1]) * ty >= 0.0 else (end, start)
        length = np.sqrt((p2[0] - p1[0]) ** 2 + (p2[1] - p1[1]) ** 2)
    elif count > 2:
        _, _, _, _, p1, p2 = _scan_crossings(poly, label, m, a, na, b, nb, tol, h, perim, tx, ty)
        length = (p2[0] - p1[0]) * tx + (p2[1] - p1[1]) * ty
    else:
        p1 = (cx, cy)
        p2 = (cx, cy)
        length = 0.0
    result[AREA] = area
    result[CX] = x0 + cx
    result[CY] = y0 + cy
    result[P1X] = x0 + p1[0]
    result[P1Y] = y0 + p1[1]
    result[P2X] = x0 + p2[0]
    result[P2Y] = y0 + p2[1]
    result[NX] = nx
    result[NY] = ny
    result[TX] = tx
    result[TY] = ty
    result[DEPTH] = _extent_along(poly, m, nx, ny)
    result[LENGTH] = length
    result[N_CROSSINGS] = count
    return True


@kernel
def contact_frame(poly, label, m, a, na, b, nb, ref_a, ref_b, result):
    """Contact frame of the overlap poly[:m] (labels from clip_overlap) of A = a[:na], B = b[:nb].

    ref_a, ref_b: (2,) reference points of A and B (the slabs' centroids), m, fixing the sign
    of n. Fills result[:RESULT_SIZE] (see the index constants) and returns True when the
    overlap has positive area; otherwise zeros and False.

    - AREA, (CX, CY): shoelace area and centroid, m², m: the action point.
    - (P1X, P1Y), (P2X, P2Y): the boundary crossings, ordered along t; a run of edges on both
      boundaries counts by its arc-length midpoint. N_CROSSINGS: how many there are.
    - (NX, NY): unit normal from A into B. Two crossings: ⟂ P1P2. More: ⟂ the least-squares
      line through them (P1, P2 the extreme ones along t). Fewer (containment, identical
      outlines): along ref_b − ref_a; if that is shorter than tol, across the overlap's least
      width (its minor principal axis), or (1, 0) if it has none. Sign: n·(ref_b − ref_a) > 0,
      or when that is within tol of 0, from the B-owned towards the A-owned boundary.
    - (TX, TY) = ẑ × n. DEPTH: extent of the overlap along n, m. LENGTH: |P1P2|, m (extent of
      the crossings along t when more than two; 0 when fewer).
    """
    return contact_frame_xy(poly, label, m, a, na, b, nb, ref_a[0], ref_a[1], ref_b[0], ref_b[1], result)


@kernel
def overlap_frame(a, na, b, nb, ref_a, ref_b, out, out_label, tmp, tmp_label, result):
    """clip_overlap then contact_frame: True and result filled when A and B overlap.

    Buffers as for clip_overlap (out, tmp: ≥ clip_rows(na, nb) rows of 2; out_label,
    tmp_label: int64, as many) and contact_frame (result: ≥ RESULT_SIZE); ref_a, ref_b: (2,).
    On no contact result is zeroed and out holds nothing of use.
    """
    m = clip_overlap(a, na, b, nb, out, out_label, tmp, tmp_label)
    if m == 0:
        if result.shape[0] >= RESULT_SIZE:
            for i in range(RESULT_SIZE):
                result[i] = 0.0
        return False
    return contact_frame(out, out_label, m, a, na, b, nb, ref_a, ref_b, result)
