"""Tests of the planar finite-element reference (tests/fe_frame.py) against closed forms.

The reference is what pound's slab-to-storey contact is validated against (issue 23), so it is
itself checked here only against things that do not depend on it: textbook beam formulas,
the clamped–clamped frequency equation, two-body impact in closed form, and the conservation
laws of an undamped, frictionless impact.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize

from fe_frame import (
    ContactModel,
    Frame,
    Impact,
    LinearPhase,
    Neighbour,
    beam_mass,
    beam_stiffness,
    build_fe,
    build_reduced,
    clamped_beta,
    clamped_column_frequencies,
    clamped_mode,
    fixed_fixed_point_load,
    hermite_shapes,
    point_load_flexibility,
    simulate,
    static_point_load,
    storey_shape,
)

E = 21e9  # Pa, concrete (the paper's example)
I = 0.35**4 / 12  # m⁴, 35 × 35 cm column
EI = E * I
RHOA = 2500.0 * 0.35**2  # kg/m
K_C = 2.06e10 * 0.35  # N/m: pound's k_N (N/m²) times a 35 cm contact width


def small_frame(rhoA=RHOA, n_c=9, storeys=2, h=3.0):
    return Frame([64e3] * storeys, [h] * storeys, [n_c] * storeys, E, I, rhoA)


# --- statics --------------------------------------------------------------------------------


@pytest.mark.parametrize("xi", [0.1, 0.25, 0.5, 0.9])
@pytest.mark.parametrize("n_e", [2, 5])
def test_static_point_load_matches_fixed_fixed_closed_forms(xi, n_e):
    # Cubic Hermite elements contain the exact solution of EI·w'''' = 0 between nodes, so the
    # FE statics is exact whatever the mesh; what remains is the rounding of one small solve
    # (condition number ≲ 1e6 here), hence 1e-10 relative.
    h, P = 3.5, 1.0e5
    fe = static_point_load(EI, h, xi, n_e, P)
    ref = fixed_fixed_point_load(P, xi * h, h, EI)
    assert fe["deflection"] == pytest.approx(ref["deflection"], rel=1e-10)
    assert fe["V_bottom"] == pytest.approx(ref["V_bottom"], rel=1e-10)
    assert fe["V_top"] == pytest.approx(ref["V_top"], rel=1e-10)
    assert fe["M_bottom"] == pytest.approx(ref["M_bottom"], rel=1e-10)
    # sign convention of the reference: moments of the column on the floors, the top one
    # opposite to the bottom one under a point load
    assert fe["M_top"] == pytest.approx(-ref["M_top"], rel=1e-10)
    # equilibrium of the closed forms themselves
    assert ref["V_bottom"] + ref["V_top"] == pytest.approx(P, rel=1e-14)


@pytest.mark.parametrize("xi", [0.1, 0.25, 0.5, 0.57, 0.9])
def test_consistent_nodal_forces_are_the_fixed_end_reactions(xi):
    # Virtual work: a point load P at a on one element has the consistent nodal forces P·N(a).
    # For an element spanning the whole clamped column they are the fixed-end reactions, and
    # the translational weights are the storey shape: N₁ = 1 − s(ξ), N₃ = s(ξ). Pure
    # polynomial identities, so 1e-12.
    h, P = 3.5, 1.0e5
    a = xi * h
    N = P * hermite_shapes(a, h)
    ref = fixed_fixed_point_load(P, a, h, EI)
    assert N[0] == pytest.approx(ref["V_bottom"], rel=1e-12)
    assert N[1] == pytest.approx(ref["M_bottom"], rel=1e-12)
    assert N[2] == pytest.approx(ref["V_top"], rel=1e-12)
    assert N[3] == pytest.approx(-ref["M_top"], rel=1e-12)
    assert N[0] / P == pytest.approx(1 - storey_shape(xi), rel=1e-12)
    assert N[2] / P == pytest.approx(storey_shape(xi), rel=1e-12)
    # the element's stiffness and mass are symmetric, and rigid translation costs no energy
    Ke, Me = beam_stiffness(EI, 1.3), beam_mass(RHOA, 1.3)
    assert np.allclose(Ke, Ke.T) and np.allclose(Me, Me.T)
    assert np.allclose(Ke @ [1, 0, 1, 0], 0, atol=1e-6)
    assert np.array([1, 0, 1, 0]) @ Me @ [1, 0, 1, 0] == pytest.approx(RHOA * 1.3, rel=1e-14)


def test_modal_expansion_of_the_point_load_flexibility():
    # The clamped–clamped modes (unit mean square) expand the static Green's function:
    # Σ φ_k(ξ)²·h³/(EI·β_k⁴) → a³b³/(3EIh³). The tail decays like Σ k⁻⁴ ≈ 1/(3K³) relative to the
    # first term, so 40 modes leave a few 1e-5; the normalisation and orthogonality of the
    # analytic modes hold to quadrature accuracy (1e-12).
    z, w = np.polynomial.legendre.leggauss(300)
    z, w = 0.5 * (z + 1), 0.5 * w
    phis = np.array([clamped_mode(k, z) for k in range(1, 6)])
    gram = (phis * w) @ phis.T
    assert np.allclose(gram, np.eye(5), atol=1e-12)
    assert clamped_beta(1) == pytest.approx(4.7300, abs=5e-5)
    for k in range(1, 6):
        B = clamped_beta(k)
        assert np.cos(B) - 1 / np.cosh(B) == pytest.approx(0.0, abs=1e-14)  # cos·cosh = 1
        ends = clamped_mode(k, np.array([0.0, 1.0]))
        slopes = clamped_mode(k, np.array([0.0, 1.0]), derivative=1)
        assert np.max(np.abs(ends)) < 1e-12 and np.max(np.abs(slopes)) < 1e-11
    h = 3.5
    for xi in (0.25, 0.5, 0.75):
        s = sum(clamped_mode(k, xi) ** 2 * h**3 / (EI * clamped_beta(k) ** 4) for k in range(1, 41))
        assert s == pytest.approx(point_load_flexibility(EI, h, xi), rel=1e-4)


def test_clamped_column_frequency_converges_to_beta_L_4730():
    # Fixed–fixed first mode: ω₁ = (β₁L)²·√(EI/(ρA·L⁴)), β₁L = 4.7300. Consistent-mass Hermite
    # elements converge from above at O(h⁴): the error falls ≥ 10× per halving of the mesh
    # (16× asymptotically) and is below 1e-5 with 16 elements.
    h = 3.5
    exact = clamped_beta(1) ** 2 * np.sqrt(EI / (RHOA * h**4))
    errs = [clamped_column_frequencies(EI, RHOA, h, n, count=1)[0] / exact - 1 for n in (2, 4, 8, 16)]
    assert all(e > 0 for e in errs)
    assert all(errs[i] / errs[i + 1] > 10 for i in range(3))
    assert errs[-1] < 1e-5


# --- the time integration --------------------------------------------------------------------


def two_masses(m1, m2, k, c=0.0, gap=0.01):
    M = np.diag([m1, m2])
    Z = np.zeros((2, 2))
    return ContactModel(M, Z, Z.copy(), np.array([m1, m2]), 0, np.array([0.0, 1.0]), k, c, gap, {})


def test_two_body_impact_in_closed_form():
    # Two free masses, a linear contact spring: contact after gap/v, duration π/ω with
    # ω = √(k/μ), peak force v·√(kμ), impulse 2μv, exit velocities of an elastic collision.
    # The phases are solved in closed form and the events located to rounding: 1e-12.
    m1, m2, k, v, gap = 1000.0, 3000.0, 1e7, 1.0, 0.01
    mu = m1 * m2 / (m1 + m2)
    res = simulate(two_masses(m1, m2, k, gap=gap), np.zeros(2), np.array([v, 0.0]), 0.1, 1e-4)
    (imp,) = res.impacts
    assert imp.t0 == pytest.approx(gap / v, rel=1e-12)
    assert imp.t1 - imp.t0 == pytest.approx(np.pi / np.sqrt(k / mu), rel=1e-12)
    assert imp.peak == pytest.approx(v * np.sqrt(k * mu), rel=1e-12)
    assert imp.impulse == pytest.approx(2 * mu * v, rel=1e-12)
    x, vel = res.state_end
    assert vel == pytest.approx([(m1 - m2) / (m1 + m2) * v, 2 * m1 / (m1 + m2) * v], rel=1e-12)


def test_impact_with_a_dashpot_in_closed_form():
    # Kelvin–Voigt contact of a mass m on a fixed stop: mδ̈ + cδ̇ + kδ = 0 from δ = 0, δ̇ = v;
    # the contact ends when the force kδ + cδ̇ (not δ) returns to zero. Closed form
    # δ = (v/ω_d)e^(−ζωt)·sin(ω_d·t); the release time is the root of kδ + cδ̇ = 0 (brentq on
    # the closed form). After the release the mass leaves for good (no spurious re-contact
    # while δ > 0). The damped phase goes through complex eigenvectors: 1e-12.
    m, k, v = 1000.0, 1e7, 1.0
    w = np.sqrt(k / m)
    zeta = 0.2
    c = 2 * zeta * w * m
    wd = w * np.sqrt(1 - zeta**2)
    delta = lambda t: v / wd * np.exp(-zeta * w * t) * np.sin(wd * t)  # noqa: E731
    ddelta = lambda t: v * np.exp(-zeta * w * t) * (np.cos(wd * t) - zeta * w / wd * np.sin(wd * t))  # noqa: E731
    force = lambda t: k * delta(t) + c * ddelta(t)  # noqa: E731
    t_rel = scipy.optimize.brentq(force, 0.5 * np.pi / wd, np.pi / wd, xtol=1e-16)
    Z = np.zeros((1, 1))
    stop = ContactModel(np.array([[m]]), Z, Z.copy(), np.array([m]), 0, np.zeros(1), k, c, 0.0, {})
    res = simulate(stop, np.zeros(1), np.array([v]), 0.1, 1e-4)
    (imp,) = res.impacts
    assert imp.t0 == 0.0
    assert imp.t1 == pytest.approx(t_rel, rel=1e-12)
    J = scipy.integrate.quad(force, 0, t_rel, epsabs=0, epsrel=1e-13)[0]
    assert imp.impulse == pytest.approx(J, rel=1e-12)
    assert imp.impulse == pytest.approx(m * (v - ddelta(t_rel)), rel=1e-12)  # momentum
    assert res.state_end[1][0] == pytest.approx(ddelta(t_rel), rel=1e-12)
    assert delta(t_rel) > 0  # released while still overlapping: the case the logic must handle


def free_slab_case(rhoA, n_e, xi=0.5, t_end=0.12):
    frame = small_frame(rhoA)
    nb = Neighbour([128e3], [0.0])  # a free slab: its momentum change is the contact impulse
    imp = Impact(2, xi, K_C, v0=0.5, init="slab", gap=0.002)
    model, x0, v0 = build_fe(frame, nb, imp, n_e)
    return model, x0, v0, simulate(model, x0, v0, t_end, 1e-5), nb


@pytest.mark.parametrize("rhoA,n_e", [(0.0, 4), (RHOA, 6)])
def test_energy_and_momentum_of_an_undamped_impact(rhoA, n_e):
    # Undamped and frictionless: the energy ½vᵀMv + ½xᵀKx + ½k_c·δ² is constant and a free
    # slab's momentum changes by exactly the sum of the logged impulses. Each phase is an exact
    # closed form, so both hold to rounding, which here means what a double-precision modal
    # basis can hold: a relative error ε in the modes moves the energy (and the slab's
    # velocity) by ~ε·(ω_max/ω_min)² (the column's highest FE mode against the coupled system's
    # lowest), plus ~100ε for the re-projections at the events: 2e-14 with massless columns,
    # 2e-9 with 6 consistent-mass elements (measured: 9e-15 and 2.5e-10). With distributed column
    # mass the contact chatters: several impacts, all of them logged, in order.
    model, x0, v0, res, nb = free_slab_case(rhoA, n_e)
    E = np.array([e for _, e in res.energy])
    w2 = LinearPhase(*model.matrices(True)).w2
    tol = np.finfo(float).eps * (100 + w2.max() / w2[w2 > 0].min())
    assert np.max(np.abs(E / E[0] - 1)) < tol
    x, v = res.state_end
    dp = nb.masses[0] * (v[model.slab] - v0[model.slab])
    assert dp == pytest.approx(-res.impulse(), rel=tol)
    imps = res.impacts
    assert imps[0].t0 == pytest.approx(0.002 / 0.5, rel=1e-12)
    assert all(a.t1 <= b.t0 for a, b in zip(imps, imps[1:]))
    assert all(p.peak > 0 and p.impulse > 0 for p in imps)
    if rhoA:
        assert len(imps) > 1
    # the running integral of the contact force ends at the impulse
    assert res.integral["F"][-1] == pytest.approx(res.impulse(), rel=1e-12)


def test_massless_columns_condense_to_series_flexibility():
    # With ρA = 0 the contact node is massless; statically condensed it leaves k_c in series
    # with the column's local flexibility. Against floors 1e6 times heavier than the slab (so
    # the frame barely moves while the slab bounces) the contact lasts π·√(m/k_eff),
    # 1/k_eff = 1/k_c + a³b³/(3EIh³), and returns the impulse 2mv, to within the mass ratio
    # (1e-6), hence 1e-5.
    heavy = Frame([64e9] * 2, [3.0] * 2, [9] * 2, E, I, 0.0)
    nb = Neighbour([64e3], [0.0])
    imp = Impact(2, 0.3, K_C, v0=0.5, init="slab", gap=0.0)
    model, x0, v0 = build_fe(heavy, nb, imp, 4)
    res = simulate(model, x0, v0, 0.1, 1e-5)
    keff = 1 / (1 / K_C + point_load_flexibility(EI, 3.0, 0.3))
    first = res.impacts[0]
    assert first.t1 - first.t0 == pytest.approx(np.pi * np.sqrt(64e3 / keff), rel=1e-5)
    assert first.impulse == pytest.approx(2 * 64e3 * 0.5, rel=1e-5)
    assert first.peak == pytest.approx(0.5 * np.sqrt(keff * 64e3), rel=1e-5)


def test_ground_motion_load_counts_distributed_mass_once():
    # −M·r·a_g with r the rigid translation of every lateral DOF, ground nodes included: under a
    # constant a_g (after a ramp, transients damped out), a one-storey, one-column frame is in
    # uniform acceleration and the column's base force is the whole inertia:
    # −(m_floor + ρA·h)·a_g. Counting the column's mass twice (the OpenSees pitfall of DESIGN)
    # would give −(m + 2ρAh)·a_g. Mass-proportional damping (ζ = 1 in mode 1) kills the
    # transient (e^(−40·3) by the end), so 1e-9.
    h = 3.0
    frame = Frame([64e3], [h], [1], E, I, RHOA)
    k = 12 * EI / h**3
    w1 = np.sqrt(k / (64e3 + RHOA * h / 2))
    frame.rayleigh = (2 * w1, 0.0)
    nb = Neighbour([128e3], [1e8], rayleigh=(2 * w1, 0.0))
    imp = Impact(1, 0.5, K_C, gap=1.0, v0=0.0, init="slab")
    model, x0, v0 = build_fe(frame, nb, imp, 4)
    A0 = 1.0
    ground = (np.array([0.0, 0.5, 10.0]), np.array([0.0, A0, A0]))
    res = simulate(model, x0, v0, 6.0, 1e-3, ground=ground, energy=False)
    assert not res.impacts
    assert res.series["V_bot"][-1] == pytest.approx(-(64e3 + RHOA * h) * A0, rel=1e-9)
    # and the column pulls the floor along with exactly the floor's inertia
    assert res.series["V_top"][-1] == pytest.approx(64e3 * A0, rel=1e-9)


def test_reduced_sprung_form_is_the_craig_bampton_model():
    # The sprung-mass coordinates q′ = q + (M_qb/m_k)·u_b are an exact change of variables:
    # the same response to rounding (1e-9), with a mass matrix in which the modes do not couple
    # to the floors.
    frame = small_frame()
    nb = Neighbour([128e3] * 2, [1.75e8] * 2)
    imp = Impact(2, 0.3, K_C, v0=0.5)
    out = {}
    for form in ("cb", "sprung"):
        model, x0, v0 = build_reduced(frame, nb, imp, "c", 2, form=form)
        out[form] = simulate(model, x0, v0, 0.1, 1e-5, energy=False)
        if form == "sprung":
            q = [i for i, lab in enumerate(model.labels) if lab.startswith("q")]
            fl = [i for i, lab in enumerate(model.labels) if lab.startswith("A floor")]
            assert np.max(np.abs(model.M[np.ix_(q, fl)])) < 1e-9 * RHOA
    a, b = out["cb"], out["sprung"]
    assert b.summary()["peak_F"] == pytest.approx(a.summary()["peak_F"], rel=1e-9)
    for name in ("V_bot", "V_top", "M_bot", "M_top", "drift_A2", "drift_B2"):
        assert b.peak[name] == pytest.approx(a.peak[name], rel=1e-9)
