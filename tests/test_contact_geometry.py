"""The contact geometry kernel against shapely, exact arithmetic and closed forms.

Accuracy. The overlap's area and centroid are shoelace sums over a handful of vertices. The
only error is rounding: each computed crossing point is off by about ε·X (ε = 2.2e-16, X the
largest coordinate), and the area inherits that error times the overlap's perimeter P. For an
overlap of thickness w that is a relative error of about 2ε·X/w: 1e-15 to 1e-13 for overlaps a
metre thick within a kilometre of the origin, 2.3e-11 at worst among the random pairs here (thin
overlaps of small polygons far from the origin; `python docs/measure_validation.py geometry`).
So 1e-9 relative is a tolerance with margin that still catches any wrong vertex or formula —
until the overlap is thinner than about 4e-7·X (4 µm at 10 m from the origin): then no
double-precision computation from these coordinates, shapely's included, resolves the area to
1e-9, and an absolute term for the rounding takes over:

    |ΔA| ≤ 1e-9·A + 4ε·X·P           |ΔC| ≤ 1e-9·L + 4ε·X·P·D/A

(L the polygons' size, D the overlap's diameter: a misplaced sliver of area δA moves the
centroid by up to δA·D/A). test_tiny_penetrations_against_exact_arithmetic shows against
rational arithmetic that the kernel stays within ε·X·P of the exact area of the given floats.
"""

from __future__ import annotations

import math
import timeit
import tracemalloc
from fractions import Fraction

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from numba import njit
from numba.core.runtime import _nrt_python, rtsys
from numpy.testing import assert_allclose
from shapely.geometry.polygon import orient

from pounding_cli.solver.contact_geometry import (
    AREA,
    CX,
    CY,
    DEPTH,
    LENGTH,
    N_CROSSINGS,
    NX,
    NY,
    P1X,
    P1Y,
    P2X,
    P2Y,
    RESULT_SIZE,
    TX,
    TY,
    bounding_circle,
    circles_apart,
    clip_overlap,
    clip_rows,
    contact_frame,
    depth_profile,
    overlap_frame,
    shallow_moments,
    tolerance,
)

EPS = np.finfo(float).eps
ROWS = clip_rows(12, 12)


def settings_for(n: int):
    """Fixed-seed hypothesis settings: the same n examples on every run, no example database."""
    return settings(
        derandomize=True,
        max_examples=n,
        database=None,
        deadline=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
    )


# --- helpers ------------------------------------------------------------------------------


class Buffers:
    """The caller-owned buffers of one overlap_frame call."""

    def __init__(self, rows: int = ROWS) -> None:
        self.out = np.zeros((rows, 2))
        self.tmp = np.zeros((rows, 2))
        self.out_label = np.zeros(rows, dtype=np.int64)
        self.tmp_label = np.zeros(rows, dtype=np.int64)
        self.result = np.full(RESULT_SIZE, np.nan)


def frame(a, b, ref_a=None, ref_b=None, bufs=None):
    """(contact?, result, overlap vertices, labels) for polygons a, b; refs default to centroids."""
    a = np.ascontiguousarray(a, dtype=float)
    b = np.ascontiguousarray(b, dtype=float)
    bufs = bufs or Buffers(clip_rows(len(a), len(b)))
    ref_a = centroid(a) if ref_a is None else np.asarray(ref_a, dtype=float)
    ref_b = centroid(b) if ref_b is None else np.asarray(ref_b, dtype=float)
    ok = overlap_frame(a, len(a), b, len(b), ref_a, ref_b, bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label,
                       bufs.result)  # fmt: skip
    m = clip_overlap(a, len(a), b, len(b), bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label)
    return ok, bufs.result.copy(), bufs.out[:m].copy(), bufs.out_label[:m].copy()


def centroid(v: np.ndarray) -> np.ndarray:
    c = shapely.Polygon(v).centroid
    return np.array([c.x, c.y])


def rectangle(x0, y0, w, h) -> np.ndarray:
    return np.array([(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)], dtype=float)


def rotate(v: np.ndarray, angle: float, about=(0.0, 0.0)) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    p = np.asarray(v, dtype=float) - about
    return np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]]) + about


def angle_between(n1, n2) -> float:
    return abs(math.atan2(n1[0] * n2[1] - n1[1] * n2[0], n1[0] * n2[0] + n1[1] * n2[1]))


def check_frame(a, b, ref_a=None, ref_b=None, label=""):
    """Everything that must hold for any pair: shapely's area and centroid, a unit orthonormal
    frame pointing from A into B, finite numbers. Returns (contact?, result)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    ref_a = centroid(a) if ref_a is None else np.asarray(ref_a, dtype=float)
    ref_b = centroid(b) if ref_b is None else np.asarray(ref_b, dtype=float)
    ok, r, poly, labels = frame(a, b, ref_a, ref_b)
    assert np.all(np.isfinite(r)), f"{label}: non-finite result {r}"
    inter = shapely.intersection(shapely.Polygon(a), shapely.Polygon(b))
    tol = tolerance(a, len(a), b, len(b))
    big = max(np.abs(a).max(), np.abs(b).max())
    size = max(np.ptp(a, axis=0).max(), np.ptp(b, axis=0).max())
    perimeter = inter.length
    floor = 4 * EPS * big * perimeter  # the rounding of the crossing points, see the module docstring
    area = inter.area
    centre = (inter.centroid.x, inter.centroid.y) if area > 0 else (np.inf, np.inf)
    if ok:
        agree = abs(r[AREA] - area) <= 1e-9 * area + floor
    else:
        agree = area <= tol * perimeter + floor
    if not agree:
        # GEOS is not infallible on near-coincident outlines (two triangles 1e-48 m apart came
        # back as an empty MULTIPOINT). Where the kernel and shapely disagree, the exact overlap
        # of the same float polygons (rational arithmetic) decides.
        area, cx, cy, perimeter = exact_overlap(a, b)
        centre = (cx, cy)
        floor = 4 * EPS * big * perimeter
    if not ok:
        # no contact: the overlap is empty or thinner than tol
        assert area <= tol * perimeter + floor, f"{label}: missed an overlap of {area} m²"
        assert np.all(r == 0.0), label
        return ok, r
    assert len(poly) >= 3 and np.all(np.abs(labels) >= 1), label
    assert r[AREA] > 0, label
    assert abs(r[AREA] - area) <= 1e-9 * area + floor, f"{label}: area {r[AREA]} vs {area}"
    diameter = math.dist(*np.reshape(shapely.Polygon(poly).bounds, (2, 2)))
    c_tol = 1e-9 * size + floor * diameter / area
    if math.dist(r[CX:CY + 1], centre) > c_tol:
        area, cx, cy, _ = exact_overlap(a, b)
        centre = (cx, cy)
    assert math.dist(r[CX:CY + 1], centre) <= c_tol, f"{label}: centroid {r[CX:CY + 1]} vs {centre}"
    n = r[NX:NY + 1]
    t = r[TX:TY + 1]
    assert abs(math.hypot(*n) - 1) <= 1e-12, f"{label}: |n| = {math.hypot(*n)}"
    assert t[0] == -n[1] and t[1] == n[0], f"{label}: t ≠ ẑ × n"
    assert abs(n @ t) <= 1e-15
    # the sign rule: n·(ref_b − ref_a) > 0 unless that projection is within tol of zero
    s = n @ (ref_b - ref_a)
    assert s > 0 or abs(s) <= tol, f"{label}: n·(ref_b − ref_a) = {s}"
    # depth: the overlap's extent along n
    ring = poly if inter.geom_type != "Polygon" else np.asarray(inter.exterior.coords)
    along = ring @ n
    assert abs(r[DEPTH] - np.ptp(along)) <= 1e-9 * size + 8 * EPS * big, f"{label}: depth"
    # crossings: an even count; P1, P2 on the overlap's boundary, in order along t
    count = r[N_CROSSINGS]
    assert count == int(count) and int(count) % 2 == 0, label
    if count >= 2:
        p1, p2 = r[P1X:P1Y + 1], r[P2X:P2Y + 1]
        boundary = shapely.Polygon(poly).exterior
        for p in (p1, p2):
            assert boundary.distance(shapely.Point(p)) <= 1e-9 * size + 8 * EPS * big, f"{label}: P off boundary"
        assert (p2 - p1) @ t >= -1e-12 * size
        assert r[LENGTH] >= 0
    else:
        assert r[LENGTH] == 0
    return ok, r


# --- strategies ---------------------------------------------------------------------------

unit = st.floats(-1.0, 1.0, allow_nan=False)


@st.composite
def convex_polygons(draw, scale=None):
    """The convex hull of 3–12 random points, scaled by 0.1–100 m, counter-clockwise.

    The points come from a drawn seed (drawing 24 floats one by one would triple the run
    time); hypothesis explores the scales and placements, where the edge cases live."""
    n = draw(st.integers(3, 12))
    points = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).uniform(-1, 1, (n, 2))
    hull = shapely.MultiPoint(points).convex_hull
    assume(hull.geom_type == "Polygon" and hull.area > 1e-3)
    v = np.asarray(orient(hull, 1.0).exterior.coords)[:-1]
    s = draw(st.floats(0.1, 100.0)) if scale is None else scale
    return v * s


@st.composite
def polygon_pairs(draw):
    """A at up to ±500 m, B placed from A's centre at 0–1.3 times the sum of their radii."""
    a = draw(convex_polygons())
    b = draw(convex_polygons())
    a = a + np.array(draw(st.tuples(st.floats(-500, 500), st.floats(-500, 500))))
    ra = np.ptp(a, axis=0).max()
    rb = np.ptp(b, axis=0).max()
    angle = draw(st.floats(0, 2 * math.pi))
    reach = draw(st.floats(0.0, 1.3)) * (ra + rb) / 2
    shift = a.mean(axis=0) - b.mean(axis=0) + reach * np.array([math.cos(angle), math.sin(angle)])
    return a, b + shift


def with_collinear_vertices(v: np.ndarray, every: int) -> np.ndarray:
    """Insert each edge's midpoint (and a point at a third) as extra, collinear vertices."""
    out = []
    for k in range(len(v)):
        p, q = v[k], v[(k + 1) % len(v)]
        out.append(p)
        if k % every == 0:
            out.append(p + (q - p) / 3)
            out.append(p + (q - p) / 2)
    return np.array(out)


# --- against shapely: random pairs and degenerate families ---------------------------------


@settings_for(6500)
@given(polygon_pairs())
def test_random_pairs_match_shapely(pair):
    """6,500 random convex pairs, each both ways round (13,000 frames): overlaps of every kind,
    or none; see the module docstring for why 1e-9 (plus the rounding of sliver vertices) is
    the right tolerance. Swapping the bodies keeps the overlap and turns the normal round.
    With the degenerate families below, 12,000 examples: the issue asks for at least 10,000
    pairs; every example passes, so the margin costs run time only (~7 s per 1,000 here)."""
    a, b = pair
    ok, r = check_frame(a, b, label="random")
    ok2, r2 = check_frame(b, a, label="random, swapped")
    assert ok == ok2
    if ok and r[N_CROSSINGS] == r2[N_CROSSINGS] == 2:
        assert angle_between(r[NX:NY + 1], -r2[NX:NY + 1]) <= 1e-6


@settings_for(1500)
@given(polygon_pairs(), st.integers(1, 3))
def test_collinear_vertices_match_shapely(pair, every):
    """Polygons with extra collinear vertices on their edges: same overlap, same frame."""
    a, b = pair
    a2, b2 = with_collinear_vertices(a, every), with_collinear_vertices(b, every)
    ok, r = check_frame(a2, b2, label="collinear")
    ok0, r0 = frame(a, b)[:2]
    assert ok == ok0
    if ok:
        size = max(np.ptp(a, axis=0).max(), np.ptp(b, axis=0).max())
        assert_allclose(r[AREA], r0[AREA], rtol=1e-9, atol=4 * EPS * np.abs(a).max() * size)
        if r[N_CROSSINGS] == r0[N_CROSSINGS] == 2:
            assert angle_between(r[NX:NY + 1], r0[NX:NY + 1]) <= 1e-6


@settings_for(1000)
@given(
    st.floats(1.0, 30.0), st.floats(1.0, 30.0), st.floats(1.0, 30.0), st.floats(1e-6, 0.5),
    st.floats(0, 2 * math.pi), st.tuples(st.floats(-300, 300), st.floats(-300, 300)),
)  # fmt: skip
def test_equal_widths_face_to_face(width_a, width_b, height, penetration, angle, origin):
    """Two rectangles of equal height pressed face to face, rotated and moved together: the
    top and bottom boundaries coincide (up to the rounding of the rotation). The frame is the
    face's: n along the rotated x axis, P1P2 across the middle of the strip, length = height."""
    delta = penetration * min(width_a, width_b)
    a = rotate(rectangle(0, 0, width_a, height), angle) + origin
    b = rotate(rectangle(width_a - delta, 0, width_b, height), angle) + origin
    ok, r = check_frame(a, b, label="equal widths")
    assert ok
    axis = np.array([math.cos(angle), math.sin(angle)])
    size = max(width_a, width_b, height)
    big = max(np.abs(a).max(), np.abs(b).max())
    assert angle_between(r[NX:NY + 1], axis) <= 1e-9
    # δ itself is only represented to ε·X once added to coordinates of size X
    assert_allclose(r[AREA], delta * height, rtol=1e-9, atol=4 * EPS * big * 2 * (height + delta))
    assert_allclose(r[DEPTH], delta, rtol=1e-6, atol=1e-9 * size)
    assert_allclose(r[LENGTH], height, rtol=1e-9)
    middle = rotate(np.array([[width_a - delta / 2, 0.0], [width_a - delta / 2, height]]), angle) + origin
    assert_allclose(r[P1X:P2Y + 1], middle.ravel(), atol=1e-9 * size)


@settings_for(500)
@given(convex_polygons(scale=10.0), st.floats(0.05, 0.95), st.floats(0.1, 3.0), st.floats(-1.5, 1.5))
def test_vertex_exactly_on_an_edge(a, where, reach, turn):
    """B's vertex lies exactly on A's edge (B a triangle with its apex there, pointing out of A
    or into it): the shared point must not leave a zero-length edge in the overlap."""
    p, q = a[0], a[1]
    apex = p + where * (q - p)
    outward = np.array([q[1] - p[1], p[0] - q[0]]) / math.dist(p, q)
    along = (q - p) / math.dist(p, q)
    for side in (1.0, -1.0):
        d = rotate(side * outward[None, :], turn)[0]
        base = apex + reach * d * 3
        b = np.array([apex, base + reach * along * 2, base - reach * along * 2])
        if shapely.Polygon(b).exterior.is_ccw is False:
            b = b[::-1]
        ok, r, poly, _ = frame(a, b)
        check_frame(a, b, label="vertex on edge")
        if ok:
            edges = np.diff(np.vstack([poly, poly[:1]]), axis=0)
            assert np.all(np.hypot(*edges.T) > tolerance(a, len(a), b, len(b)))


@settings_for(500)
@given(convex_polygons(), st.floats(0.05, 0.9), st.tuples(unit, unit), st.floats(0, 2 * math.pi))
def test_one_inside_the_other(a, shrink, shift, angle):
    """A small B inside A (and A inside B): the overlap is the inner polygon, no crossings,
    n along ref_b − ref_a."""
    inner = rotate((a - a.mean(axis=0)) * shrink, angle) * 0.5 + a.mean(axis=0)
    inner = inner + np.array(shift) * 0.05 * np.ptp(a, axis=0).max()
    assume(shapely.Polygon(a).contains(shapely.Polygon(inner)))
    for outer_first in (True, False):
        x, y = (a, inner) if outer_first else (inner, a)
        ok, r = check_frame(x, y, label="inside")
        assert ok and r[N_CROSSINGS] == 0
        d = centroid(y) - centroid(x)
        if np.hypot(*d) > 1e-9 * np.ptp(a, axis=0).max():
            assert angle_between(r[NX:NY + 1], d) <= 1e-9


@settings_for(300)
@given(convex_polygons())
def test_identical_polygons(a):
    """A on itself: the overlap is A; no crossings; the references coincide, so n falls back
    to the overlap's least width (or (1, 0)) — defined, unit, finite."""
    ok, r = check_frame(a, a.copy(), label="identical")
    assert ok and r[N_CROSSINGS] == 0 and r[LENGTH] == 0
    assert_allclose(r[AREA], shapely.Polygon(a).area, rtol=1e-12)


@settings_for(500)
@given(convex_polygons(), st.integers(0, 11), st.floats(0, 2 * math.pi), st.floats(0.0, 1.0), st.booleans())
def test_touching_only_is_no_contact(a, k, angle, where, at_vertex):
    """B touching A along (part of) an edge, or at one vertex only: area 0, no contact."""
    k %= len(a)
    p, q = a[k], a[(k + 1) % len(a)]
    length = math.dist(p, q)
    along = (q - p) / length
    outward = np.array([along[1], -along[0]])
    if at_vertex:  # a square balanced on A's vertex p, outside A
        corner = rotate(rectangle(0, 0, length, length), angle)
        corner = corner - corner[np.argmin(corner @ outward)]
        b = corner + p
        assume(shapely.Polygon(a).intersection(shapely.Polygon(b)).area == 0)
    else:  # a rectangle lying on the edge, outside A, its base shifted along the edge
        s = where * length
        base = p + along * s
        b = np.array([base, base + outward * length, base + (along + outward) * length, base + along * length])
    ok, r = check_frame(a, b, label="touching")
    assert not ok


@settings_for(1200)
@given(
    st.floats(-9.0, -6.0), st.floats(0, 2 * math.pi), st.floats(-5.0, 5.0),
    st.tuples(st.floats(-100, 100), st.floats(-100, 100)), st.booleans(),
)  # fmt: skip
def test_tiny_penetrations_match_shapely(log_delta, angle, shift, origin, rotated):
    """10 m slabs pressed together by 1e-9 … 1e-6 m: contact, and the strip's area."""
    delta = 10.0**log_delta
    a = rectangle(0, 0, 10, 10)
    b = rectangle(10 - delta, shift, 10, 10)
    if rotated:
        a, b = rotate(a, angle) + origin, rotate(b, angle) + origin
    ok, r = check_frame(a, b, label="tiny")
    assert ok
    if not rotated:  # no rounding beyond the input's: exact to 1e-9 for the δ represented
        delta = 10 - b[0, 0]
        assert_allclose(r[AREA], delta * (min(10, b[2, 1]) - max(0, b[0, 1])), rtol=1e-9)


def exact_overlap(a: np.ndarray, b: np.ndarray) -> tuple[float, float, float, float]:
    """Area, centroid and perimeter of the overlap of the given float polygons, computed in
    rational arithmetic (Sutherland–Hodgman without a tolerance; only the results are rounded)."""
    poly = [(Fraction(x), Fraction(y)) for x, y in b]
    clip = [(Fraction(x), Fraction(y)) for x, y in a]
    for j in range(len(clip)):
        (x0, y0), (x1, y1) = clip[j], clip[(j + 1) % len(clip)]

        def dist(p):
            return (x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0)

        out = []
        for i in range(len(poly)):
            s, e = poly[i - 1], poly[i]
            ds, de = dist(s), dist(e)
            if (ds >= 0) != (de >= 0):
                f = ds / (ds - de)
                out.append((s[0] + f * (e[0] - s[0]), s[1] + f * (e[1] - s[1])))
            if de >= 0:
                out.append(e)
        poly = out
    twice = sx = sy = Fraction(0)
    for i in range(len(poly)):
        (px, py), (qx, qy) = poly[i - 1], poly[i]
        c = px * qy - qx * py
        twice, sx, sy = twice + c, sx + (px + qx) * c, sy + (py + qy) * c
    perimeter = sum(math.dist(poly[i - 1], poly[i]) for i in range(len(poly)))
    if twice == 0:
        return 0.0, 0.0, 0.0, perimeter
    return float(twice / 2), float(sx / (3 * twice)), float(sy / (3 * twice)), perimeter


@pytest.mark.parametrize("seed", range(4))
def test_tiny_penetrations_against_exact_arithmetic(seed):
    """Rotated 10 m slabs pressed together by 1e-9 … 1e-6 m, against the exact overlap of the
    same float polygons: the kernel's area error stays below ε·X·P (and so does shapely's),
    which is why the tolerances carry that term: 1e-9 relative is not reachable for a
    1e-9 m sliver at 100 m from the origin, by anybody, in double precision."""
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(25):
        angle = rng.uniform(0, 2 * math.pi)
        origin = rng.uniform(-100, 100, 2)
        delta = 10.0 ** rng.uniform(-9, -6)
        a = rotate(rectangle(0, 0, 10, 10), angle) + origin
        b = rotate(rectangle(10 - delta, rng.uniform(-5, 5), 10, 10), angle) + origin
        ok, r = check_frame(a, b, label="exact")
        area, cx, cy, _ = exact_overlap(a, b)
        big = max(np.abs(a).max(), np.abs(b).max())
        perimeter = shapely.intersection(shapely.Polygon(a), shapely.Polygon(b)).length
        worst = max(worst, abs(r[AREA] - area) / (EPS * big * perimeter))
        assert math.dist(r[CX:CY + 1], (cx, cy)) <= 1e-9 * 10 + 4 * EPS * big * perimeter * 10 / area
    assert worst < 1.0


# --- physics with exact answers -------------------------------------------------------------


@pytest.mark.parametrize("delta", [1e-9, 1e-6, 1e-3, 0.05, 1.0])
def test_squares_face_to_face(delta):
    """Two 8×8 squares, B pressed into A along x by δ: area 8δ, the strip's middle, n = (1, 0)
    from A (left) into B (right), P1P2 vertical across the middle, depth δ, length 8."""
    a = rectangle(0, 0, 8, 8)
    b = rectangle(8 - delta, 0, 8, 8)
    delta = 8 - b[0, 0]  # the penetration the floats represent (exact: Sterbenz)
    ok, r = check_frame(a, b)
    assert ok
    assert_allclose(r[AREA], 8 * delta, rtol=1e-12)
    assert_allclose(r[CX:CY + 1], [8 - delta / 2, 4.0], rtol=1e-15, atol=1e-15)
    assert tuple(r[NX:TY + 1]) == (1.0, 0.0, 0.0, 1.0)
    assert_allclose(r[P1X:P2Y + 1], [8 - delta / 2, 0.0, 8 - delta / 2, 8.0], rtol=1e-15)
    assert_allclose(r[DEPTH], delta, rtol=1e-12)
    assert r[LENGTH] == 8.0 and r[N_CROSSINGS] == 2
    # swapping the bodies turns the normal round: it still points from A (now right) into B
    ok, r2 = check_frame(b, a)
    assert tuple(r2[NX:NY + 1]) == (-1.0, 0.0) and r2[AREA] == r[AREA]


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_squares_face_to_face_shifted_sideways(sign):
    """The same with B shifted by ±ε along the face: the normal tilts by at most δ/8 (the
    paper's P1P2 joins opposite corners of the strip once the top and bottom edges are
    clearly apart) and tends to (1, 0) continuously as ε → 0 from either side."""
    delta = 1e-3
    tilts = []
    for eps in np.geomspace(1.0, 1e-14, 57):
        ok, r = check_frame(rectangle(0, 0, 8, 8), rectangle(8 - delta, sign * eps, 8, 8))
        assert ok and r[NX] > 0
        tilt = math.atan2(r[NY], r[NX])
        assert sign * tilt >= 0  # towards the side B moved to
        assert abs(tilt) <= math.atan2(delta, 8 - eps) * (1 + 1e-12)
        tilts.append(abs(tilt))
    assert tilts[0] == pytest.approx(math.atan2(delta, 7), rel=1e-9)  # ε = 1: corner to corner
    assert np.all(np.diff(tilts) <= 1e-15)  # monotone as ε decreases
    assert tilts[-1] <= 1e-12  # and → 0: no jump at ε = 0


@pytest.mark.parametrize("about", [(7.9995, 4.0), (7.999, 0.0), (12.0, 4.0)])
def test_squares_face_to_face_turned_slightly(about):
    """The equal-width strip with B turned by ±θ (about the strip's middle, its corner, or B's
    centre): the normal returns to (1, 0) continuously as θ → 0, so the top and bottom
    boundaries passing through collinearity cause no jump. Turning about a point at lever
    arm 4 m from the strip also slides B's top and bottom edges by ε = 4θ: the sideways case
    above, whose tilt ε/(8·NEAR_SLOPE) = 5θ adds to B's own θ, and never exceeds δ/8 + θ."""
    delta = 1e-3
    for sign in (1.0, -1.0):
        for theta in np.geomspace(1e-2, 1e-15, 27):
            b = rotate(rectangle(8 - delta, 0, 8, 8), sign * theta, about)
            ok, r = check_frame(rectangle(0, 0, 8, 8), b)
            bound = min(6 * theta, delta / 8 + theta) * (1 + 1e-6) + 1e-15
            assert ok and abs(math.atan2(r[NY], r[NX])) <= bound, theta


@pytest.mark.parametrize("delta", [1e-6, 1e-3, 0.1])
def test_rotated_corner_into_a_face(delta):
    """A square rotated 30° pushes one corner δ into A's right face: a triangle with angles
    60° and 30° at the face, area δ²(tan 30° + tan 60°)/2, n = the face normal (1, 0)."""
    a = rectangle(0, 0, 8, 8)
    b = rotate(rectangle(0, 0, 4, 4), math.radians(30))
    b = b - b[np.argmin(b[:, 0])] + (8 - delta, 4)  # the leftmost corner δ inside the face
    delta = 8 - b[:, 0].min()
    ok, r = check_frame(a, b)
    assert ok
    expected = delta**2 * (math.tan(math.radians(30)) + math.tan(math.radians(60))) / 2
    assert_allclose(r[AREA], expected, rtol=1e-9)
    assert angle_between(r[NX:NY + 1], (1.0, 0.0)) <= 1e-12
    assert_allclose(r[DEPTH], delta, rtol=1e-9)
    assert r[N_CROSSINGS] == 2
    assert_allclose([r[P1X], r[P2X]], [8.0, 8.0], atol=1e-12)


# --- continuity -------------------------------------------------------------------------------


def drive(angle_deg: float, steps: int = 2000):
    """A 6×6 square rotated by `angle` is driven into the right face of an 8×8 square A, then
    slid along it over A's top corner: triangle → quadrilateral → pentagon (A's corner inside B)
    → quadrilateral. Returns per-step (vertex count, crossings, normal, length, step length)."""
    phi = math.radians(angle_deg)
    a = rectangle(0, 0, 8, 8)
    square = rotate(rectangle(-3, -3, 6, 6), phi)
    depth = 6 * math.sin(phi) + 0.05  # both left corners end up inside A
    rise = 0.6
    top_left = square[3]
    y0 = 8 - top_left[1] - depth * math.tan(phi) - rise / 3  # reaches A's corner a third of the way up
    p0 = np.array([8 - top_left[0] + 0.01, y0])
    p1 = p0 + (-0.01 - depth, 0.0)
    p2 = p1 + (0.0, rise)
    path = np.vstack([np.linspace(p0, p1, steps // 2, endpoint=False), np.linspace(p1, p2, steps // 2 + 1)])
    bufs = Buffers(clip_rows(4, 4))
    rows = []
    for k, centre in enumerate(path):
        ok, r, poly, _ = frame(a, square + centre, (4.0, 4.0), centre, bufs)
        step = math.dist(path[k], path[k - 1]) if k else 0.0
        rows.append((len(poly), r[N_CROSSINGS], r[NX:NY + 1].copy(), r[LENGTH], step, ok))
    return rows


@pytest.mark.parametrize("angle_deg", [3.0, 8.0, 30.0])
def test_normal_is_continuous_while_the_overlap_changes_shape(angle_deg):
    """Paper 4.2: no jump of the normal as the overlap turns triangle → quadrilateral →
    pentagon and back, or as a crossing passes over A's corner onto its next edge.

    Bound. n ⟂ P1P2, so one step turns it by Δθ ≤ (|ΔP1| + |ΔP2|)/|P1P2|. A crossing is the
    intersection of an edge of A with an edge of B; translating B by Δs moves it by at most
    Δs/sin α along A's edge, α the angle between the two edges (here the squares' relative
    rotation φ or 90° − φ, so sin α ≥ sin φ). Hence Δθ ≤ 2Δs/(|P1P2|·sin φ) per step. At
    φ = 3° the pentagon's short piece of A's top edge runs within 6° of B's edge, so the
    nearly-shared rule moves P2 back along it by a fixed fraction of its length: that slows
    P2 rather than speeding it up, and the same bound holds (measured: 0.26 of it)."""
    rows = drive(angle_deg)
    shapes = [m for m, *_ in rows]
    sequence = [m for i, m in enumerate(shapes) if m and (i == 0 or m != shapes[i - 1])]
    assert sequence[:3] == [3, 4, 5], sequence
    phi = math.radians(angle_deg)
    worst = 0.0
    contact = [row for row in rows if row[5]]
    for (_, c0, n0, l0, _, _), (_, c1, n1, l1, step, _) in zip(contact, contact[1:]):
        assert c0 == c1 == 2
        assert n0 @ n1 > 0  # never flips
        turn = angle_between(n0, n1)
        bound = 2 * step / (min(l0, l1) * math.sin(phi))
        assert turn <= bound, (turn, bound)
        worst = max(worst, turn / bound)
    assert worst < 1.0


def test_normal_stays_continuous_through_four_crossings():
    """A 45° square whose side passes over A's bottom corner: the overlap has four crossings for
    a while. The least-squares line weights each crossing by its shorter adjacent chain, so the
    crossing pair born with a vanishing chain enters the fit without a jump (an unweighted fit
    jumps by 8.4e-3 rad there, ten times the bound below). The weights grow as the chains do, at up to 1/sin α per
    unit step like the crossings themselves, which adds to the turn: the bound here is four
    times the two-crossing one (1.7 times it was measured)."""
    rows = drive(45.0)
    contact = [row for row in rows if row[5]]
    assert any(c == 4 for _, c, *_ in contact)
    for (_, _, n0, l0, _, _), (_, _, n1, l1, step, _) in zip(contact, contact[1:]):
        assert n0 @ n1 > 0
        assert angle_between(n0, n1) <= 8 * step / (min(l0, l1) * math.sin(math.pi / 4))


# --- allocation, buffers, broad phase ---------------------------------------------------------


@njit  # not cached: a cached caller would keep linking a stale build of the kernel
def _repeat(a, b, ref_a, ref_b, out, out_label, tmp, tmp_label, result, times):
    hits = 0
    for _ in range(times):
        if overlap_frame(a, a.shape[0], b, b.shape[0], ref_a, ref_b, out, out_label, tmp, tmp_label, result):
            hits += 1
    return hits


def test_kernels_allocate_nothing():
    """All buffers come from the caller: repeating the kernel inside compiled code makes no
    numba (NRT) allocation, and repeating it from Python allocates no Python memory."""
    a = rectangle(0, 0, 8, 8)
    b = rotate(rectangle(7.9, 1, 8, 8), 0.1, (7.9, 1))
    bufs = Buffers(clip_rows(4, 4))
    args = (a, b, centroid(a), centroid(b), bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label, bufs.result)
    assert _repeat(*args, 1) == 1  # compiled
    was_enabled = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    try:
        before = rtsys.get_allocation_stats()
        _repeat(*args, 1)
        once = rtsys.get_allocation_stats()
        _repeat(*args, 10_000)
        many = rtsys.get_allocation_stats()
    finally:
        if not was_enabled:
            _nrt_python.memsys_disable_stats()
    # whatever a call from Python costs (wrapping the arrays), 10,000 kernel runs cost the same
    assert many.alloc - once.alloc == once.alloc - before.alloc
    assert many.mi_alloc - once.mi_alloc == once.mi_alloc - before.mi_alloc
    call = (a, 4, b, 4, args[2], args[3], bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label, bufs.result)
    for _ in range(100):
        overlap_frame(*call)
    tracemalloc.start()
    try:
        start, _ = tracemalloc.get_traced_memory()
        for _ in range(10_000):
            overlap_frame(*call)
        end, _ = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert end - start < 10_000  # bytes, for 10,000 calls: nothing per call


def test_small_buffers_and_bad_input_never_fail():
    """Buffers too small, degenerate or clockwise polygons, coincident points: no exception,
    no write outside the buffers, no NaN."""
    a = rectangle(0, 0, 8, 8)
    b = rotate(rectangle(6, 2, 8, 8), 0.3, (6, 2))
    for rows in range(0, 8):
        bufs = Buffers(rows)
        guard = np.full((rows + 4, 2), 7.0)
        bufs.out = guard[:rows]
        ok, r, _, _ = frame(a, b, bufs=bufs)
        assert np.all(guard[rows:] == 7.0) and np.all(np.isfinite(r))
    short = np.zeros(RESULT_SIZE - 1)
    bufs = Buffers()
    assert not contact_frame(a, bufs.out_label, 4, a, 4, b, 4, centroid(a), centroid(b), short)
    odd = [
        np.zeros((4, 2)),  # all points at one place
        np.array([(0, 0), (4, 0), (8, 0)], float),  # collinear
        a[::-1].copy(),  # clockwise
        np.array([(0, 0), (8, 0), (8, 0), (8, 8), (0, 8), (0, 8)], float),  # repeated vertices
    ]
    for p in odd:
        for x, y in ((p, b), (b, p), (p, p)):
            ok, r, _, _ = frame(x, y)
            assert np.all(np.isfinite(r))
    assert frame(odd[3], b)[1][AREA] == pytest.approx(shapely.Polygon(a).intersection(shapely.Polygon(b)).area)


def test_broad_phase_circles():
    assert circles_apart(np.array([0.0, 0.0]), 1.0, np.array([3.0, 0.0]), 1.5)
    assert not circles_apart(np.array([0.0, 0.0]), 1.0, np.array([2.5, 0.0]), 1.5)  # touching
    assert not circles_apart(np.array([0.0, 0.0]), 1.0, np.array([1.0, 1.0]), 1.0)
    slab = rotate(rectangle(2, 3, 16, 8), 0.4) + (100, -50)
    centre = np.zeros(2)
    radius = bounding_circle(slab, 4, centre)
    assert np.all(np.hypot(*(slab - centre).T) <= radius * (1 + 1e-15))
    assert radius == pytest.approx(math.hypot(8, 4))  # a rectangle's box centre is its centre


def test_timing_is_reported(capsys):
    """Not an assertion on speed: prints µs per call for the report (pytest -s to see it)."""
    a = rectangle(0, 0, 8, 8)
    b = rotate(rectangle(7.9, 1, 8, 8), 0.1, (7.9, 1))
    bufs = Buffers(clip_rows(4, 4))
    ra, rb = centroid(a), centroid(b)
    call = (a, 4, b, 4, ra, rb, bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label, bufs.result)
    far = rb + 100.0
    n = 20_000
    t_frame = min(timeit.repeat(lambda: overlap_frame(*call), number=n, repeat=3)) / n
    t_apart = min(timeit.repeat(lambda: circles_apart(ra, 6.0, far, 6.0), number=n, repeat=3)) / n
    args = (a, b, ra, rb, bufs.out, bufs.out_label, bufs.tmp, bufs.tmp_label, bufs.result)
    _repeat(*args, 1)
    t_loop = min(timeit.repeat(lambda: _repeat(*args, n), number=1, repeat=3)) / n
    with capsys.disabled():
        print(f"\noverlap_frame 4-gons in contact: {t_frame * 1e6:.2f} µs/call from Python, "
              f"{t_loop * 1e6:.3f} µs/call inside compiled code; circles_apart: {t_apart * 1e6:.2f} µs/call")


def _on_frame(local, angle, origin):
    """Points given as (depth z along n, abscissa y along t) placed on the frame n = (cos a,
    sin a), t = (−sin a, cos a) about origin; returns (global points, n, t)."""
    n = np.array([math.cos(angle), math.sin(angle)])
    t = np.array([-n[1], n[0]])
    pts = np.array([origin + z * n + y * t for z, y in local])
    return pts, n, t


def _profile_reference(local, r0, dr, whole):
    """The moments shallow_moments returns, by adaptive quadrature of the depth profile that
    shapely cuts from the polygon (in its own frame: z along n, y along t), split at the
    vertices and where the depth meets the rate r = r0 + dr·y."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    polygon = shapely.Polygon(local)
    ys = sorted({y for _, y in local})

    def chord(y):
        cut = polygon.intersection(shapely.LineString([(-1e3, y), (1e3, y)]))
        return cut.length

    def depth(y):
        e = chord(y)
        return min(e, (r0 + dr * y) * (1 - 1e-12)) if whole else e

    def h(y):
        e, r = depth(y), r0 + dr * y
        return (e - r / 2) ** 2 / (2 * r) if 0 < e <= r and r > 0 else 0.0

    grid = np.linspace(ys[0], ys[-1], 2001)
    g = np.array([depth(y) - (r0 + dr * y) for y in grid])
    cuts = [brentq(lambda y: depth(y) - (r0 + dr * y), grid[i], grid[i + 1], xtol=1e-15)
            for i in range(grid.size - 1) if g[i] * g[i + 1] < 0]  # fmt: skip
    points = sorted(set(ys + cuts))

    def integral(f):
        return sum(quad(f, a, b, epsabs=0, epsrel=1e-13, limit=200)[0] for a, b in zip(points[:-1], points[1:]))

    deep = lambda f: (lambda y: f(y) if depth(y) > r0 + dr * y else 0.0)  # noqa: E731
    rest = [integral(deep(f)) for f in (lambda y: 1.0, depth, lambda y: depth(y) ** 2, lambda y: y,
                                        lambda y: depth(y) * y, lambda y: depth(y) ** 2 * y)]  # fmt: skip
    return integral(h), integral(lambda y: h(y) * y), max(chord(y) for y in ys), rest


# overlaps in their own frame, (depth along n, abscissa along t): a face met parallel, a face
# turned (the depth tapering along the line), a corner (a tent), and a corner near a face's end
PROFILES = {
    "parallel": [(0.0, 0.0), (0.3, 0.0), (0.3, 4.0), (0.0, 4.0)],
    "taper": [(0.0, 0.0), (0.1, 0.0), (0.7, 4.0), (0.0, 4.0)],
    "tent": [(0.0, 0.0), (0.6, 1.5), (0.0, 4.0)],
    "pentagon": [(0.0, 0.0), (0.2, 0.0), (0.9, 1.0), (0.4, 3.5), (0.0, 3.9)],
}


@pytest.mark.parametrize("name", sorted(PROFILES))
@pytest.mark.parametrize("r0, dr, whole", [(0.5, 0.0, False), (0.25, 0.0, False), (0.5, 0.0, True),
                                           (0.5, 0.02, False)])  # fmt: skip
def test_shallow_moments_integrate_the_depth_profile(name, r0, dr, whole):
    """depth_profile and shallow_moments against adaptive quadrature of the depth profile
    shapely cuts from the overlap, with the frame turned and away from the origin: with a uniform rate r (no relative
    turning) Simpson's rule is exact on every piece (quadratic and cubic integrands), so they
    agree to 1e-10 of the moments' size (rounding in the frame's projections); with r varying
    along the line (dr·L/r = 0.16, the Kobe example's turning at its slowest impacts) the
    integrand is rational, and four Simpson panels are off by its fourth derivative: within
    1e-4 (a single panel was 1.2e-3 off on the taper's first moment)."""
    local = PROFILES[name]
    angle, origin = 0.7, np.array([12.0, -3.0])
    pts, n, t = _on_frame(local, angle, origin)
    # ox, oy: where y = 0; the moments are taken about it
    work = np.zeros((len(pts) + 2, 2))
    rest = np.zeros(6)
    count, deepest = depth_profile(pts, len(pts), n[0], n[1], t[0], t[1], origin[0], origin[1], work)
    i0, i1 = shallow_moments(work, count, r0, dr, whole, rest)
    ref0, ref1, ref_deepest, ref_rest = _profile_reference(local, r0, dr, whole)
    tol = 1e-10 if dr == 0 else 1e-4
    scale = r0 * 4.0
    assert abs(i0 - ref0) <= tol * scale
    assert abs(i1 - ref1) <= tol * scale * 4.0
    assert_allclose(deepest, ref_deepest, rtol=1e-12)
    assert_allclose(rest, ref_rest, rtol=0, atol=tol * 16.0)
    if whole:
        assert_allclose(rest, 0.0, atol=1e-12), "at an episode's first step every point is new"
