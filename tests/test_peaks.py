"""Peaks between exact states: the cubic Hermite interpolant's maximum (solver/peaks.py)
against closed forms, and the hybrid's peaks against the exact solution sampled finely."""

from __future__ import annotations

import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli.assembly import assemble, ground_motion
from pounding_cli.solver.peaks import hermite_peak

from test_time_history import _eccentric_case, _exact_peaks


@pytest.mark.parametrize("omega_h", [0.05, 0.2, 0.4])
def test_crest_of_a_sine_within_the_hermite_bound(omega_h):
    """q = A·cos(ω(τ − τ_c)) with its crest at τ_c inside the step: the interpolant's maximum
    is within h⁴·max|q''''|/384 = (ω·h)⁴/384·A of A (the cubic Hermite error bound), whereas
    the larger end value misses by up to 1 − cos(ω·h/2) ≈ (ω·h)²/8."""
    amplitude, omega = 0.03, 20.0
    h = omega_h / omega
    worst_end = 0.0
    for fraction in np.linspace(0.02, 0.98, 49):
        crest = fraction * h
        q0, q1 = amplitude * np.cos(omega * (0.0 - crest)), amplitude * np.cos(omega * (h - crest))
        m0, m1 = -amplitude * omega * np.sin(omega * (0.0 - crest)), -amplitude * omega * np.sin(omega * (h - crest))
        peak = hermite_peak(q0, m0, q1, m1, h, 0.0)
        assert abs(peak - amplitude) <= omega_h**4 / 384 * amplitude * (1 + 1e-9), fraction
        worst_end = max(worst_end, amplitude - max(abs(q0), abs(q1)))
    assert worst_end > 0.9 * (1 - np.cos(omega_h / 2)) * amplitude  # what sampling the ends alone would miss


def test_cubic_interpolated_exactly():
    """A cubic is its own Hermite interpolant: its interior extrema, found by numpy's roots of
    q', are returned to rounding (q = s³ − 1.35s² + 0.42s − 0.05 on s = τ/h ∈ [0, 1], h = 0.5 s:
    stationary at s = 0.2 and 0.7, the largest |q| = 0.0745 inside, above both ends)."""
    h = 0.5
    coefficients = np.array([1.0, -1.35, 0.42, -0.05])  # highest power first
    q = np.poly1d(coefficients)
    dq = q.deriv()
    stationary = [s.real for s in dq.r if abs(s.imag) < 1e-12 and 0 < s.real < 1]
    assert len(stationary) == 2
    expected = max(abs(q(s)) for s in stationary)
    assert expected > max(abs(q(0.0)), abs(q(1.0)))
    got = hermite_peak(q(0.0), dq(0.0) / h, q(1.0), dq(1.0) / h, h, 0.0)
    assert got == pytest.approx(expected, rel=1e-14)


def test_running_peak_kept_when_the_step_cannot_exceed_it():
    """The bound max(|q₀|, |q₁|) + 4/27·h·(|q̇₀| + |q̇₁|) below the running peak: returned as is;
    a monotonic step (no interior stationary point) never lowers or raises it."""
    assert hermite_peak(0.1, 1.0, 0.2, 1.0, 0.01, 0.5) == 0.5
    assert hermite_peak(0.1, 10.0, 0.2, 10.0, 0.01, 0.15) == 0.15


def test_hybrid_peaks_match_the_exact_solution_sampled_finely():
    """With the interpolated peaks, every significant peak interstorey deflection (x, y, θ) of
    the eccentric 4-storey building under both components is within 1e-6 of the exact
    (matrix-exponential) solution sampled every 0.05 ms, where the exact samples' own error is
    (ω₁·0.05 ms)²/8 ≈ 5e-8. The hybrid's substeps are 2 ms (ω_max·h = 0.2), taken two at once
    here (no contact): sampled at the substeps alone, the peaks were 3.6e-4 off; the
    interpolant's bound over 4 ms is (ω·2h)⁴/384 = 6.7e-5 of the highest mode's share of a
    peak, and the peaks are the lower modes'. Measured 5.3e-7 (1.0e-7 with single substeps)."""
    loaded = _eccentric_case("hybrid")
    result = pound.run_model(loaded)
    assert result.diagnostics["cdm_steps"] == 0 and result.diagnostics["substep"] == pytest.approx(0.002)
    exact, _ = _exact_peaks(assemble(loaded).buildings[0], ground_motion(loaded), substeps=200)
    got = result.buildings["b"].interstorey_deflection
    for k, name in enumerate(("x", "y", "θ")):
        significant = exact[:, :, k] > 1e-3 * exact[:, :, k].max()
        rel = np.abs(got[:, :, k] - exact[:, :, k])[significant] / exact[:, :, k][significant]
        assert rel.max() < 1e-6, f"{name}: worst relative peak error {rel.max():.2e}"


def test_hybrid_peak_accelerations_match_the_exact_solution_sampled_finely():
    """Peak absolute floor accelerations (x, y, θ of every floor) of the same building, against
    the exact solution's −M⁻¹(K·u + C·v) sampled every 0.05 ms (its own sampling error
    (ω_max·0.05 ms)²/8 ≈ 3e-6 of the highest mode's share). Accelerations weigh the high
    modes by ω², so sampling them at the exact states alone missed by up to (ω·h)²/8 of the
    highest mode's share; the cubic through (a, ȧ) at both ends of each exact step is within
    (ω·h)⁴/384 of it: 6.7e-5 at the double substeps of 4 ms (ω_max·2h = 0.4)."""
    from exact import exact_response

    loaded = _eccentric_case("hybrid")
    result = pound.run_model(loaded)
    building = assemble(loaded).buildings[0]
    ground = ground_motion(loaded)
    a0, a1 = building.rayleigh
    damping = a0 * np.diag(building.mass) + a1 * building.stiffness
    influence = np.zeros((building.mass.size, 2))
    influence[0::3, 0] = 1.0
    influence[1::3, 1] = 1.0
    substeps = 200
    n = (ground.acceleration.shape[0] - 1) * substeps + 1
    u, v = exact_response(building.mass, building.stiffness, damping, influence, ground.acceleration, ground.dt,
                          substeps, n, velocities=True)  # fmt: skip
    exact = (np.abs(u @ building.stiffness.T + v @ damping.T) / building.mass).max(axis=0).reshape(-1, 3)
    got = result.buildings["b"].peak_acceleration
    rel = np.abs(got - exact) / exact
    print(f"worst relative peak acceleration error {rel.max():.2e}")
    assert rel.max() < 1e-4


def test_hybrid_energy_balance_closes_at_fourth_order():
    """The input and damping work over exact steps by the end-corrected trapezoidal rule
    h/2·(p₀ + p₁) + h²/12·(ṗ₀ − ṗ₁): the balance error of the eccentric building (no contact,
    every step exact) falls as h⁴: its observed order between the default substep (2 ms) and
    half of it is above 3.5 (the plain trapezoidal rule's is 2), and at the default it is
    below 1e-6 of the input (8.6e-5 with the trapezoidal rule). Measured 3.8e-7 and 3.0e-8:
    order 3.65."""
    from pounding_cli.api import execute, prepare
    from pounding_cli.bench.run import Setting, with_setting

    scene = prepare(_eccentric_case("hybrid"))
    errors, substeps = [], []
    for sampling in (0.2, 0.1):
        result = execute(with_setting(scene, Setting("x", "hybrid", sampling=sampling)))
        assert result.diagnostics["cdm_steps"] == 0
        errors.append(result.balance_error_ratio)
        substeps.append(result.diagnostics["substep"])
    order = np.log(errors[0] / errors[1]) / np.log(substeps[0] / substeps[1])
    print(f"balance error {errors[0]:.2e} at h = {substeps[0] * 1e3:.3g} ms, {errors[1]:.2e} at "
          f"{substeps[1] * 1e3:.3g} ms: order {order:.2f}")  # fmt: skip
    assert substeps[0] == pytest.approx(2 * substeps[1])
    assert order > 3.5
    assert errors[0] < 1e-6
