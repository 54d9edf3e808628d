"""The CDM solver against an exact solution, energy conservation, and the excitation angle."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pounding_cli as pound
from pounding_cli.assembly import assemble, ground_motion
from pounding_cli.solver import simulate

from conftest import load_doc, model_doc, square_building
from exact import exact_response


def _eccentric_case(integrator="auto"):
    """A 4-storey building, eccentric, rotated in plan, irregular in height, under both
    components at θ = 35°."""
    building = square_building(storeys=2, eccentricity=(0.4, -0.3), rotation=20.0, origin=(5.0, 3.0))
    upper = {**building["floors"][0], "repeat": 2, "height": 3.5, "eccentricity": [-0.2, 0.5]}
    upper["column_grid"] = {**upper["column_grid"], "section": [0.3, 0.4], "angle": 15.0}
    building["floors"].append(upper)
    return load_doc(model_doc(building, angle=35.0, integrator=integrator))


def _exact_peaks(building, ground, substeps):
    a0, a1 = building.rayleigh
    damping = a0 * np.diag(building.mass) + a1 * building.stiffness
    influence = np.zeros((building.mass.size, 2))
    influence[0::3, 0] = 1.0
    influence[1::3, 1] = 1.0
    n = (ground.acceleration.shape[0] - 1) * substeps + 1
    u = exact_response(building.mass, building.stiffness, damping, influence, ground.acceleration, ground.dt, substeps, n)
    c, s = np.cos(building.rotation), np.sin(building.rotation)
    peaks = np.full((len(building.column_lines), building.n_floors, 3), np.nan)
    for col in building.columns:
        q = col.storey
        top, bottom = u[:, 3 * q : 3 * q + 3], (u[:, 3 * q - 3 : 3 * q] if q > 0 else np.zeros((n, 3)))
        d = top[:, :2] + top[:, 2:] * [-col.arm_top[1], col.arm_top[0]]
        d -= bottom[:, :2] + bottom[:, 2:] * [-col.arm_bottom[1], col.arm_bottom[0]]
        local = np.column_stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]])
        peaks[col.line, q, :2] = np.abs(local).max(axis=0)
        peaks[col.line, q, 2] = np.abs(top[:, 2] - bottom[:, 2]).max()
    return peaks, u


@pytest.mark.parametrize("integrator", ["hybrid", "cdm"])
def test_peaks_match_exact_solution_at_default_dt(integrator):
    """Peak interstorey deflections of every column and storey within 0.1 % of the exact
    (matrix-exponential) solution. The exact peaks are sampled every 0.5 ms: their own
    sampling error is below 1e-5 for the 0.5 s fundamental period."""
    loaded = _eccentric_case(integrator)
    result = pound.run_model(loaded)
    building = assemble(loaded).buildings[0]
    exact, _ = _exact_peaks(building, ground_motion(loaded), substeps=20)
    got = result.buildings["b"].interstorey_deflection
    assert np.isnan(got).sum() == np.isnan(exact).sum() == 0
    for k, name in enumerate(("x", "y", "θ")):
        scale = exact[:, :, k].max()
        significant = exact[:, :, k] > 1e-3 * scale
        rel = np.abs(got[:, :, k] - exact[:, :, k])[significant] / exact[:, :, k][significant]
        assert rel.max() < 1e-3, f"{name}: worst relative peak error {rel.max():.2e}"


@pytest.mark.slow
def test_cdm_converges_at_second_order():
    """Error of the displacement history against the exact solution falls as Δt²: the fitted
    log-log slope lies within 0.1 of 2 (the central difference method is second order)."""
    loaded = _eccentric_case()
    system = assemble(loaded)
    ground = ground_motion(loaded)
    building = system.buildings[0]
    _, u_exact = _exact_peaks(building, ground, substeps=4)  # samples every 2.5 ms
    n_out = 1001  # the first 10 s, every 10 ms
    reference = u_exact[: 4 * (n_out - 1) + 1 : 4]
    steps, errors = [], []
    for per_output in (8, 16, 32, 64):
        dt = 0.01 / per_output
        r = simulate(system, ground.acceleration, ground.dt, dt, per_output, per_output * (n_out - 1))
        errors.append(np.abs(r.displacement - reference).max())
        steps.append(dt)
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert abs(slope - 2.0) < 0.1, f"slope {slope:.3f}, errors {errors}"


@pytest.mark.parametrize("integrator", ["hybrid", "cdm"])
def test_energy_balance_at_default_dt(integrator):
    """input = kinetic + strain + damping within 0.5 % of the input energy; kinetic and strain
    columns equal ½vᵀMv and ½uᵀKu recomputed from the stored histories."""
    loaded = _eccentric_case(integrator)
    result = pound.run_model(loaded)
    e = {name: result.energy_column(name) for name in pound.results.ENERGY_NAMES}
    e_in = np.abs(e["input"]).max()
    assert e_in > 0
    assert np.abs(e["input"] - e["kinetic"] - e["strain"] - e["damping"]).max() < 5e-3 * e_in
    assert_allclose(e["balance_error"], e["input"] - e["kinetic"] - e["strain"] - e["damping"], atol=1e-9 * e_in)
    building = assemble(loaded).buildings[0]
    b = result.buildings["b"]
    u = b.displacement.reshape(len(result.time), -1)
    v = b.velocity.reshape(len(result.time), -1)
    assert_allclose(e["strain"], 0.5 * np.einsum("ti,ij,tj->t", u, building.stiffness, u), rtol=1e-9, atol=1e-12 * e_in)
    assert_allclose(e["kinetic"], 0.5 * (v * v * building.mass).sum(axis=1), rtol=1e-12, atol=1e-12 * e_in)
    assert np.all(np.diff(e["damping"]) >= -1e-12 * e_in), "damping energy must never decrease"


def _single_component(angle, component, trace="HNE"):
    doc = model_doc(square_building(storeys=3), angle=angle, components=[component])
    doc["excitation"]["record"][component]["trace"] = trace
    return pound.run_model(load_doc(doc)).buildings["b"]


def test_angle_90_with_L_equals_angle_0_with_T():
    """θ = 90° with the record on L shakes along Y exactly as θ = 0° with it on T (eq. 2)."""
    a = _single_component(90.0, "L")
    b = _single_component(0.0, "T")
    scale = np.abs(b.displacement).max()
    # cos 90° is 6e-17 in floating point: the X response of (a) is of that relative order
    assert_allclose(a.displacement, b.displacement, rtol=0, atol=1e-12 * scale)
    assert_allclose(a.interstorey_deflection, b.interstorey_deflection, rtol=1e-10, atol=1e-12 * scale)


def test_square_symmetric_building_turns_with_the_excitation():
    """A square, symmetric building shaken at θ = 90° moves along Y as it moves along X at θ = 0°."""
    a = _single_component(0.0, "L")
    b = _single_component(90.0, "L")
    scale = np.abs(a.displacement).max()
    assert_allclose(b.displacement[:, :, 1], a.displacement[:, :, 0], rtol=0, atol=1e-10 * scale)
    assert_allclose(b.interstorey_deflection[:, :, 1], a.interstorey_deflection[:, :, 0], rtol=1e-9)
    assert np.abs(a.displacement[:, :, 2]).max() < 1e-12 * scale, "no torsion in a symmetric building"
