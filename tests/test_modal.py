"""Stiffness, periods and Rayleigh damping against closed forms and hand-built matrices."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from numpy.testing import assert_allclose

from pounding_cli.assembly import assemble
from pounding_cli.assembly.columns import column_local_stiffness
from pounding_cli.errors import InputError

from conftest import load_doc, model_doc, square_building

E = 21e9


def test_column_stiffness_is_12EI_over_h3():
    # deflection along local x bends about local y: I = b_y b_x³ / 12
    kx, ky = column_local_stiffness(E, 1.0, 0.3, 3.0)
    assert_allclose(kx, 12 * E * (0.3 * 1.0**3 / 12) / 27, rtol=1e-15)
    assert_allclose(ky, 12 * E * (1.0 * 0.3**3 / 12) / 27, rtol=1e-15)


def test_one_storey_periods_closed_form():
    """Symmetric one-storey building: ω_x = √(Σk_x/m), ω_y = √(Σk_y/m), ω_θ = √(k_θ/J)."""
    bx, by = 0.35, 0.5  # different stiffness along x and y
    system = assemble(load_doc(model_doc(square_building(section=(bx, by)))))
    b = system.buildings[0]
    m = 64e3
    j = m * (8**2 + 8**2) / 12
    kx, ky = E * by * bx**3 / 27, E * bx * by**3 / 27
    sum_r2 = 3 * (16 + 0 + 16)  # Σ over the 3×3 grid of (x − 4)², and likewise (y − 4)²
    expected = np.sort([np.sqrt(9 * kx / m), np.sqrt(9 * ky / m), np.sqrt((kx + ky) * sum_r2 / j)])
    # a 3×3 symmetric eigenproblem: exact to rounding
    assert_allclose(b.modes.omega, expected, rtol=1e-12)
    assert_allclose(b.mass, [m, m, j], rtol=1e-14)


def _hand_storey(columns, centre):
    """Storey stiffness relative to a mass centre, written out term by term."""
    k = np.zeros((3, 3))
    for x, y, kx, ky in columns:
        ry, rx = y - centre[1], x - centre[0]
        k += [[kx, 0, -kx * ry], [0, ky, ky * rx], [-kx * ry, ky * rx, kx * ry**2 + ky * rx**2]]
    return k


def test_eccentric_three_storey_matches_hand_built_matrices():
    """Storeys with different columns, eccentric mass: K and periods from a hand-built model."""
    building = square_building(storeys=1, eccentricity=(0.4, -0.3))
    grid = building["floors"][0]["column_grid"]
    second = {**building["floors"][0], "column_grid": {**grid, "section": [0.4, 0.3]}}
    third = {
        **building["floors"][0],
        "column_grid": None,
        "columns": [
            {"name": "A", "x": 0, "y": 0, "section": [0.5, 0.5], "material": "concrete"},
            {"name": "B", "x": 8, "y": 0, "section": [0.3, 0.3], "material": "concrete"},
            {"name": "C", "x": 8, "y": 8, "section": [0.3, 0.6], "material": "concrete"},
        ],
    }
    building["floors"] = [building["floors"][0], second, third]
    b = assemble(load_doc(model_doc(building))).buildings[0]

    centre = (4.4, 3.7)
    def grid_cols(bx, by):
        return [(x, y, E * by * bx**3 / 27, E * bx * by**3 / 27) for x in (0, 4, 8) for y in (0, 4, 8)]
    third_cols = [(0, 0, *column_local_stiffness(E, 0.5, 0.5, 3)), (8, 0, *column_local_stiffness(E, 0.3, 0.3, 3)),
                  (8, 8, *column_local_stiffness(E, 0.3, 0.6, 3))]
    k1, k2, k3 = (_hand_storey(c, centre) for c in (grid_cols(0.35, 0.35), grid_cols(0.4, 0.3), third_cols))
    z = np.zeros((3, 3))
    k_hand = np.block([[k1 + k2, -k2, z], [-k2, k2 + k3, -k3], [z, -k3, k3]])
    # same sums in a different order: equal to rounding relative to the largest entry
    assert_allclose(b.stiffness, k_hand, rtol=0, atol=1e-12 * np.abs(k_hand).max())
    m = 64e3
    m_hand = np.tile([m, m, m * 128 / 12], 3)
    omega_hand = np.sqrt(scipy.linalg.eigh(k_hand, np.diag(m_hand), eigvals_only=True))
    assert_allclose(b.modes.omega, omega_hand, rtol=1e-10)
    # eccentricity couples x, y and θ: no mode is purely translational
    assert (b.modes.participation[:, 2] > 1e-6).sum() >= 3


def test_rotated_building_has_rotated_stiffness_and_same_periods():
    base = assemble(load_doc(model_doc(square_building(storeys=2, eccentricity=(0.5, 0.2))))).buildings[0]
    phi = np.radians(30)
    turned = assemble(
        load_doc(model_doc(square_building(storeys=2, eccentricity=(0.5, 0.2), rotation=30, origin=(3, -2))))
    ).buildings[0]
    r = np.eye(6)
    for f in range(2):
        r[3 * f : 3 * f + 2, 3 * f : 3 * f + 2] = [[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]]
    scale = np.abs(base.stiffness).max()
    assert_allclose(turned.stiffness, r @ base.stiffness @ r.T, rtol=0, atol=1e-12 * scale)
    assert_allclose(turned.modes.omega, base.modes.omega, rtol=1e-10)
    # participation is reported in building axes, so it does not change either
    assert_allclose(turned.modes.participation, base.modes.participation, atol=1e-9)


def test_participation_sums_to_one():
    b = assemble(load_doc(model_doc(square_building(storeys=4, eccentricity=(0.4, 0.1))))).buildings[0]
    assert_allclose(b.modes.participation.sum(axis=0), 1.0, rtol=1e-12)


def test_rayleigh_reproduces_both_ratios():
    doc = model_doc(square_building(storeys=4, eccentricity=(0.3, 0.0)))
    doc["buildings"][0]["damping"] = {"ratios": [0.02, 0.07], "modes": [1, 5]}
    b = assemble(load_doc(doc)).buildings[0]
    a0, a1 = b.rayleigh
    c = a0 * np.diag(b.mass) + a1 * b.stiffness
    phi, w = b.modes.shapes, b.modes.omega
    zeta = np.diag(phi.T @ c @ phi) / (2 * w)  # φ are mass-normalised
    assert_allclose(zeta[[0, 4]], [0.02, 0.07], rtol=1e-10)


def test_equal_frequency_modes_are_refused_with_a_reason():
    doc = model_doc(square_building(storeys=2))
    doc["buildings"][0]["damping"] = {"modes": [1, 2]}
    with pytest.raises(InputError, match=r"buildings\[0\]\.damping\.modes: modes 1 and 2 have the same frequency"):
        assemble(load_doc(doc))


def test_paper_left_building_periods(example):
    """The paper's left building (4 storeys, 9 columns 35×35 cm, 64 t floors): the shear-beam
    closed form ω_k = 2√(k/m)·sin((2k−1)π/(2(2N+1))) for the x and y modes."""
    b = assemble(load_doc(example)).buildings[0]
    k = 9 * E * 0.35**4 / 27
    w = [2 * np.sqrt(k / 64e3) * np.sin((2 * i - 1) * np.pi / 18) for i in (1, 2)]
    assert_allclose(b.modes.periods[[0, 1, 3, 4]], np.repeat(2 * np.pi / np.array(w), 2), rtol=1e-10)
