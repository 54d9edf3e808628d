"""The struck columns' local modes (assembly/local_modes.py), each against something independent.

- The clamped–clamped constants against their closed forms: β_k roots of cos β·cosh β = 1
  (Blevins' table: 4.730041, 7.853205, 10.995608, 14.137165), φ_k orthonormal and with zero
  value and slope at both ends, the couplings w_k against scipy's adaptive quadrature (1e-12:
  both are converged quadratures of smooth integrands), and the frequencies EI·β⁴/h³ against a
  64-element Hermite finite-element column (tests/fe_frame.py, 1e-6: the FE's own
  discretisation error at 64 elements is below 1e-8 for the first three modes).
- The residual flexibility: the point-load flexibility a³b³/(3EIh³) is the modes' static sum
  Σφ_k(ξ)²h³/(EIβ_k⁴) over all modes (Mercer's theorem for the clamped beam's Green's function),
  so the residual fraction falls towards 0 as modes are added, within the tail's bound.
- The assembled pseudo-floors: the rigid-body mass the ground drives (ιᵀMι) is unchanged by
  the modes (exact to rounding); every floor gives up m·w_b·Σw; the stiffness links add up to
  the 9 × 9 spring ½·k·(y − w·T·u)², which has the storey's rigid translation (u = 1, y = Σw) in
  its null space.
- A run: the energy balance closes to ≤ 1e-6 of the input (the time loop's own check) with the
  modes ringing through exact and CDM phases, and pound's plain CDM and hybrid agree on a linear
  run with the modes excited (no contact) to the CDM's phase error.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
import scipy.integrate

from pounding_cli.assembly.local_modes import (
    clamped_beta, clamped_mode, modal_mobility, residual_fraction, storey_weights,
)  # fmt: skip
from pounding_cli.assembly.storey_contact import storey_shape

import test_storey_fe as T
from fe_frame import clamped_column_frequencies

RHO = 2500.0


@pytest.mark.parametrize("k, beta", [(1, 4.730040745), (2, 7.853204624), (3, 10.995607838), (4, 14.137165491)])
def test_clamped_roots(k: int, beta: float) -> None:
    assert clamped_beta(k) == pytest.approx(beta, abs=1e-8)
    assert np.cos(clamped_beta(k)) * np.cosh(clamped_beta(k)) == pytest.approx(1.0, abs=1e-9)


def test_modes_are_orthonormal_and_clamped() -> None:
    x, w = np.polynomial.legendre.leggauss(300)
    xi, w = 0.5 * (x + 1), 0.5 * w
    phi = np.array([clamped_mode(k, xi) for k in range(1, 9)])
    assert np.allclose((phi * w) @ phi.T, np.eye(8), atol=1e-11)
    for k in range(1, 9):
        eps = 1e-6
        for end in (0.0, 1.0):
            assert abs(clamped_mode(k, end)) < 1e-9
            slope = (clamped_mode(k, min(1.0, end + eps)) - clamped_mode(k, max(0.0, end - eps))) / eps
            assert abs(slope) < 1e-3 * clamped_beta(k)


@pytest.mark.parametrize("k", [1, 2, 3, 5, 8])
def test_couplings_against_adaptive_quadrature(k: int) -> None:
    below = scipy.integrate.quad(lambda z: (1 - storey_shape(z)) * clamped_mode(k, z), 0, 1, epsabs=1e-14, limit=200)[0]
    above = scipy.integrate.quad(lambda z: storey_shape(z) * clamped_mode(k, z), 0, 1, epsabs=1e-14, limit=200)[0]
    assert storey_weights(k) == pytest.approx((below, above), abs=1e-12)
    if k % 2 == 0:  # antisymmetric about mid-height: no net translation
        assert sum(storey_weights(k)) == pytest.approx(0.0, abs=1e-12)


def test_frequencies_against_a_finite_element_column() -> None:
    ei, rho_a, h = T.E * T.I, RHO * T.B_COL**2, T.H
    fe = clamped_column_frequencies(ei, rho_a, h, 64, count=3)
    closed = [np.sqrt(ei * clamped_beta(k) ** 4 / h**3 / (rho_a * h)) for k in (1, 2, 3)]
    assert fe == pytest.approx(closed, rel=1e-6)


@pytest.mark.parametrize("xi", [0.1, 0.25, 0.5, 0.9])
def test_residual_flexibility_falls_to_zero(xi: float) -> None:
    fractions = [residual_fraction(xi, n) for n in (0, 1, 3, 8, 40)]
    assert fractions[0] == 1.0
    assert all(a >= b for a, b in zip(fractions, fractions[1:]))
    # what 40 modes leave is the tail 12·Σ_{k>40} φ_k(ξ)²/β_k⁴ over 4ξ³(1 − ξ)³, with φ_k² ≤ 4 and
    # β_k > (k + ½)π: a bound independent of the sum pound computes
    tail = 12 * 4 * sum(1 / ((k + 0.5) * np.pi) ** 4 for k in range(41, 100_000)) / (4 * xi**3 * (1 - xi) ** 3)
    assert 0 <= fractions[-1] <= tail
    assert modal_mobility(xi, 1000.0, 3) == pytest.approx(sum(clamped_mode(k, xi) ** 2 for k in (1, 2, 3)) / 1000.0)


def _scene(tmp_path, xi: float = 0.5, modes: int = 3) -> dict:
    m = T._pound_model(tmp_path, xi)
    m["materials"]["concrete"]["density"] = RHO
    m["materials"]["light"] = {"elastic_modulus": T.E, "poisson_ratio": 0.2}
    a, b = m["buildings"]
    column = RHO * T.B_COL**2 * T.H
    floors = []
    for i in range(3):
        f = copy.deepcopy(a["floors"][0])
        f["repeat"] = 1
        f.pop("mass_per_area")
        f["mass"] = 64e3 + 9 * column / 2 * (2 if i < 2 else 1)  # the floors hold their columns' mass
        floors.append(f)
    a["floors"] = floors
    b["floors"][0]["column_grid"]["material"] = "light"
    m["contact"]["column_modes"] = modes
    return m


def test_pseudo_floors_keep_the_ground_driven_mass(tmp_path) -> None:
    from pounding_cli.api import prepare
    from pounding_cli.model import validate_model

    plain = _scene(tmp_path, modes=0)
    with_modes = _scene(tmp_path, modes=3)
    a = prepare(validate_model(plain, tmp_path / "a.toml")).system
    b = prepare(validate_model(with_modes, tmp_path / "b.toml")).system
    assert a.n_dof == 3 * 4 and b.n_dof == 3 * 7 and len(b.local_modes) == 3
    for axis in (0, 1):
        assert (b.mass * b.influence**2)[axis::3].sum() == pytest.approx(a.mass[axis::3].sum(), rel=1e-14)
    column = RHO * T.B_COL**2 * T.H
    given = sum(m.mass * m.weights[0] * sum(m.weights) for m in b.local_modes)
    assert a.mass[0] - b.mass[0] == pytest.approx(given, rel=1e-12)  # floor 1, below the struck storey 2
    assert all(m.mass == pytest.approx(column) for m in b.local_modes)
    # the links add up to the modes' springs (dense on all DOFs), whose null space holds each
    # storey translation that carries the modes' masses along (u = 1 on both floors, y = Σw)
    n = b.n_dof
    dense = np.zeros((n + 3, n + 3))
    links = b.stiffness_links
    for k6, lo, hi in zip(links.matrix, links.bottom, links.top):
        idx = np.r_[3 * (lo if lo >= 0 else n // 3) + np.arange(3), 3 * hi + np.arange(3)]
        dense[np.ix_(idx, idx)] += k6
    springs = np.zeros((n + 3, n + 3))
    for m, p in zip(b.local_modes, b.mode_floor):
        idx = np.r_[3 * m.below + np.arange(3), 3 * m.above + np.arange(3), 3 * p + np.arange(3)]
        springs[np.ix_(idx, idx)] += m.spring()
    assert np.allclose(dense[:n, :n], springs[:n, :n], rtol=0, atol=1e-12 * np.abs(springs).max())
    for axis in (0, 1):
        x = np.zeros(n + 3)
        x[[axis, 3 + axis]] = 1.0
        for m, p in zip(b.local_modes, b.mode_floor):
            x[3 * p + axis] = sum(m.weights)
        assert np.abs(dense @ x).max() <= 1e-12 * np.abs(springs).max()


def test_modes_ring_through_both_integrators_alike(tmp_path) -> None:
    """Linear, no contact: the hybrid's exact propagation against the plain CDM at 2e-6 s, with
    two modes set ringing (0.1 and 0.05 m/s) under a ground motion; they agree to 1e-6 of each
    DOF's peak (measured 5e-6 of mode 3's, the CDM's phase error (ω·Δt)²/24 over 130 periods,
    below 1e-8 on the floors), and both balance their energy to 1e-6."""
    from pounding_cli.api import prepare
    from pounding_cli.model import validate_model
    from pounding_cli.solver.integrate import simulate

    system = prepare(validate_model(_scene(tmp_path), tmp_path / "m.toml")).system
    ground = np.zeros((60, 2))
    ground[:, 0] = 2.0 * np.sin(0.1 * np.arange(60))
    v0 = np.zeros(system.n_dof)
    v0[3 * int(system.mode_floor[0])] = 0.1
    v0[3 * int(system.mode_floor[2])] = 0.05
    runs = [simulate(system, ground, 0.01, 2e-6, 500, 500 * 120, initial_velocity=v0, substep=s) for s in (500, 0)]
    for d in range(0, 12, 3):  # the floors
        peak = np.abs(runs[1].displacement[:, d]).max()
        assert np.abs(runs[0].displacement[:, d] - runs[1].displacement[:, d]).max() <= 1e-6 * peak
    for p in system.mode_floor:
        peak = np.abs(runs[1].displacement[:, 3 * p]).max()
        assert np.abs(runs[0].displacement[:, 3 * p] - runs[1].displacement[:, 3 * p]).max() <= 2e-5 * peak
    for r in runs:
        assert abs(r.energy[-1, -1]) <= 1e-6 * r.energy[-1, 0]


def test_a_run_with_modes_balances_its_energy(tmp_path) -> None:
    from pounding_cli.api import run_model
    from pounding_cli.model import validate_model

    result = run_model(validate_model(_scene(tmp_path, 0.25, 3), tmp_path / "m.toml"), output=None)
    assert result.complete and result.contact.events.size >= 2
    assert result.diagnostics["balance_error_ratio"] <= 1e-6
    assert set(result.buildings["A"].peak_displacement.shape) == {3}  # the pseudo-floors are not in the results


def test_the_hybrid_meets_the_cdm_through_impacts(tmp_path) -> None:
    """The scene at ξ = 0.5 with three local modes, the hybrid (exact between contact phases)
    against the plain CDM at the same 2 µs contact step: the first cluster of impacts (20, before
    the chatter amplifies differences, test_local_modes_fe's docstring) agree impact by impact
    to 1e-5 in peak force and impulse (measured ≤ 2.5e-6: both integrate the contacts by the
    CDM; they differ in how the state got there, exactly or by the CDM at 2 µs), and both
    balance their energy to 1e-6 of the input."""
    from pounding_cli.api import run_model
    from pounding_cli.model import validate_model

    runs = []
    for integrator in ("hybrid", "cdm"):
        doc = _scene(tmp_path, 0.5, 3)
        doc["analysis"]["integrator"] = integrator
        runs.append(run_model(validate_model(doc, tmp_path / f"{integrator}.toml"), output=None))
    hybrid, cdm = (r.contact.events for r in runs)
    assert hybrid.size >= 20 and cdm.size >= 20
    for name in ("peak_normal_force", "normal_impulse"):
        assert np.max(np.abs(hybrid[name][:20] / cdm[name][:20] - 1)) <= 1e-5, name
    for r in runs:
        assert r.diagnostics["balance_error_ratio"] <= 1e-6


def test_a_failure_in_a_local_mode_is_named_as_one(tmp_path) -> None:
    from pounding_cli.api import prepare, where_it_failed
    from pounding_cli.model import validate_model

    system = prepare(validate_model(_scene(tmp_path), tmp_path / "m.toml")).system
    mode = system.local_modes[1]
    text = where_it_failed(system, 3 * int(system.mode_floor[1]) + 1)
    assert text == f"first at building 'A', local mode {mode.number} of the columns struck in storey 2 (u_y)"
    assert where_it_failed(system, 3) == "first at building 'A', floor 2 (u_x)"


def test_the_factored_solve_is_the_dense_one() -> None:
    """cdm._solve_reduced with integrate._factored (the Schur complement on a building's own
    floors, its local modes' block B_pp block-diagonal) against numpy's dense solve of the same
    B: 1e-12 relative (a well-conditioned random B; only rounding differs)."""
    import numba

    from pounding_cli.solver.cdm import solve_blocks
    from pounding_cli.solver.integrate import _factored

    @numba.njit
    def solve(binv, start, count, real, r, out):
        solve_blocks(binv, start, count, real, r, out)

    rng = np.random.default_rng(7)
    nr, n_p = 9, 12
    n = nr + n_p
    a = rng.normal(0, 1, (n, n))
    b = a @ a.T + n * np.eye(n)
    for j in range(nr, n, 3):  # a mode is linked to the floors alone
        for k in range(nr, n, 3):
            if k != j:
                b[j : j + 3, k : k + 3] = 0.0
    x = rng.normal(0, 1, n)
    r = b @ x
    out = np.zeros(n)
    solve(_factored(b, nr)[None], np.array([0]), np.array([n]), np.array([nr]), r.copy(), out)
    assert np.allclose(out, np.linalg.solve(b, r), rtol=0, atol=1e-12 * np.abs(x).max())


def test_columns_struck_by_two_slabs_in_two_sets_are_warned_of(tmp_path) -> None:
    """A second strip B2 strikes A's façade between two columns (y 0.5–1.5 m: the columns at
    y = 0 and 4 m take it), B the column at y = 4 m alone: that column is in two bundles with
    modes of their own, and its mass in both: a warning names it."""
    from pounding_cli.plausibility import notices
    from pounding_cli.api import prepare
    from pounding_cli.model import validate_model

    doc = _scene(tmp_path)
    b2 = copy.deepcopy(doc["buildings"][1])
    b2["name"] = "B2"
    b2["origin"] = [b2["origin"][0], 0.5]
    doc["buildings"].append(b2)
    scene = prepare(validate_model(doc, tmp_path / "m.toml"))
    bundles = {m.columns for m in scene.system.local_modes}
    assert len(bundles) == 2 and len(set.intersection(*map(set, bundles))) == 1
    found = [n for n in notices(scene) if "struck by two slabs" in n.message]
    assert len(found) == 1 and "storey 2 of building 'A'" in found[0].message
    single = prepare(validate_model(_scene(tmp_path), tmp_path / "one.toml"))
    assert not [n for n in notices(single) if "struck by two slabs" in n.message]


def test_floors_lighter_than_the_mass_the_modes_take_are_refused(tmp_path) -> None:
    """Floors of 400 kg beside 1,072 kg columns (the floors' masses must include their columns',
    half of each): the modes would take more than the floor has; pound validate exits 2 naming
    the file and the field."""
    import json
    import subprocess
    import sys

    doc = _scene(tmp_path)
    for floor in doc["buildings"][0]["floors"]:
        floor["mass"] = 400.0
    path = tmp_path / "light.json"
    path.write_text(json.dumps(doc))
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "light.json" in proc.stderr and "contact.column_modes" in proc.stderr
    assert "take more mass (or rotational inertia) from its floor" in proc.stderr


def test_auto_takes_the_modes_up_to_eight_times_the_contacts_frequency(tmp_path) -> None:
    """column_modes = "auto" (the default) in the FE comparison's scene: the contact's own
    frequency against the struck column's mass √(k_N·L/m), L = 1 m, is 4,380 rad/s, and the
    fewest modes whose highest reaches 8 times it are 12 (ω₁₁ = 7.1×, ω₁₂ = 8.4×): the count
    tests/test_local_modes_fe.py measured the first peak force within 0.4 % with (8 modes: 7.6 %)."""
    from pounding_cli.api import prepare
    from pounding_cli.model import validate_model

    doc = _scene(tmp_path)
    del doc["contact"]["column_modes"]
    system = prepare(validate_model(doc, tmp_path / "m.toml")).system
    assert len(system.local_modes) == 12
    k_c = T.K_N * 1.0
    mass = RHO * T.B_COL**2 * T.H
    omega_c = np.sqrt(k_c / mass)
    omegas = [np.sqrt(clamped_beta(k) ** 4 * T.E * T.I / T.H**3 / mass) for k in (11, 12)]
    assert omegas[0] < 8 * omega_c <= omegas[1]
    assert system.local_modes[-1].omega == pytest.approx(omegas[1], rel=1e-12)


def test_auto_held_at_its_cap_is_warned_of(tmp_path) -> None:
    """A contact 10 times stiffer (k_N given) would need more than 16 modes by the "auto" rule:
    a warning on contact.column_modes says so; the FE scene's own contact (12 modes) none."""
    from pounding_cli.api import prepare
    from pounding_cli.model import validate_model
    from pounding_cli.plausibility import notices

    doc = _scene(tmp_path)
    del doc["contact"]["column_modes"]
    plain = prepare(validate_model(doc, tmp_path / "m.toml"))
    assert not [n for n in notices(plain) if n.field == "contact.column_modes"]
    doc["contact"]["k_normal"] = 10 * T.K_N
    stiff = prepare(validate_model(doc, tmp_path / "stiff.toml"))
    assert len(stiff.system.local_modes) == 16
    (found,) = [n for n in notices(stiff) if n.field == "contact.column_modes"]
    assert "would need more than 16 local modes" in found.message and "storey 2 of building 'A'" in found.message
