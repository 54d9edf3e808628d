"""Intensity measures against closed forms, and the response spectrum against closed forms and scipy."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import signal

from pounding_cli.records.metrics import G, arias_build_up, integrate, metrics
from pounding_cli.records.spectrum import oscillator_response, pseudo_acceleration

DT = 0.01


# --- integration and intensity measures ----------------------------------------------------------


def test_integration_of_a_ramp_is_exact():
    """a = c·t integrates to v = c t²/2, u = c t³/6: exact for piecewise-linear a, to the
    rounding of the running sums (1e-12 relative over 1000 steps)."""
    t = np.arange(1001) * DT
    v, u = integrate(3.0 * t, DT)
    np.testing.assert_allclose(v, 1.5 * t**2, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(u, 0.5 * t**3, rtol=1e-12, atol=1e-15)


def test_constant_acceleration_measures():
    """a = 2 m/s² for 10 s: PGV = 20 m/s, PGD = 100 m, I_A = π/(2g)·a²·T, D5-95 = 0.9 T."""
    a = np.full(1001, 2.0)
    m = metrics(a, DT)
    assert (m.points, m.dt) == (1001, DT) and m.duration == pytest.approx(10.0, rel=1e-15)
    assert m.pga == 2.0 and m.pga_g == 2.0 / 9.80665 and m.pga_time == 0.0
    assert m.pgv == pytest.approx(20.0, rel=1e-12) and m.pgv_time == pytest.approx(10.0)
    assert m.pgd == pytest.approx(100.0, rel=1e-12)
    assert m.arias_intensity == pytest.approx(math.pi / (2 * G) * 4.0 * 10.0, rel=1e-12)
    assert (m.t5, m.t95) == (pytest.approx(0.5, abs=1e-9), pytest.approx(9.5, abs=1e-9))
    assert m.significant_duration == pytest.approx(9.0, abs=1e-9)


def test_arias_of_a_linear_segment_is_exact():
    """One step from a0 to a1: ∫a² = Δt (a0² + a0 a1 + a1²)/3 (no trapezoidal error)."""
    build_up = arias_build_up(np.array([1.0, 3.0]), 0.5)
    assert build_up[-1] == pytest.approx(math.pi / (2 * G) * 0.5 * (1 + 3 + 9) / 3, rel=1e-15)


KOBE = Path(__file__).resolve().parents[3] / "shared" / "records" / "kobe1995_kjma"


@pytest.mark.skipif(not KOBE.is_dir(), reason=f"PEER Kobe records absent: {KOBE}")
@pytest.mark.parametrize("component, peer", [("000", 8.4), ("090", None)])
def test_trapezoid_arias_exceeds_the_exact_one_by_the_linear_term(component, peer):
    """PEER's I_A for RSN1106 (8.4 m/s) is the trapezoid rule on the samples of a²; pound's
    exact integral of linear a is lower by π/(2g)·Σ Δt·(a_{i+1} − a_i)²/6 (an identity:
    checked to 1e-9 relative of that 1.4 % difference, far above the rounding of 7500-term
    sums, ~1e-11 of it)."""
    from pounding_cli.records import read_accelerogram

    rec = read_accelerogram(KOBE / f"RSN1106_KOBE_KJM{component}.AT2")
    a, dt = rec.acceleration, rec.dt
    trapezoid = math.pi / (2 * G) * float(np.sum(dt * (a[:-1] ** 2 + a[1:] ** 2) / 2))
    term = math.pi / (2 * G) * float(np.sum(dt * np.diff(a) ** 2 / 6))
    exact = metrics(a, dt).arias_intensity
    assert trapezoid - exact == pytest.approx(term, rel=1e-9)
    assert 0.013 < term / exact < 0.015
    if peer is not None:
        assert round(trapezoid, 1) == peer != round(exact, 1)


def test_peak_times_and_sign():
    a = np.zeros(501)
    a[120] = -4.0
    m = metrics(a, DT)
    assert m.pga == 4.0 and m.pga_time == pytest.approx(1.2)
    # a triangle of area −4·Δt: the velocity ends at −0.04 m/s, the displacement keeps growing
    assert m.pgv == pytest.approx(0.04, rel=1e-12) and m.pgd_time == pytest.approx(5.0)


# --- the response spectrum -----------------------------------------------------------------------


def closed_form_step(t: np.ndarray, a0: float, period: float, zeta: float) -> np.ndarray:
    """u(t) of ü + 2ζωu̇ + ω²u = −a0 from rest (a constant ground acceleration a0 from t = 0)."""
    w = 2 * np.pi / period
    wd = w * np.sqrt(1 - zeta**2)
    return -a0 / w**2 * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta / np.sqrt(1 - zeta**2) * np.sin(wd * t)))


@pytest.mark.parametrize("period", [0.05, 0.3, 1.0, 4.0])
def test_oscillator_matches_the_closed_form_step_response(period):
    """Constant input is piecewise linear, so the recurrence is exact at the samples. Tolerance
    1e-9 relative: the rounding of 2000 recurrence steps and of the coefficients' cancellation
    at long periods (ωΔt small), far below the 1e-6 asked of the spectrum."""
    t = np.arange(2001) * DT
    u, _ = oscillator_response(np.full(t.size, 1.5), DT, np.array([period]), 0.05)
    exact = closed_form_step(t, 1.5, period, 0.05)
    np.testing.assert_allclose(u[:, 0], exact, rtol=0, atol=1e-9 * np.abs(exact).max())


@pytest.mark.parametrize("period", [0.05, 0.3, 1.0, 4.0])
def test_oscillator_matches_scipy_for_a_random_record(period):
    """scipy.signal.lsim with interp=True integrates the state-space SDOF exactly for input
    linear between samples (matrix exponential of the augmented system): a method independent
    of the Nigam-Jennings coefficients. Tolerance 1e-9 relative to the peak (as above)."""
    rng = np.random.default_rng(7)
    a = rng.standard_normal(3000)
    t = np.arange(a.size) * DT
    w, z = 2 * np.pi / period, 0.05
    system = signal.StateSpace([[0, 1], [-w * w, -2 * z * w]], [[0], [-1]], [[1, 0], [0, 1]], [[0], [0]])
    _, y, _ = signal.lsim(system, a, t, interp=True)
    u, v = oscillator_response(a, DT, np.array([period]), z)
    np.testing.assert_allclose(u[:, 0], y[:, 0], rtol=0, atol=1e-9 * np.abs(y[:, 0]).max())
    np.testing.assert_allclose(v[:, 0], y[:, 1], rtol=0, atol=1e-9 * np.abs(y[:, 1]).max())
    psa = pseudo_acceleration(a, DT, np.array([period]), z)
    assert psa[0] == pytest.approx(w * w * np.abs(y[:, 0]).max(), rel=1e-6)


def test_psa_limits():
    """A rigid oscillator (T → 0) follows the ground: PSA → PGA; a very flexible one (T ≫
    record) hardly moves under a zero-mean pulse: PSA → 0."""
    t = np.arange(1001) * DT
    a = 3.0 * np.sin(2 * np.pi * 1.0 * t) * (t < 2.0)
    psa = pseudo_acceleration(a, DT, np.array([0.001, 100.0]))
    assert psa[0] == pytest.approx(3.0, rel=1e-3)
    assert psa[1] < 1e-2 * 3.0
