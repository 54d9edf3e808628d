"""An isolated single-storey building against an independent solution of the same equations
(issue 6, "Validation": within 1 % on peak isolator displacement and superstructure drift).

The building: a 6 m × 6 m base slab (36 t) on four identical lead-rubber bearings at its
corners (K1 = 1.8 MN/m, K2 = 0.18 MN/m, Q = 9 kN, so F_y = 10 kN and d_y = 5.56 mm), one
storey of 3 m with four 35 × 35 cm concrete columns at the corners (linear) under a 36 t
floor, 5 % Rayleigh damping of the superstructure at its modes 1 and 3 on a fixed base, no
viscous damping of the isolation system (the default). Doubly symmetric, so shaken along x
it moves along x only: two DOFs, u_b (base slab) and u_1 (floor), relative to the ground,

    M·ü + C·u̇ + K0·u − (4·k_h·p, 0) = −M·1·a_g(t),
    M = diag(m_b, m_1),  K0 = [[4·K1 + k_c, −k_c], [−k_c, k_c]],
    C = c_s·[[1, −1], [−1, 1]],  c_s = a0·m_1 + a1·k_c,

with k_c = 4·12EI/h³, k_h = K1 − K2 and p the bearings' plastic deflection (the bilinear
bearing split into a linear spring K2 and an elastic–perfectly-plastic one k_h, f_h = (1 −
K2/K1)·F_y; docs/theory.md §12). C is the superstructure's fixed-base Rayleigh damping
a0·m_1 + a1·k_c acting on its drift u_1 − u_b, the dashpot of the classical two-mass model of
an isolated building (docs/theory.md §12, "Damping of an isolated building"): nothing damps
the building moving rigidly on its bearings but their hysteresis. a0, a1 are taken from the
result (BuildingResult.rayleigh) and checked against the two fixed-base modes they are
anchored to; M and K0 are checked against the reported periods.

The reference integrates this with scipy's solve_ivp (LSODA, rtol 1e-10, atol 1e-13) with
the bearing as an event-driven EPP spring: elastic (p fixed) until |u_b − p| reaches δ_y =
f_h/k_h (event), then plastic (p = u_b ∓ δ_y, the bearing force 4·(K2·u_b ± f_h)) until the
base slab's velocity reverses (event). The ground acceleration is the record's samples,
linear between them (np.interp), zero after its end, as pound applies it. Radau at the same
tolerance agrees with it to 1e-9 (checked while writing this test; LSODA is 7× faster).

The ground motion: three cycles of a 1 Hz sine of 3 m/s², sampled at 0.01 s and written as a
one-column plain-text record, then 5 s of free vibration. The bearings yield nine times
(ductility ≈ 44), so both integrators spend most of the shaking on the yield branch.

Measured (hybrid at the default step, CDM Δt 1 ms / exact substeps 2 ms, 18 hand-overs;
CDM at its default Δt 1.11 ms), relative errors, hybrid / CDM:
  peak isolator displacement        8.5e-6 / 6.8e-6
  peak superstructure drift         1.0e-5 / 7.4e-6
  u_b history (of its peak)         1.4e-5 / 7.4e-6
  drift history (of its peak)       1.5e-4 / 2.1e-4
  bearing force history             2.8e-5 / 2.2e-5
  residual deflection               3.2e-5 / 5.0e-6
  hysteretic energy vs reference    1.1e-5 / 9.2e-6
  loop area (0.01 s outputs)        4.4e-4 / 4.4e-4 of the hysteretic energy
  energy balance_error_ratio        9.1e-6 / 3.7e-6
The tests assert 1e-3 (ten times tighter than the issue's 1 %), 1e-2 for the residual
deflection and the loop area, 1e-3 for the balance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pounding_cli import run_model
from pounding_cli.model import validate_model

SIZE = 6.0  # m
MASS_PER_AREA = 1000.0  # kg/m²
K1, K2, Q = 1.8e6, 1.8e5, 9.0e3  # N/m, N/m, N
N_ISO = 4
E_CONCRETE = 21e9
SECTION = 0.35
HEIGHT = 3.0
RECORD_DT = 0.01
DURATION = 8.0
TOL = 1e-3  # relative; the issue asks for 1 %


def ground_motion() -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(0.0, 4.0 + 1e-9, RECORD_DT)
    return t, np.where(t <= 3.0, 3.0 * np.sin(2 * np.pi * t), 0.0)


def model_doc(integrator: str) -> dict:
    square = [[0, 0], [SIZE, 0], [SIZE, SIZE], [0, SIZE]]
    return {
        "materials": {"concrete": {"elastic_modulus": E_CONCRETE, "poisson_ratio": 0.2}},
        "bearings": {"lrb": {"initial_stiffness": K1, "post_yield_stiffness": K2, "characteristic_strength": Q}},
        "buildings": [
            {
                "name": "iso",
                "damping": {"ratios": [0.05, 0.05], "modes": [1, 3]},
                "isolation": {
                    "height": 0.5,
                    "slab": square,
                    "mass_per_area": MASS_PER_AREA,
                    "isolator_grid": {"x": [0, SIZE], "y": [0, SIZE], "bearing": "lrb"},
                },
                "floors": [
                    {
                        "height": HEIGHT,
                        "slab": square,
                        "mass_per_area": MASS_PER_AREA,
                        "column_grid": {"x": [0, SIZE], "y": [0, SIZE], "section": [SECTION, SECTION],
                                        "material": "concrete"},  # fmt: skip
                    }
                ],
            }
        ],
        "excitation": {
            "angle": 0.0,
            "components": ["L"],
            "record": {"L": {"file": "pulse.txt", "units": "m/s2", "dt": RECORD_DT, "format": "text"}},
        },
        "analysis": {"duration": DURATION, "integrator": integrator},
    }


def column_stiffness() -> float:
    """All four columns, 12EI/h³ each, N/m."""
    return N_ISO * 12 * E_CONCRETE * (SECTION**4 / 12) / HEIGHT**3


def reference(m: tuple[float, float], a0: float, a1: float, t_rec: np.ndarray, a_rec: np.ndarray,
              rtol: float = 1e-10, atol: float = 1e-13) -> dict:  # fmt: skip
    """The event-driven 2-DOF solution: dense samples every ≤ 1e-4 s of (u_b, u_1, v_b, v_1)
    and of p, and the energy the bearings dissipated (4·f_h·Σ|Δp|)."""
    fy = Q * K1 / (K1 - K2)
    alpha = K2 / K1
    kh, fh = (1 - alpha) * K1, (1 - alpha) * fy
    dy = fh / kh
    kc = column_stiffness()
    mass = np.array(m)
    k0 = np.array([[N_ISO * K1 + kc, -kc], [-kc, kc]])
    c = (a0 * mass[1] + a1 * kc) * np.array([[1.0, -1.0], [-1.0, 1.0]])  # on the drift only

    def rhs(phase: int, p: float):
        def f(t, y):
            g = N_ISO * kh * (p if phase == 0 else y[0] - phase * dy)
            ag = np.interp(t, t_rec, a_rec, right=0.0)
            acc = (-mass * ag - c @ y[2:] - k0 @ y[:2] + np.array([g, 0.0])) / mass
            return np.concatenate([y[2:], acc])

        return f

    def event(fun, direction):
        fun.terminal, fun.direction = True, direction
        return fun

    ts, ys, ps = [], [], []
    t0, y0, phase, p, p_start, dissipated, n_events = 0.0, np.zeros(4), 0, 0.0, 0.0, 0.0, 0
    while t0 < DURATION - 1e-12:
        if phase == 0:
            events = [event(lambda t, y, p=p: y[0] - p - dy, 1), event(lambda t, y, p=p: y[0] - p + dy, -1)]
        else:
            events = [event(lambda t, y: y[2], -phase)]
        sol = solve_ivp(rhs(phase, p), (t0, DURATION), y0, method="LSODA", rtol=rtol, atol=atol,
                        events=events, dense_output=True)  # fmt: skip
        assert sol.success, sol.message
        t1 = sol.t[-1]
        tt = np.linspace(t0, t1, max(2, math.ceil((t1 - t0) / 1e-4) + 1))
        yy = sol.sol(tt)
        ts.append(tt)
        ys.append(yy)
        ps.append(np.full(tt.size, p) if phase == 0 else yy[0] - phase * dy)
        y1 = sol.y[:, -1]
        if sol.status == 1:  # an event ended the phase
            n_events += 1
            if phase == 0:
                phase = 1 if sol.t_events[0].size else -1
                y1 = (sol.y_events[0] if phase == 1 else sol.y_events[1])[0]
                p_start = y1[0] - phase * dy
                assert abs(p_start - p) < 1e-9 * dy
            else:
                p = y1[0] - phase * dy
                dissipated += N_ISO * fh * abs(p - p_start)
                phase = 0
        t0, y0 = t1, y1
    if phase != 0:
        p = y0[0] - phase * dy
        dissipated += N_ISO * fh * abs(p - p_start)
    t = np.concatenate(ts)
    y = np.concatenate(ys, axis=1)
    return {"t": t, "u": y[:2], "v": y[2:], "p": np.concatenate(ps), "dissipated": dissipated,
            "p_final": p, "yield_events": n_events, "kh": kh, "alpha": alpha, "fy": fy}  # fmt: skip


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("isolation")
    t_rec, a_rec = ground_motion()
    np.savetxt(tmp / "pulse.txt", a_rec, header="1 Hz sine, 3 cycles, m/s2, dt = 0.01 s")
    results = {name: run_model(validate_model(model_doc(name), tmp / "model.toml")) for name in ("auto", "cdm")}
    b = results["auto"].buildings["iso"]
    ref = reference(tuple(b.floor_mass[:, 0]), *b.rayleigh, t_rec, a_rec)
    return results, ref


@pytest.fixture(params=["auto", "cdm"])
def case(request, runs):
    results, ref = runs
    return request.param, results[request.param], ref


def test_model_is_the_reference_2dof(runs):
    """Masses, stiffness (through the periods) and Rayleigh coefficients of the run are those
    the reference assumes."""
    results, _ = runs
    b = results["auto"].buildings["iso"]
    m = MASS_PER_AREA * SIZE**2
    j = m * 2 * SIZE**2 / 12
    np.testing.assert_allclose(b.floor_mass, [[m, j], [m, j]], rtol=1e-12)
    assert b.isolated
    # x (= y) and torsion of the full 6-DOF model: translation K0, torsion Σ k·r² (r² = 2·(S/2)²)
    kc = column_stiffness()
    k0 = np.array([[N_ISO * K1 + kc, -kc], [-kc, kc]])
    r2 = 2 * (SIZE / 2) ** 2
    w_x = np.sqrt(np.linalg.eigvalsh(k0 / m))  # M = m·I
    w_t = np.sqrt(np.linalg.eigvalsh(k0 * r2 / j))
    omegas = np.sort(np.concatenate([w_x, w_x, w_t]))
    np.testing.assert_allclose(b.periods, 2 * np.pi / omegas, rtol=1e-9)
    # Rayleigh damping from the superstructure on a fixed base: x (= y) at √(k_c/m), torsion at
    # √(Σk·r²/J) = √(18·k_c/(6·m)) (the four corner columns, each k_c/4 along x and y)
    w1, w3 = np.sqrt(kc / m), np.sqrt(kc * r2 / j)
    zeta = 0.05
    np.testing.assert_allclose(b.rayleigh, (2 * zeta * w1 * w3 / (w1 + w3), 2 * zeta / (w1 + w3)), rtol=1e-9)
    members = b.yielding.members
    assert list(members["kind"]) == ["isolator"] * 4
    np.testing.assert_allclose(members["stiffness"], K1, rtol=1e-12)
    np.testing.assert_allclose(members["yield_force"], Q * K1 / (K1 - K2), rtol=1e-12)
    np.testing.assert_allclose(members["post_yield_ratio"], K2 / K1, rtol=1e-12)


def test_reference_is_converged(runs):
    """The reference's own error: at rtol 1e-8 (100 times looser) its peaks move by 5e-7
    (measured), far below what the tests resolve; at 1e-10 the error is smaller still."""
    results, ref = runs
    b = results["auto"].buildings["iso"]
    t_rec, a_rec = ground_motion()
    loose = reference(tuple(b.floor_mass[:, 0]), *b.rayleigh, t_rec, a_rec, rtol=1e-8, atol=1e-11)
    assert np.abs(loose["u"][0]).max() == pytest.approx(np.abs(ref["u"][0]).max(), rel=1e-6)
    assert np.abs(loose["u"][1] - loose["u"][0]).max() == pytest.approx(np.abs(ref["u"][1] - ref["u"][0]).max(), rel=1e-6)
    assert ref["yield_events"] >= 8  # the bearings yield on both sides, several times


def test_peaks_against_reference(case):
    integrator, result, ref = case
    assert result.complete
    assert result.diagnostics["integrator"] == ("hybrid" if integrator == "auto" else integrator)
    assert result.diagnostics["contact_pairs"] == 0
    if integrator == "auto":  # the hybrid ran exact substeps while elastic and the CDM around yielding
        assert result.diagnostics["switches"] > 0
        assert result.diagnostics["exact_substeps"] > 0 and result.diagnostics["cdm_steps"] > 0
    b = result.buildings["iso"]
    y = b.yielding
    peak_iso_ref = np.abs(ref["u"][0]).max()
    peak_drift_ref = np.abs(ref["u"][1] - ref["u"][0]).max()
    # every isolator moves with the slab (no twist): the same peak, along x only
    np.testing.assert_allclose(y.peak[:, 0], y.peak[0, 0], rtol=1e-9)
    assert np.abs(y.peak[:, 1]).max() <= 1e-9 * y.peak[0, 0]
    assert np.abs(b.displacement[:, :, 1:]).max() <= 1e-9 * peak_iso_ref
    err_iso = y.peak[0, 0] / peak_iso_ref - 1
    assert abs(err_iso) < TOL, f"peak isolator displacement {y.peak[0, 0]:.6g} m vs {peak_iso_ref:.6g} m"
    assert y.ductility.max() == pytest.approx(peak_iso_ref / (ref["fy"] / K1), rel=TOL)
    # superstructure drift: storey 2 (storey 1 is the isolation storey, without columns)
    drift = b.interstorey_deflection[:, 1, 0]
    assert np.all(np.isnan(b.interstorey_deflection[:, 0, :]))
    np.testing.assert_allclose(drift, drift[0], rtol=1e-9)
    err_drift = drift[0] / peak_drift_ref - 1
    assert abs(err_drift) < TOL, f"peak drift {drift[0]:.6g} m vs {peak_drift_ref:.6g} m"
    # peak floor displacement
    assert b.peak_displacement[1, 0] == pytest.approx(np.abs(ref["u"][1]).max(), rel=TOL)


def test_histories_against_reference(case):
    _, result, ref = case
    b = result.buildings["iso"]
    t = result.time
    ub = np.interp(t, ref["t"], ref["u"][0])
    u1 = np.interp(t, ref["t"], ref["u"][1])
    peak_iso = np.abs(ref["u"][0]).max()
    peak_drift = np.abs(ref["u"][1] - ref["u"][0]).max()
    assert np.abs(b.displacement[:, 0, 0] - ub).max() < TOL * peak_iso
    assert np.abs(b.displacement[:, 1, 0] - b.displacement[:, 0, 0] - (u1 - ub)).max() < TOL * peak_drift
    # the bearings' deflection and force (the hysteresis loop) at every output sample
    y = b.yielding
    np.testing.assert_allclose(y.deflection[:, :, 0], np.repeat(b.displacement[:, :1, 0], 4, axis=1), rtol=0,
                               atol=1e-12 * peak_iso)  # fmt: skip
    p = np.interp(t, ref["t"], ref["p"])
    force_ref = K1 * ub - ref["kh"] * p
    assert np.abs(y.force[:, 0, 0] - force_ref).max() < TOL * np.abs(force_ref).max()
    # residual deflection at rest: K0·u = (4·k_h·p, 0) gives u_b = u_1 = (1 − α)·p
    np.testing.assert_allclose(y.residual_deflection[:, 0], (1 - ref["alpha"]) * ref["p_final"], rtol=10 * TOL)


def test_energy(case):
    _, result, ref = case
    assert result.balance_error_ratio < 1e-3
    hyst = result.energy_column("hysteretic")
    assert hyst[-1] > 0
    assert np.all(np.diff(hyst) >= 0)
    assert hyst[-1] == pytest.approx(ref["dissipated"], rel=TOL)
    # the loop area: ∫ f dδ along the stored force–deflection histories (trapezoidal, at the
    # output interval) minus what the bearings still store at the end
    y = result.buildings["iso"].yielding
    d, f = y.deflection[:, :, 0], y.force[:, :, 0]
    work = (0.5 * (f[1:] + f[:-1]) * np.diff(d, axis=0)).sum()
    alpha = ref["alpha"]
    kh = ref["kh"]
    f_epp = f[-1] - alpha * K1 * d[-1]
    stored = (0.5 * alpha * K1 * d[-1] ** 2 + f_epp**2 / (2 * kh)).sum()
    area = work - stored
    assert area == pytest.approx(hyst[-1], rel=1e-2)
