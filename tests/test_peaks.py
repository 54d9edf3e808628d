"""Peaks between exact states: the quintic Hermite interpolant's maximum (solver/peaks.py)
against closed forms, and the hybrid's peaks against the exact solution sampled finely."""

from __future__ import annotations

import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli.assembly import assemble, ground_motion
from pounding_cli.solver.peaks import CREST_DISPLACEMENT, quintic_crests
from pounding_cli.solver.tunables import CREST_SPAN

from test_time_history import _eccentric_case, _exact_peaks


def _crests(q0, m0, c0, q1, m1, c1, h, floor):
    """quintic_crests' list: the s = τ/h of the stationary points it finds above floor."""
    crests = np.zeros((4, 3))
    n = quintic_crests(q0, m0, c0, q1, m1, c1, h, floor, CREST_DISPLACEMENT, 7, crests, 0)
    assert np.all(crests[:n, :2] == [CREST_DISPLACEMENT, 7])
    return crests[:n, 2]


@pytest.mark.parametrize("omega_h", [0.8, 1.6, 4.0])
def test_quintic_locates_the_crest_of_a_sine(omega_h):
    """q = A·cos(ω(τ − τ_c)) with its crest at τ_c inside the step, given q, q̇ and q̈ at both
    ends: the quintic's stationary points are within (ω·h)⁵/3840 of a radian of the crest and
    of a trough a half period off, where ω·h > π puts one inside the step (its
    derivative's Hermite error over the curvature Aω²), well inside Newton's reach (a quarter
    period) up to the longest step the peaks allow (ω·h = CREST_SPAN = 4: 0.27 rad)."""
    amplitude, omega = 0.03, 20.0
    h = omega_h / omega
    for fraction in np.linspace(0.02, 0.98, 49):
        crest = fraction * h
        q0, q1 = (amplitude * np.cos(omega * (t - crest)) for t in (0.0, h))
        m0, m1 = (-amplitude * omega * np.sin(omega * (t - crest)) for t in (0.0, h))
        c0, c1 = -(omega**2) * q0, -(omega**2) * q1
        found = _crests(q0, m0, c0, q1, m1, c1, h, 0.0)
        exact = fraction + np.arange(-2, 3) * np.pi / omega_h  # the crest, and the troughs a half period off
        exact = exact[(exact > 0.0) & (exact < 1.0)]
        assert len(found) == len(exact), fraction
        assert np.abs(found - exact).max() * omega_h <= omega_h**5 / 3840, fraction
    assert omega_h <= CREST_SPAN


def test_quintic_interpolated_exactly():
    """A quintic is its own Hermite interpolant: its interior extrema, found by numpy's roots
    of q', are listed to rounding (q = s(1 − s)(s − 0.35)(s² + 0.1) + 0.001 on s = τ/h,
    h = 0.5 s: stationary at s = 0.20 and 0.82, |q| = 0.0546 at the latter, 0.001 at the ends);
    a floor between their values lists the higher alone."""
    h = 0.5
    q = np.poly1d([-1.0, 1.0, 0.0]) * np.poly1d([1.0, -0.35]) * np.poly1d([1.0, 0.0, 0.1]) + 0.001
    dq, ddq = q.deriv(), q.deriv(2)
    stationary = sorted(s.real for s in dq.r if abs(s.imag) < 1e-12 and 0 < s.real < 1)
    assert len(stationary) == 2
    ends = (q(0.0), dq(0.0) / h, ddq(0.0) / h**2, q(1.0), dq(1.0) / h, ddq(1.0) / h**2, h)
    np.testing.assert_allclose(_crests(*ends, 0.0), stationary, rtol=1e-12)
    lower, higher = sorted(abs(q(s)) for s in stationary)
    assert higher > max(abs(q(0.0)), abs(q(1.0)))
    np.testing.assert_allclose(_crests(*ends, 0.5 * (lower + higher)), [stationary[1]], rtol=1e-12)


def test_nothing_listed_when_the_step_cannot_reach_the_floor():
    """The bound max(|q₀|, |q₁|) + 4/27·h·(|q̇₀| + |q̇₁|) + 0.01728·(|E₀| + |E₁|) below the
    floor (E: the second derivatives' mismatch with the cubic's): nothing listed; a monotonic
    step (no interior stationary point) lists nothing either."""
    assert len(_crests(0.1, 1.0, 0.0, 0.2, 1.0, 0.0, 0.01, 0.5)) == 0
    assert len(_crests(0.1, 10.0, 0.0, 0.2, 10.0, 0.0, 0.01, 0.15)) == 0
    assert len(_crests(0.1, 10.0, 50.0, 0.2, 10.0, -50.0, 0.01, 0.15)) == 0


@pytest.mark.parametrize("omega_h", [1.0, 1.64, 2.5, 3.9])
def test_peaks_between_exact_states_are_exact_at_any_span(omega_h):
    """A one-storey symmetric building in free vibration along x (initial velocity v₀, no
    ground motion) is a damped oscillator: u = v₀/ω_d·e^(−ζωt)·sin(ω_d·t), closed form. The
    hybrid propagates it exactly in steps of ω·h = 1, 1.64 (the paper's scenes), 2.5 and 3.9
    (an output at every step: none doubled), where the larger end value misses the crest by up to 1 − cos(ω·h/2) of it (62 %
    at 3.9) and the quintic alone by up to (ω·h)⁶/46080 (7.6 %): the peak displacement and the
    peak absolute acceleration −(ω²·u + 2ζω·v) agree with the closed form's maxima (by
    scipy's bounded search on it) to 1e-12, the Taylor series' truncation and rounding."""
    from scipy.optimize import minimize_scalar

    from pounding_cli.assembly import assemble
    from pounding_cli.solver import simulate
    from pounding_cli.solver.integrate import damping_blocks, stiffness_blocks
    from conftest import load_doc, model_doc, square_building

    system = assemble(load_doc(model_doc(square_building(storeys=1))))
    m, k, c = system.mass[0], stiffness_blocks(system)[0][0, 0], damping_blocks(system)[0][0, 0]
    assert np.allclose(stiffness_blocks(system)[0][0, 1:], 0.0)  # x is a mode of its own
    omega, zeta = np.sqrt(k / m), c / (2.0 * np.sqrt(k * m))
    omega_d = omega * np.sqrt(1.0 - zeta**2)
    v0 = 0.3
    h = omega_h / omega
    sub, n_sub = 4, int(np.ceil(4 * np.pi / omega / h))  # two periods
    response = simulate(system, np.zeros((n_sub + 1, 2)), h, h / sub, sub, n_sub * sub,
                        initial_velocity=np.array([v0, 0.0, 0.0]), substep=sub)  # fmt: skip
    assert response.integrator == "hybrid" and response.cdm_steps == 0
    assert response.exact_substeps == n_sub  # one span each: an output sample ends every substep

    def u(t):
        return v0 / omega_d * np.exp(-zeta * omega * t) * np.sin(omega_d * t)

    def v(t):
        return v0 * np.exp(-zeta * omega * t) * (np.cos(omega_d * t) - zeta * omega / omega_d * np.sin(omega_d * t))

    def a(t):
        return -(omega**2 * u(t) + 2.0 * zeta * omega * v(t))

    span = n_sub * h
    for f, got in ((u, response.peak_displacement[0]), (a, response.peak_acceleration[0])):
        grid = np.linspace(0.0, span, 20001)
        i = int(np.argmax(np.abs(f(grid))))
        best = minimize_scalar(lambda t: -abs(f(t)), bounds=(grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]),
                               method="bounded", options={"xatol": 1e-15})  # fmt: skip
        exact = max(-best.fun, abs(f(grid[i])))
        ends = np.abs(f(np.arange(n_sub + 1) * h)).max()
        assert (exact - ends) / exact > 1e-3 * omega_h**2  # the crests fall between the exact states
        assert got == pytest.approx(exact, rel=1e-12)


def test_hybrid_peaks_match_the_exact_solution_sampled_finely():
    """With the peaks between exact states, every significant peak interstorey deflection (x, y,
    θ) of the eccentric 4-storey building under both components is within 4e-7 of the exact
    (matrix-exponential) solution sampled every 0.05 ms, where the exact samples' own error is
    (ω₁·0.05 ms)²/8 ≈ 5e-8. The hybrid's substeps are the whole 10 ms record interval here
    (ω_max·h = 0.99, no contact): sampled at the substeps alone, the peaks were 3.6e-4 off at
    2 ms; the quintic alone would allow (ω·h)⁶/46080 = 2.0e-5 of the highest mode's share, and
    the exact crests (settle_crests) remove even that. Measured 1.7e-7: the exact samples' own
    error, as with the quintic alone at ω_max·h = 0.1 … 0.8 before."""
    loaded = _eccentric_case("hybrid")
    result = pound.run_model(loaded)
    assert result.diagnostics["cdm_steps"] == 0 and result.diagnostics["substep"] == pytest.approx(0.01)
    exact, _ = _exact_peaks(assemble(loaded).buildings[0], ground_motion(loaded), substeps=200)
    got = result.buildings["b"].interstorey_deflection
    for k, name in enumerate(("x", "y", "θ")):
        significant = exact[:, :, k] > 1e-3 * exact[:, :, k].max()
        rel = np.abs(got[:, :, k] - exact[:, :, k])[significant] / exact[:, :, k][significant]
        print(f"{name}: worst relative peak error {rel.max():.2e}")
        assert rel.max() < 4e-7, f"{name}: worst relative peak error {rel.max():.2e}"


def test_hybrid_peak_accelerations_match_the_exact_solution_sampled_finely():
    """Peak absolute floor accelerations (x, y, θ of every floor) of the same building, against
    the exact solution's −M⁻¹(K·u + C·v) sampled every 0.05 ms (its own sampling error
    (ω_max·0.05 ms)²/8 ≈ 3e-6 of the highest mode's share). Accelerations weigh the high
    modes by ω², so sampling them at the exact states alone missed by up to (ω·h)²/8 of the
    highest mode's share; the quintic through (a, ȧ, ä) at both ends of each exact step is
    within (ω·h)⁶/46080 of it: 1.9e-6 at the double substeps of 6.7 ms (ω_max·2h = 0.67).
    Measured 1.9e-7; the cubic through (a, ȧ) alone gave 2.2e-5 at this substep."""
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
    assert rel.max() < 1e-6


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_exact_crests_of_a_mode_sum_at_the_longest_span(seed):
    """An eccentric 3-storey building (9 coupled modes, 5 % Rayleigh damping) in free
    vibration from a random initial velocity, every exact step at ρ·h = 3.9 (just within
    CREST_SPAN; an output at every step, so none is doubled): the peak floor displacements
    and absolute accelerations agree with the exact solution's maxima to 1e-10. The exact
    solution is the state matrix's eigen-expansion x(t) = V·e^(Λt)·V⁻¹·x₀, sampled 400 times a
    step and each maximum refined by scipy's bounded search; its own error is rounding,
    ~1e-13. Here the sum of modes puts several crests in some steps, where a single mode puts
    one: the case the prototype's random mode sums covered (theory §6). Measured 3.5e-14 to
    7.4e-14."""
    from scipy.optimize import minimize_scalar

    from pounding_cli.assembly import assemble
    from pounding_cli.solver import simulate
    from pounding_cli.solver.integrate import building_dofs, damping_blocks, fastest_rate, stiffness_blocks
    from conftest import load_doc, model_doc, square_building

    system = assemble(load_doc(model_doc(square_building(storeys=3, eccentricity=(0.4, -0.3)))))
    k, c, m = stiffness_blocks(system)[0], damping_blocks(system)[0], system.mass
    n = m.size
    rho = fastest_rate([k], [c], m, *building_dofs(system))
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-k / m[:, None], -c / m[:, None]]])
    lam, vec = np.linalg.eig(a)
    rng = np.random.default_rng(seed)
    v0 = rng.normal(size=n) * np.tile([0.2, 0.2, 0.02], n // 3)
    coef = np.linalg.solve(vec, np.concatenate([np.zeros(n), v0]))
    h = 3.9 / rho
    n_sub = int(np.ceil(2.0 * 2.0 * np.pi / np.abs(lam).min() / h))  # two periods of the slowest mode
    response = simulate(system, np.zeros((n_sub + 1, 2)), h, h / 4, 4, 4 * n_sub, initial_velocity=v0, substep=4)
    assert response.status == "complete" and response.cdm_steps == 0 and response.exact_substeps == n_sub

    def motion(t, row):  # the exact displacement (row < n) or absolute acceleration (row ≥ n) of a DOF
        x = (np.exp(np.multiply.outer(np.atleast_1d(t), lam)) * coef) @ vec.T  # (times, 2n)
        if row < n:
            return x[:, row].real
        return (-(k[row - n] @ x[:, :n].T + c[row - n] @ x[:, n:].T) / m[row - n]).real

    grid = np.linspace(0.0, n_sub * h, 400 * n_sub + 1)
    worst = 0.0
    for row, got in enumerate(np.concatenate([response.peak_displacement, response.peak_acceleration])):
        values = np.abs(motion(grid, row))
        i = int(np.argmax(values))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        best = minimize_scalar(lambda t: -abs(motion(t, row)[0]), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-15})  # fmt: skip
        exact = max(-best.fun, values[i])
        worst = max(worst, abs(got - exact) / exact)
    print(f"seed {seed}: worst relative peak error {worst:.1e} over {2 * n} peaks, {n_sub} steps of ρ·h = 3.9")
    assert worst < 1e-10
