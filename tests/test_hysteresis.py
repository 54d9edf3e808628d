"""The bilinear hysteretic law of yielding members (pounding_cli/solver/hysteresis.py) against
closed forms (issue 6, "Validation").

Closed forms used here (k initial stiffness, F_y yield force, δ_y = F_y/k, α post-yield ratio,
k_h = (1 − α)·k, f_h = (1 − α)·F_y):

* Monotonic loading from rest: f = k·δ for |δ| ≤ δ_y, f = ±F_y + α·k·(δ ∓ δ_y) beyond.
* Kinematic hardening: at any time the force lies in the band between the bounding lines
  α·k·δ ± f_h; an increment moves it with slope k until it meets a bounding line, then along it
  (slope α·k). This "bounding-line" form is an independent statement of the same law (the code
  uses the split into a linear spring α·k and an elastic–perfectly-plastic spring k_h, f_h).
* A stabilised loop between δ_min and δ_max (range Δ = δ_max − δ_min > 2·δ_y) is a
  parallelogram: unloading sides of slope k and length 2·δ_y in deflection, yielding sides of
  slope α·k. Its area, the energy dissipated per cycle, is the cross product of two sides:
  a = (2·δ_y, 2·F_y), b = (Δ − 2·δ_y, α·k·(Δ − 2·δ_y)):
  |a × b| = 2·(Δ − 2·δ_y)·|2·δ_y·α·k − 2·F_y| = 2·F_y·(1 − α)·(Δ − 2·δ_y), which for a
  symmetric cycle ±δ_max (Δ = 2·δ_max) is 4·F_y·(1 − α)·(δ_max − δ_y). Equivalently: the
  linear spring stores and returns, the EPP spring slides by Δ − 2·δ_y twice per cycle at the
  force f_h. A cycle with Δ ≤ 2·δ_y is elastic and dissipates nothing.
* Dissipated energy along any path = work ∫f·dδ − recoverable energy
  ½·α·k·δ² + (f − α·k·δ)²/(2·k_h) (computed below exactly, segment by segment).

Tolerance 1e-9 relative: for an imposed deflection the return mapping is exact, not an
approximation — a rate-independent 1D bilinear law's state after a monotonic increment
depends only on the end points, and backward Euler with a closest-point (here: clamp) return
gives exactly that state whatever the increment's size. So only rounding remains (measured:
2.6e-15 of F_y on forces, 8e-16 relative on loop areas); the tests also check that coarse
and fine sampling of the same path agree.

Biaxial: "elliptical" follows the flow on the yield ellipse along the straight path between
two deflections (exactly: closed form for a circle, RK4 in short pieces otherwise);
"independent" clamps each axis. A member driven along a circle of radius R > δ_y (isotropic)
ends up in a steady state where the EPP spring's elastic deflection e (|e| = δ_y) is
perpendicular to the plastic deflection p (ṗ ∥ e and p moves on a circle), so
|p| = √(R² − δ_y²), the force lags the deflection by arccos(δ_y/R) and a revolution dissipates
2π·f_h·√(R² − δ_y²). The path map converges to this at second order in the angular step (the
chords are all it assumes; measured, energy per revolution: 2.9e-7 relative at 3600 steps per
revolution and 2.9e-5 at 360 for R = 3·δ_y; 2.3e-6 at 3600 for R = 1.2·δ_y). The flow itself
is checked against scipy's integration of the flow rule in force space, for a circle and a
100 × 30 cm-like column.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pounding_cli.solver.hysteresis import bilinear_response, return_map, update_members

K = 2.0e7  # N/m
FY = 1.0e5  # N
DY = FY / K  # 5 mm
RTOL = 1e-9


# --- an independent 1D reference: the bounding-line form, with the dissipated energy from work


def bounding_line_reference(delta: np.ndarray, k: float, fy: float, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Force and cumulative dissipated energy of the 1D bilinear law (kinematic hardening) along
    a piecewise-linear deflection path through the given samples, by the bounding-line form; the
    energy is the exact work along each segment (split where the force meets a bounding line)
    minus the recoverable energy."""
    fh = (1 - alpha) * fy
    kh = (1 - alpha) * k
    f = 0.0
    d0 = 0.0
    work = 0.0
    forces = np.empty(delta.size)
    energy = np.empty(delta.size)
    for i, d1 in enumerate(np.asarray(delta, dtype=float)):
        step = d1 - d0
        if step != 0.0:
            s = 1.0 if step > 0 else -1.0
            # elastic (slope k) until f = α·k·δ + s·f_h, i.e. at δ* = (s·f_h − f + k·d0)/(k − α·k)
            d_star = (s * fh - f + k * d0) / (k - alpha * k)
            if (d_star - d0) * s >= (d1 - d0) * s:  # stays inside the band
                f1 = f + k * step
                work += 0.5 * (f + f1) * step
            else:
                f_star = f + k * (d_star - d0)
                f1 = alpha * k * d1 + s * fh
                work += 0.5 * (f + f_star) * (d_star - d0) + 0.5 * (f_star + f1) * (d1 - d_star)
            f = f1
        recoverable = 0.5 * alpha * k * d1**2 + (f - alpha * k * d1) ** 2 / (2 * kh)
        forces[i] = f
        energy[i] = work - recoverable
        d0 = d1
    return forces, energy


def refine(turning_points: list[float], per_segment: int) -> np.ndarray:
    """The piecewise-linear path through the turning points (starting from 0), sampled
    `per_segment` times per segment, turning points included."""
    pts = [0.0, *turning_points]
    out = [np.linspace(a, b, per_segment + 1)[1:] for a, b in zip(pts[:-1], pts[1:])]
    return np.concatenate(out)


def response_1d(delta: np.ndarray, alpha: float, k: float = K, fy: float = FY) -> tuple[np.ndarray, np.ndarray]:
    path = np.column_stack([delta, np.zeros_like(delta)])
    f, e = bilinear_response(path, (k, k), (fy, fy), (alpha, alpha), False)
    assert np.all(f[:, 1] == 0.0)
    return f[:, 0], e


def loop_area(d: np.ndarray, f: np.ndarray) -> float:
    """Shoelace area of a closed (δ, f) polygon."""
    return 0.5 * abs(np.dot(d, np.roll(f, -1)) - np.dot(f, np.roll(d, -1)))


# --- (a) one member, imposed cyclic deflection


@pytest.mark.parametrize("alpha", [0.0, 0.05, 0.3])
def test_monotonic_loading_yield_point_and_post_yield_slope(alpha):
    d = np.linspace(0.0, 6 * DY, 601)  # δ_y is sample 100
    f, e = response_1d(d, alpha)
    closed = np.where(d <= DY, K * d, FY + alpha * K * (d - DY))
    np.testing.assert_allclose(f, closed, rtol=0, atol=RTOL * FY)
    assert f[100] == pytest.approx(FY, rel=RTOL)  # yields at +F_y, δ_y
    assert np.all(e[:101] == 0.0)  # nothing dissipated up to the yield point
    # dissipated: the EPP spring slid δ − δ_y at f_h
    np.testing.assert_allclose(e, np.maximum(d - DY, 0) * (1 - alpha) * FY, rtol=0, atol=RTOL * FY * DY)
    slopes = np.diff(f) / np.diff(d)
    np.testing.assert_allclose(slopes[:100], K, rtol=RTOL)
    np.testing.assert_allclose(slopes[100:], alpha * K, rtol=0, atol=RTOL * K)
    # the same in the negative direction
    fn, _ = response_1d(-d, alpha)
    np.testing.assert_allclose(fn, -closed, rtol=0, atol=RTOL * FY)


@pytest.mark.parametrize("alpha", [0.0, 0.05, 0.3])
@pytest.mark.parametrize("ductility", [1.5, 3.0, 10.0])
def test_symmetric_cycles_reproduce_the_parallelogram(alpha, ductility):
    """Cycles 0 → +δ_m → −δ_m → +δ_m → −δ_m → +δ_m, with the closed-form corners of the loop as
    samples: every corner's force, both slopes and the area per cycle (= dissipated energy)."""
    dm = ductility * DY
    fm = FY + alpha * K * (dm - DY)  # force at the turning points
    # corners: turning point, end of elastic unloading (δ_m − 2δ_y, f_m − 2F_y), other turning point, ...
    corners = [dm, dm - 2 * DY, -dm, -dm + 2 * DY] * 2 + [dm]
    path = refine(corners, 40)
    f, e = response_1d(path, alpha)
    idx = 40 * np.arange(1, len(corners) + 1) - 1  # the samples at the corners
    fc = f[idx]
    expected = np.array([fm, fm - 2 * FY, -fm, -fm + 2 * FY] * 2 + [fm])
    np.testing.assert_allclose(fc, expected, rtol=0, atol=RTOL * FY)
    # slopes: elastic unloading k over 2δ_y, then α·k
    seg_slopes = np.diff(f) / np.diff(path)
    for j in range(1, len(corners)):
        s = seg_slopes[40 * j : 40 * (j + 1) - 1]
        np.testing.assert_allclose(s, K if j % 2 == 1 else alpha * K, rtol=0, atol=RTOL * K)
    # energy per full cycle: from a turning point back to it, the closed form and the loop area
    closed = 4 * FY * (1 - alpha) * (dm - DY)
    e_turn = e[idx]
    assert e_turn[4] - e_turn[0] == pytest.approx(closed, rel=RTOL)
    assert e_turn[8] - e_turn[4] == pytest.approx(closed, rel=RTOL)
    assert loop_area(path[idx[4:8]], f[idx[4:8]]) == pytest.approx(closed, rel=RTOL)
    # the first loading dissipates the slide from δ_y to δ_m
    assert e_turn[0] == pytest.approx(FY * (1 - alpha) * (dm - DY), rel=RTOL)
    # and the bounding-line reference agrees at every sample
    fr, er = bounding_line_reference(path, K, FY, alpha)
    np.testing.assert_allclose(f, fr, rtol=0, atol=RTOL * FY)
    np.testing.assert_allclose(e, er, rtol=0, atol=RTOL * FY * DY * ductility)


@pytest.mark.parametrize("alpha", [0.0, 0.1])
def test_partial_cycles_unloading_and_reloading(alpha):
    """Growing and shrinking amplitudes, partial unloading inside the elastic band, reloading,
    asymmetric cycles: force and dissipated energy at every sample as the reference gives them,
    whether the path is sampled only at its turning points or finely."""
    turning = [3 * DY, 1.5 * DY, 4 * DY, -2 * DY, -0.5 * DY, -1.2 * DY, 2.5 * DY, 0.8 * DY,
               7 * DY, -7 * DY, 0.0, 3 * DY, 2 * DY, 3.5 * DY, -DY, 0.3 * DY]  # fmt: skip
    fine = refine(turning, 50)
    f, e = response_1d(fine, alpha)
    fr, er = bounding_line_reference(fine, K, FY, alpha)
    np.testing.assert_allclose(f, fr, rtol=0, atol=RTOL * FY)
    np.testing.assert_allclose(e, er, rtol=0, atol=RTOL * FY * DY * 10)
    # only the turning points: the same states (the return map is exact for any increment)
    coarse = np.array(turning)
    fc, ec = response_1d(coarse, alpha)
    ends = np.arange(1, len(turning) + 1) * 50 - 1
    np.testing.assert_allclose(fc, f[ends], rtol=0, atol=1e-12 * FY)
    np.testing.assert_allclose(ec, e[ends], rtol=0, atol=1e-12 * FY * DY * 10)
    # every force stays within the bounding lines
    band = (1 - alpha) * FY * (1 + 1e-12)
    assert np.all(np.abs(f - alpha * K * fine) <= band)
    # a small cycle inside the band (range < 2δ_y) dissipates nothing, a stabilised
    # asymmetric cycle of range Δ dissipates 2·F_y·(1 − α)·(Δ − 2δ_y)
    small = [5 * DY, 3.5 * DY, 5 * DY]
    _, es = response_1d(refine(small, 20), alpha)
    assert es[-1] - es[19] == pytest.approx(0.0, abs=RTOL * FY * DY)
    lo, hi = -1.0 * DY, 4.0 * DY
    asym = [hi, lo, hi, lo, hi]
    _, ea = response_1d(refine(asym, 20), alpha)
    per_cycle = 2 * FY * (1 - alpha) * ((hi - lo) - 2 * DY)
    assert ea[20 * 5 - 1] - ea[20 * 3 - 1] == pytest.approx(per_cycle, rel=RTOL)


def test_time_loop_kernel_matches_bilinear_response():
    """update_members (what cdm.py and hybrid.py call after each step) applied to a single
    member between a floor and the ground gives the same forces, energy and plastic
    correction g as bilinear_response, for a rotated member off the mass centre."""
    rng = np.random.default_rng(6)
    angle = math.radians(30.0)
    kx, ky, fx, fy, ax_, ay_ = 2.0e7, 1.2e7, 1.0e5, 0.8e5, 0.05, 0.2
    members = (
        np.array([1]), np.array([0]),  # bottom: the ground (the extra floor after floor 0); top: floor 0
        np.zeros((1, 2)), np.array([[1.5, -2.0]]),  # arms from the mass centres, m
        np.array([[math.cos(angle), math.sin(angle)]]),
        np.array([[kx, ky]]), np.array([[(1 - ax_) * kx, (1 - ay_) * ky]]),
        np.array([[(1 - ax_) * fx, (1 - ay_) * fy]]), np.array([1]),
    )  # fmt: skip
    plastic = np.zeros((1, 4))  # p; the deflection at the last call
    g = np.zeros(6)
    u = np.zeros(6)
    local = np.cumsum(rng.normal(scale=0.004, size=(400, 2)), axis=0)
    total = 0.0
    forces = []
    q = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])  # local → global
    arm = members[3][0]
    for i, (lx, ly) in enumerate(local):
        theta = 1e-3 * math.sin(0.1 * i)
        dxy = q @ (lx, ly)  # global deflection of the member's top = u + θ·ẑ×r
        u[:3] = dxy[0] + theta * arm[1], dxy[1] - theta * arm[0], theta
        total += update_members(u, members, plastic, g)[0]
        forces.append(members[5][0] * (lx, ly) - members[6][0] * plastic[0, :2])
    f_ref, e_ref = bilinear_response(local, (kx, ky), (fx, fy), (ax_, ay_), True)
    np.testing.assert_allclose(np.array(forces), f_ref, rtol=0, atol=1e-9 * fx)
    assert total == pytest.approx(e_ref[-1], rel=1e-9)
    # g = Bᵀ·Q·(k_h ⊙ p): the floor force and moment of the plastic-spring offset
    gl = q @ (members[6][0] * plastic[0, :2])
    np.testing.assert_allclose(g[:3], [gl[0], gl[1], arm[0] * gl[1] - arm[1] * gl[0]], rtol=1e-9, atol=1e-9 * fx)
    np.testing.assert_allclose(g[3:], [-gl[0], -gl[1], 0.0], rtol=1e-9, atol=1e-9 * fx)


# --- (b) interaction: a square column bent diagonally


@pytest.mark.parametrize("alpha", [0.0, 0.05])
def test_diagonal_independent_yields_at_root2_elliptical_at_f(alpha):
    s = np.linspace(0.0, 5 * DY, 1001)  # distance along the diagonal
    path = np.column_stack([s, s]) / math.sqrt(2)
    fi, _ = bilinear_response(path, (K, K), (FY, FY), (alpha, alpha), False)
    fe, _ = bilinear_response(path, (K, K), (FY, FY), (alpha, alpha), True)
    along_i = fi.sum(axis=1) / math.sqrt(2)  # force component along the diagonal
    along_e = fe.sum(axis=1) / math.sqrt(2)
    np.testing.assert_allclose(fi[:, 0], fi[:, 1], rtol=1e-14)  # stays on the diagonal
    np.testing.assert_allclose(fe[:, 0], fe[:, 1], rtol=1e-14)
    # independent: each axis yields when k·s/√2 = F_y: at s = √2·δ_y, force √2·F_y
    closed_i = np.where(s <= math.sqrt(2) * DY, K * s, math.sqrt(2) * FY + alpha * K * (s - math.sqrt(2) * DY))
    # elliptical (a circle here): yields at s = δ_y, force F_y
    closed_e = np.where(s <= DY, K * s, FY + alpha * K * (s - DY))
    np.testing.assert_allclose(along_i, closed_i, rtol=0, atol=RTOL * FY)
    np.testing.assert_allclose(along_e, closed_e, rtol=0, atol=RTOL * FY)
    if alpha == 0.0:
        assert along_i[-1] == pytest.approx(math.sqrt(2) * FY, rel=RTOL)
        assert along_e[-1] == pytest.approx(FY, rel=RTOL)
    # along an axis both laws are the same uniaxial law
    ax = np.column_stack([s, 0 * s])
    f1, e1 = bilinear_response(ax, (K, K), (FY, FY), (alpha, alpha), False)
    f2, e2 = bilinear_response(ax, (K, K), (FY, FY), (alpha, alpha), True)
    np.testing.assert_allclose(f1, f2, rtol=0, atol=RTOL * FY)
    np.testing.assert_allclose(e1, e2, rtol=0, atol=RTOL * FY * DY)


@pytest.mark.parametrize("phi_deg", [0.0, 20.0, 45.0, 70.0, 90.0, 135.0, 250.0])
def test_radial_paths_yield_on_the_ellipse(phi_deg):
    """An anisotropic elliptical member (k_x ≠ k_y, F_x ≠ F_y) loaded radially at angle φ stays
    elastic up to the radius where (k_x·r·cos φ/F_x)² + (k_y·r·sin φ/F_y)² = 1, and its first
    yielded force lies on the ellipse (f_x/F_x)² + (f_y/F_y)² = 1 (α = 0)."""
    kx, ky, fx, fy = 2.0e7, 6.0e6, 1.5e5, 4.0e4
    phi = math.radians(phi_deg)
    c, s = math.cos(phi), math.sin(phi)
    r_yield = 1.0 / math.hypot(kx * c / fx, ky * s / fy)
    r = np.concatenate([np.linspace(0, r_yield, 201), np.linspace(r_yield, 4 * r_yield, 301)[1:]])
    f, _ = bilinear_response(np.column_stack([r * c, r * s]), (kx, ky), (fx, fy), (0.0, 0.0), True)
    elastic = r <= r_yield
    np.testing.assert_allclose(f[elastic], np.column_stack([kx * r * c, ky * r * s])[elastic], rtol=0, atol=RTOL * fx)
    surface = np.hypot(f[:, 0] / fx, f[:, 1] / fy)
    assert surface[200] == pytest.approx(1.0, rel=RTOL)  # at r_yield exactly on the surface
    np.testing.assert_allclose(surface[~elastic], 1.0, rtol=RTOL)  # and stays there (radial, α = 0)
    assert np.all(surface[elastic][:-1] < 1.0)


# --- (c) biaxial: driven along a circle


def circle_path(radius: float, per_rev: int, revs: int, radial: int = 100) -> np.ndarray:
    """Radially out along +x to the radius (δ_y at sample radial/… if it lies there), then
    counter-clockwise around the circle."""
    rad = np.linspace(0.0, radius, radial + 1)
    th = np.linspace(0.0, 2 * np.pi * revs, per_rev * revs + 1)[1:]
    return np.vstack([np.column_stack([rad, 0 * rad]), np.column_stack([radius * np.cos(th), radius * np.sin(th)])])


@pytest.mark.parametrize("ratio", [1.2, 3.0])
def test_circle_alpha0_force_on_yield_circle(ratio):
    R = ratio * DY
    path = circle_path(R, 3600, 4, radial=round(100 * ratio))  # δ_y is sample 100
    f, e = bilinear_response(path, (K, K), (FY, FY), (0.0, 0.0), True)
    mag = np.hypot(f[:, 0], f[:, 1])
    r = np.hypot(path[:, 0], path[:, 1])
    # first yield at radius δ_y: elastic (f = k·δ) up to it, on the yield circle beyond
    np.testing.assert_allclose(f[:101], K * path[:101], rtol=0, atol=RTOL * FY)
    assert mag[100] == pytest.approx(FY, rel=RTOL) and r[100] == pytest.approx(DY, rel=1e-14)
    assert np.all(e[:101] == 0.0) and e[101] > 0.0
    np.testing.assert_allclose(mag[101:], FY, rtol=RTOL)  # |f| = F_y once yielded, all around
    # energy increments are ∫f·dp ≥ 0
    assert np.all(np.diff(e) >= 0)
    p = path - f / K  # α = 0
    # steady state: |p| → √(R² − δ_y²), force lags the deflection by arccos(δ_y/R), one
    # revolution dissipates 2π·F_y·√(R² − δ_y²) — second order in the angular step (the
    # chord between samples is all the path map assumes). Measured at 3600 steps per
    # revolution: energy 2.3e-6 (R = 1.2·δ_y, still settling after 4 revolutions) and 2.9e-7
    # (3·δ_y); the closest-point return this replaced gave 1.3e-3 and 3.1e-4.
    tol = 1e-5
    rho = math.sqrt(R**2 - DY**2)
    per_rev = e[-1] - e[-1 - 3600]
    assert per_rev == pytest.approx(2 * math.pi * FY * rho, rel=tol)
    assert np.hypot(*p[-1]) == pytest.approx(rho, rel=tol)
    lag = math.acos(np.dot(path[-1], f[-1]) / (R * mag[-1]))
    assert lag == pytest.approx(math.acos(DY / R), rel=3 * tol)


def test_circle_energy_converges_at_second_order():
    """Ten times finer, a hundred times smaller (measured 2.9e-5 → 2.9e-7 for R = 3·δ_y)."""
    R = 3 * DY
    exact = 2 * math.pi * FY * math.sqrt(R**2 - DY**2)
    errors = []
    for n in (360, 3600):
        _, e = bilinear_response(circle_path(R, n, 4, 300), (K, K), (FY, FY), (0.0, 0.0), True)
        errors.append(abs((e[-1] - e[-1 - n]) / exact - 1))
    assert errors[1] < 1e-6
    assert 80 < errors[0] / errors[1] < 120


@pytest.mark.parametrize("alpha", [0.05, 0.3])
def test_circle_with_hardening_epp_part_on_its_circle(alpha):
    """With α > 0 the total force is α·k·δ plus the EPP spring's, which stays on the circle of
    radius f_h = (1 − α)·F_y once yielded (so |f| is not constant, but |f − α·k·δ| is)."""
    R = 2.5 * DY
    path = circle_path(R, 720, 2, radial=250)
    f, e = bilinear_response(path, (K, K), (FY, FY), (alpha, alpha), True)
    epp = f - alpha * K * path
    mag = np.hypot(epp[:, 0], epp[:, 1])
    np.testing.assert_allclose(mag[:101], (1 - alpha) * K * np.hypot(*path[:101].T), rtol=0, atol=RTOL * FY)
    np.testing.assert_allclose(mag[101:], (1 - alpha) * FY, rtol=RTOL)
    # radially out: the uniaxial bilinear law
    r = path[:251, 0]
    np.testing.assert_allclose(f[:251, 0], np.where(r <= DY, K * r, FY + alpha * K * (r - DY)), rtol=0, atol=RTOL * FY)
    assert np.all(np.diff(e) >= 0)


def _flow_reference(f0, p0, step, kh, fh):
    """The elastic–perfectly-plastic spring driven along the straight deflection increment
    `step` from force f0 on its yield ellipse (f_x/f_h,x)² + (f_y/f_h,y)² = 1, loading:
    f' = K_h·(δ' − p'), p' = μ·n with n = ∇φ/2 = (f_x/f_h,x², f_y/f_h,y²) and μ from
    n·f' = 0; integrated by scipy's solve_ivp in force space (written here from the flow
    rule, independently of the kernel's normalised form). Returns f, p, ∫f·dp."""
    from scipy.integrate import solve_ivp

    kh = np.asarray(kh, float)
    fh = np.asarray(fh, float)
    d = np.asarray(step, float)

    def rate(_, y):
        f = y[:2]
        n = f / fh**2
        mu = max(0.0, (n @ (kh * d)) / (n @ (kh * n)))
        dp = mu * n
        return np.concatenate([kh * (d - dp), dp, [f @ dp]])

    y = solve_ivp(rate, (0.0, 1.0), np.concatenate([f0, p0, [0.0]]), method="DOP853", rtol=1e-12, atol=1e-14 * fh.max()).y[:, -1]
    return y[:2], y[2:4], y[4]


@pytest.mark.parametrize("axes", [(1.0, 1.0), (4.0, 0.3)], ids=["circle", "ellipse"])
@pytest.mark.parametrize("turn", [0.0, 40.0, 85.0])
def test_path_return_follows_the_flow_rule(axes, turn):
    """From a point on the yield surface, a straight increment turned `turn`° from the force
    in the normalised space (loading), 3 yield deflections long: the kernel's force, plastic deflection and
    dissipation against solve_ivp of the flow rule in force space (tolerance 1e-8 of F_y and
    δ_y: the RK4 pieces of 0.05 and the closed form for the circle are both far inside it).
    The column is 100 × 30 cm-like for the ellipse (k_h,x/f_h,x² ≠ k_h,y/f_h,y²)."""
    kx, ky = K * axes[0], K * axes[1] ** 3
    fx, fy = FY * axes[0], FY * axes[1] ** 2
    phi = math.radians(35.0)
    f0 = np.array([fx * math.cos(phi), fy * math.sin(phi)])
    p0 = np.array([0.002, -0.001])
    d0 = p0 + f0 / (kx, ky)
    # the increment: 3 yield deflections' worth, its force-space rate K_h·δ' turned `turn`°
    # from the normalised force q0 = f0 ⊘ f_h (loading: q0·(K_h·δ' ⊘ f_h) > 0)
    direction = phi + math.radians(turn)
    step = 3 * np.array([math.cos(direction) * fx / kx, math.sin(direction) * fy / ky])
    fxr, fyr, px, py, work, yielded = return_map(d0[0], d0[1], *(d0 + step), *p0, kx, ky, fx, fy, True)
    f_ref, p_ref, w_ref = _flow_reference(f0, p0, step, (kx, ky), (fx, fy))
    assert yielded
    np.testing.assert_allclose((fxr, fyr), f_ref, rtol=0, atol=1e-8 * FY)
    np.testing.assert_allclose((px, py), p_ref, rtol=0, atol=1e-8 * DY)
    assert work == pytest.approx(w_ref, rel=1e-8)
    assert math.hypot(fxr / fx, fyr / fy) == pytest.approx(1.0, rel=1e-14)


@pytest.mark.parametrize("axes", [(1.0, 1.0), (4.0, 0.3)], ids=["circle", "ellipse"])
@pytest.mark.parametrize("start", [(0.0, 0.0), (-0.6, 0.5), (0.9, 0.0)])
def test_path_return_is_exact_whatever_the_increments(axes, start):
    """The map is exact along a straight path, so one increment and the same path cut into
    1000 give the same state (an elastic start inside the surface, then yield on the way; a
    closest-point return fails this by the increment squared). Tolerance 1e-8 of F_y, δ_y
    and the dissipation: rounding, and the RK4 pieces for the ellipse."""
    kx, ky = K * axes[0], K * axes[1] ** 3
    fx, fy = FY * axes[0], FY * axes[1] ** 2
    d0 = np.array(start) * (fx / kx, fy / ky)
    d1 = d0 + np.array([2.5 * DY, 1.5 * DY])
    whole = return_map(*d0, *d1, 0.0, 0.0, kx, ky, fx, fy, True)
    p = np.zeros(2)
    last = d0
    total = 0.0
    for point in np.linspace(d0, d1, 1001)[1:]:
        fxr, fyr, px, py, work, _ = return_map(*last, *point, *p, kx, ky, fx, fy, True)
        p[:] = px, py
        total += work
        last = point
    np.testing.assert_allclose(whole[:2], (fxr, fyr), rtol=0, atol=1e-8 * FY)
    np.testing.assert_allclose(whole[2:4], p, rtol=0, atol=1e-8 * DY)
    assert whole[4] == pytest.approx(total, rel=1e-8)


# --- (d) energy along random paths


def check_energy_path(path: np.ndarray, k, fy, alpha, coupled: bool) -> None:
    f, e = bilinear_response(path, k, fy, alpha, coupled)
    scale = max(fy) * float(np.abs(path).max() + 1e-30)
    assert np.all(e >= 0.0)
    assert np.all(np.diff(e) >= -1e-12 * scale)
    # the EPP part of the force stays inside its yield surface
    a = np.asarray(alpha)
    epp = (f - a * np.asarray(k) * path) / ((1 - a) * np.asarray(fy))
    if coupled:
        assert np.all(np.hypot(epp[:, 0], epp[:, 1]) <= 1 + 1e-12)
    else:
        assert np.all(np.abs(epp) <= 1 + 1e-12)


@pytest.mark.parametrize("coupled", [False, True])
def test_energy_non_negative_non_decreasing_random_walks(coupled):
    rng = np.random.default_rng(2024)
    for _ in range(5):
        k = tuple(rng.uniform(1e6, 5e7, 2))
        fy = tuple(rng.uniform(1e4, 5e5, 2))
        alpha = tuple(rng.uniform(0, 0.5, 2))
        scale = max(f / kk for f, kk in zip(fy, k))
        path = np.cumsum(rng.normal(scale=0.7 * scale, size=(600, 2)), axis=0)
        check_energy_path(path, k, fy, alpha, coupled)


def test_random_1d_paths_match_reference_exactly():
    rng = np.random.default_rng(7)
    for alpha in (0.0, 0.02, 0.5):
        path = np.cumsum(rng.normal(scale=1.3 * DY, size=2000))
        f, e = response_1d(path, alpha)
        fr, er = bounding_line_reference(path, K, FY, alpha)
        np.testing.assert_allclose(f, fr, rtol=0, atol=RTOL * FY)
        np.testing.assert_allclose(e, er, rtol=0, atol=RTOL * FY * float(np.abs(path).max()) * 10)


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4)), min_size=1, max_size=60),
    alpha=st.floats(0.0, 0.9),
    aniso=st.floats(0.3, 3.0),
    coupled=st.booleans(),
)
def test_energy_hypothesis(steps, alpha, aniso, coupled):
    path = np.cumsum(np.array(steps) * DY, axis=0)
    check_energy_path(path, (K, K * aniso), (FY, FY / aniso), (alpha, alpha), coupled)
    if not coupled:  # per axis the uniaxial law: the exact reference
        f, e = bilinear_response(path, (K, K), (FY, FY), (alpha, alpha), False)
        fr0, er0 = bounding_line_reference(path[:, 0], K, FY, alpha)
        fr1, er1 = bounding_line_reference(path[:, 1], K, FY, alpha)
        np.testing.assert_allclose(f[:, 0], fr0, rtol=0, atol=RTOL * FY)
        np.testing.assert_allclose(f[:, 1], fr1, rtol=0, atol=RTOL * FY)
        np.testing.assert_allclose(e, er0 + er1, rtol=0, atol=RTOL * FY * DY * 200)
