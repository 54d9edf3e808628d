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


def _hand_column(kxx, kyy, kxy, r_bot, r_top):
    """6×6 stiffness of one column between two floors, DOFs (u_x, u_y, θ) of the floor below
    then of the floor above, each at its own mass centre; r_bot, r_top: the column's plan
    offsets from those centres (None: the ground). Written from the deflection:
    δ_x = (u_x,top − θ_top·r_y,top) − (u_x,bot − θ_bot·r_y,bot),
    δ_y = (u_y,top + θ_top·r_x,top) − (u_y,bot + θ_bot·r_x,bot), energy ½(k_xx δ_x² + 2k_xy δ_x δ_y + k_yy δ_y²),
    so K = k_xx·a·aᵀ + k_xy·(a·bᵀ + b·aᵀ) + k_yy·b·bᵀ with a, b the coefficients of δ_x, δ_y."""
    (rxb, ryb), (rxt, ryt) = r_bot if r_bot is not None else (0.0, 0.0), r_top
    a = np.array([-1.0, 0.0, ryb, 1.0, 0.0, -ryt])
    b = np.array([0.0, -1.0, -rxb, 0.0, 1.0, rxt])
    if r_bot is None:
        a[:3] = b[:3] = 0.0
    return kxx * np.outer(a, a) + kxy * (np.outer(a, b) + np.outer(b, a)) + kyy * np.outer(b, b)


def test_setback_with_eccentricity_per_floor_matches_hand_built_matrices():
    """Three floors that differ in slab (12 × 8 m, a setback 8 × 8 m, a right triangle
    8 × 6 m), in mass (per area, given, per area) and in eccentricity, with one column turned
    30° in plan: M (masses from the slab areas, J = m(a² + b²)/12 for the rectangles,
    m(a² + b²)/18 for the triangle) and K (each column linking two different mass centres)
    built by hand; periods by scipy.linalg.eigh of the hand-built matrices. Tolerances as for
    the uniform building: K to 1e-12 of its largest entry (same sums, other order), masses to
    1e-14, ω to 1e-10."""
    col = {"material": "concrete"}
    floors = [
        {"height": 3.5, "slab": [[0, 0], [12, 0], [12, 8], [0, 8]], "mass_per_area": 1000.0,
         "eccentricity": [0.5, -0.2],
         "column_grid": {"x": [0, 6, 12], "y": [0, 4, 8], "section": [0.4, 0.4], **col}},
        {"height": 3.0, "slab": [[0, 0], [8, 0], [8, 8], [0, 8]], "mass": 50e3, "eccentricity": [-0.3, 0.6],
         "columns": [{"name": n, "x": x, "y": y, "section": [0.35, 0.5], **col}
                     for n, x, y in (("A", 0, 0), ("B", 8, 0), ("C", 8, 8), ("D", 0, 8))]
                    + [{"name": "R", "x": 4, "y": 4, "section": [0.6, 0.3], "angle": 30.0, **col}]},
        {"height": 2.8, "slab": [[0, 0], [8, 0], [0, 6]], "mass_per_area": 800.0, "eccentricity": [0.4, 0.3],
         "columns": [{"name": n, "x": x, "y": y, "section": [0.3, 0.3], **col}
                     for n, x, y in (("A", 0, 0), ("B", 8, 0), ("F", 0, 6), ("E", 2, 2))]},
    ]  # fmt: skip
    building = {"name": "setback", "floors": floors}
    b = assemble(load_doc(model_doc(building))).buildings[0]

    # M by hand: slab area × mass per area or the given mass; J of a uniform slab
    m1, m2, m3 = 1000.0 * 12 * 8, 50e3, 800.0 * 8 * 6 / 2
    j1, j2, j3 = m1 * (12**2 + 8**2) / 12, m2 * (8**2 + 8**2) / 12, m3 * (8**2 + 6**2) / 18
    m_hand = np.array([m1, m1, j1, m2, m2, j2, m3, m3, j3])
    assert_allclose(b.mass, m_hand, rtol=1e-14)
    # mass centres: slab centroid + eccentricity (the triangle's centroid is (8/3, 2))
    c1, c2, c3 = (6.5, 3.8), (3.7, 4.6), (8 / 3 + 0.4, 2.3)
    assert_allclose(b.mass_centre, [c1, c2, c3], rtol=1e-14)

    def k_local(bx, by, h):  # 12EI/h³ per local axis
        return E * by * bx**3 / h**3, E * bx * by**3 / h**3

    def arm(p, c):
        return (p[0] - c[0], p[1] - c[1])

    k_hand = np.zeros((9, 9))
    kx, ky = k_local(0.4, 0.4, 3.5)
    for x in (0, 6, 12):
        for y in (0, 4, 8):
            k_hand[0:3, 0:3] += _hand_column(kx, ky, 0.0, None, arm((x, y), c1))[3:, 3:]
    kx, ky = k_local(0.35, 0.5, 3.0)
    for p in ((0, 0), (8, 0), (8, 8), (0, 8)):
        k_hand[0:6, 0:6] += _hand_column(kx, ky, 0.0, arm(p, c1), arm(p, c2))
    kx, ky = k_local(0.6, 0.3, 3.0)  # turned 30°: k_xx = k_x c² + k_y s², k_xy = (k_x − k_y) c s
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    k_hand[0:6, 0:6] += _hand_column(kx * c * c + ky * s * s, kx * s * s + ky * c * c, (kx - ky) * c * s,
                                     arm((4, 4), c1), arm((4, 4), c2))  # fmt: skip
    kx, ky = k_local(0.3, 0.3, 2.8)
    for p in ((0, 0), (8, 0), (0, 6), (2, 2)):
        k_hand[3:9, 3:9] += _hand_column(kx, ky, 0.0, arm(p, c2), arm(p, c3))
    assert_allclose(b.stiffness, k_hand, rtol=0, atol=1e-12 * np.abs(k_hand).max())
    omega_hand = np.sqrt(scipy.linalg.eigh(k_hand, np.diag(m_hand), eigvals_only=True))
    assert_allclose(b.modes.omega, omega_hand, rtol=1e-10)
    # the floors' different mass centres couple every mode: none is a pure translation
    assert (b.modes.participation[:, 2] > 1e-6).all()


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


def test_paper_left_building_torsional_periods(example):
    """The left building twists as a uniform shear beam of its own: per storey
    k_θ = Σ k_c·(r_x² + r_y²) = 192·k_c over the 3×3 grid at 4 m (Σ r_x² = Σ r_y² = 96 m²),
    J = m(a² + b²)/12 per floor, so ω_θ,j = 2√(k_θ/J)·sin((2j − 1)π/18) (modes 3 and 6), with
    the effective modal mass ratio (Σ φ_i)²/(N·Σ φ_i²), φ_i = sin(iπ/9) of mode 3 — a 12 × 12
    eigenproblem, so to 1e-10."""
    b = assemble(load_doc(example)).buildings[0]
    k_c = E * 0.35**4 / 27
    j = 64e3 * (8**2 + 8**2) / 12
    w = [2 * np.sqrt(192 * k_c / j) * np.sin((2 * i - 1) * np.pi / 18) for i in (1, 2)]
    assert_allclose(b.modes.periods[[2, 5]], 2 * np.pi / np.array(w), rtol=1e-10)
    assert_allclose(b.modes.periods[2], 0.3158, atol=5e-5)  # the figure the docs quote
    phi = np.sin(np.arange(1, 5) * np.pi / 9)
    assert_allclose(b.modes.participation[2], [0, 0, phi.sum() ** 2 / (4 * (phi**2).sum())], atol=1e-10)


def test_paper_left_building_periods(example):
    """The paper's left building (4 storeys, 9 columns 35×35 cm, 64 t floors): the shear-beam
    closed form ω_k = 2√(k/m)·sin((2k−1)π/(2(2N+1))) for the x and y modes."""
    b = assemble(load_doc(example)).buildings[0]
    k = 9 * E * 0.35**4 / 27
    w = [2 * np.sqrt(k / 64e3) * np.sin((2 * i - 1) * np.pi / 18) for i in (1, 2)]
    assert_allclose(b.modes.periods[[0, 1, 3, 4]], np.repeat(2 * np.pi / np.array(w), 2), rtol=1e-10)
