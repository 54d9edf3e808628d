"""Is the overlap-area impact law conservative? The work of the contact kernel's forces
around closed paths, and what the spinning corner impact does with its kinetic energy.

The generalized forces Q(q) on two free slabs (F_x, F_y and the moment about the mass centre
of each; q = x, y, θ of each) come from the solver's own contact kernel at fixed
configurations, at rest (free_bodies.contact_force): F = k_N·A_c·n at the overlap's centroid
c, moment (c − G) × F about the displaced mass centre G, with the outlines moved rigidly,
P ↦ G + u + R(θ)·(P − G). Q derives from a potential — the contact stores and gives back
energy — if and only if it does no work around any closed path, that is if its Jacobian
∂Q/∂q is symmetric (no curl). TurnedExactly below is an independent implementation of the
same law (numpy rotation, the geometry kernel's clipping called directly). docs/theory.md §10
draws on these facts:

* a corner pushed into a face, or a face into a wider one: no curl, rotations included, at
  any turn of the slabs (the overlap's centroid is the work-conjugate action point of a turn);
  the kernel moved its outlines by the small-rotation map P + θ·ẑ × (P − G) until it was
  found to give these contacts a curl in proportion to θ;
* two corners in each other (turned corners, or faces pressed together along part of their
  length): k_N·A_c·n has a curl even under translations, at any θ: there the law itself is
  not conservative;
* the free spinning corner impact of tests/test_contact.py leaves with the kinetic energy it
  brought; along its path the kernel's forces do no net work.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import shapely.affinity
from numpy.testing import assert_allclose

from pounding_cli.solver import contact as kernel
from pounding_cli.solver.contact_geometry import AREA, CX, CY, DEPTH, NX, NY, RESULT_SIZE, clip_rows, overlap_frame

from free_bodies import contact_force, free_slabs, square

K_N = 1e9  # N/m²
H = 1e-6  # m, rad: finite-difference step


def _scene(b, depth=0.01):
    """(structure, contact, q): A a 4 m square at the origin, slab b moved in x until its
    leftmost vertex is `depth` m inside A's right face (x = 2)."""
    structure, contact = free_slabs([square(4.0, (0.0, 0.0)), b], k_n=K_N)
    q = np.zeros(6)
    q[3] = 2.0 - depth - b[:, 0].min()
    return structure, contact, q


def _corner_into_face():
    """B, a 4 m square turned 30°, pokes one corner 1 cm into the middle of A's right face."""
    b = square(4.0, (0.0, 0.0), angle_deg=30.0)
    return _scene(b - (0.0, b[np.argmin(b[:, 0]), 1]))


def _narrow_face():
    """B, a 3 m square, pressed 1 cm into A's right face, its whole left face within A's (the
    overlap a 1 cm × 3 m strip ending at B's corners)."""
    return _scene(square(3.0, (0.0, 0.3)))


def _faces_offset():
    """B, a 3 m square, pressed 1 cm into A's right face and 1.7 m off A's centre line: the
    faces overlap along 1.8 m only, A's upper right corner lies in B and B's lower left corner
    in A (the overlap a strip whose crossings are two of its opposite corners)."""
    return _scene(square(3.0, (0.0, 1.7)))


def _corners_in_each_other():
    """B, a 3 m square turned 10°, near A's upper right corner: B's lower left corner lies
    inside A and A's upper right corner inside B."""
    structure, contact = free_slabs([square(4.0, (0.0, 0.0)), square(3.0, (3.1, 3.6), angle_deg=10.0)], k_n=K_N)
    return structure, contact, np.zeros(6)


class TurnedExactly:
    """The kernel's law — F = k_N·A_c·n at the overlap's centroid c (contact_geometry), moment
    (c − G) × F — on outlines turned exactly, P ↦ G + u + R(θ)·(P − G), instead of by the
    small-rotation map: a rigid motion, whose virtual displacement at c is δθ·ẑ × (c − G)."""

    def __init__(self, structure, contact):
        self.poly = contact.body_poly
        self.centre = structure.floor_centre
        rows = clip_rows(4, 4)
        self.buffers = (np.zeros((rows, 2)), np.zeros(rows, np.int64), np.zeros((rows, 2)), np.zeros(rows, np.int64))
        self.frame = np.zeros(RESULT_SIZE)

    def _place(self, k, q):
        ux, uy, th = q[3 * k : 3 * k + 3]
        turn = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        g = self.centre[k] + (ux, uy)
        return np.ascontiguousarray(g + (self.poly[k] - self.centre[k]) @ turn.T), g

    def __call__(self, q):
        (pa, ga), (pb, gb) = self._place(0, q), self._place(1, q)
        r = self.frame
        out = np.zeros(6)
        if overlap_frame(pa, 4, pb, 4, ga, gb, *self.buffers, r):
            f = K_N * r[AREA] * r[NX : NY + 1]
            for sign, g, k in ((-1.0, ga, 0), (1.0, gb, 3)):
                arm = r[CX : CY + 1] - g
                out[k : k + 3] = sign * np.array([f[0], f[1], arm[0] * f[1] - arm[1] * f[0]])
        return out

    def depth(self, q):
        """The overlap's extent along n, m (0 without overlap)."""
        self(q)
        return self.frame[DEPTH]


def _kernel(structure, contact):
    return lambda q: contact_force(structure, contact, q)[0]


def _curl(forces, q):
    """Largest |∂Q_i/∂q_j − ∂Q_j/∂q_i| relative to the largest |∂Q_i/∂q_j| (central
    differences; m and rad alike, the slabs being metres across), and the Jacobian."""
    jac = np.zeros((6, 6))
    for j in range(6):
        e = np.zeros(6)
        e[j] = H
        jac[:, j] = (forces(q + e) - forces(q - e)) / (2 * H)
    return np.abs(jac - jac.T).max() / np.abs(jac).max(), jac


def _loop_work(forces, q0, i, j, size, points=64):
    """(work of Q around the square q0 → +size·e_i → +size·e_j → back, the largest work along
    one of its sides), J; Gauss–Legendre on each side."""
    x, w = np.polynomial.legendre.leggauss(points)
    corners = [np.zeros(6) for _ in range(4)]
    corners[1][i] = corners[2][i] = corners[2][j] = corners[3][j] = size
    total, side_max = 0.0, 0.0
    for c0, c1 in zip(corners, corners[1:] + corners[:1]):
        d = c1 - c0
        side = sum(wk / 2 * forces(q0 + c0 + d * (xk + 1) / 2) @ d for xk, wk in zip(x, w))
        total += side
        side_max = max(side_max, abs(side))
    return total, side_max


def _press(depth_at, q, depth):
    """Move B along x until the overlap is `depth` m deep (along its normal; depth_at(q) is 0
    without overlap), in place."""
    for _ in range(50):
        miss = depth - depth_at(q)
        if abs(miss) < 1e-12:
            return
        q[3] -= miss
    raise AssertionError("could not press B in")


@pytest.mark.parametrize("scene", [_corner_into_face, _narrow_face], ids=["corner into face", "face within a face"])
def test_no_curl_at_rest_orientation(scene):
    """A corner into a face, or a face pressed into a wider one, slabs not turned: ∂Q/∂q is
    symmetric over all six coordinates, rotations included (to 1e-8; measured 2e-10: central
    differences of a field quadratic in q over a step of 1 µm), and a square loop of 4 mm in
    (x_B, y_B) does no work (1e-9 of the work along one side). At θ = 0 both maps of the
    outlines agree, and so do the kernel and TurnedExactly (1e-12)."""
    structure, contact, q = scene()
    forces = _kernel(structure, contact)
    assert contact_force(structure, contact, q)[1][0, kernel.NOW_AREA] > 0
    assert _curl(forces, q)[0] < 1e-8
    work, side = _loop_work(forces, q - [0, 0, 0, 0.002, 0.002, 0], 3, 4, 0.004)
    assert abs(work) < 1e-9 * side
    assert_allclose(TurnedExactly(structure, contact)(q), forces(q), rtol=1e-12, atol=1e-12 * np.abs(forces(q)).max())


def test_turned_outlines_keep_the_law_conservative():
    """The corner into a face with A turned by θ and B by −θ (the corner kept 1 cm deep): the
    kernel's Q has no curl at θ = 0.01, 0.02 and 0.1 rad (1e-8; the small-rotation map the
    kernel used before gave 0.027, 0.054 and 0.21), and equals the independent TurnedExactly
    to 1e-12."""
    structure, contact, q0 = _corner_into_face()
    exact = TurnedExactly(structure, contact)
    forces = _kernel(structure, contact)
    for theta in (0.01, 0.02, 0.1):
        q = q0.copy()
        q[2], q[5] = theta, -theta
        _press(lambda x: contact_force(structure, contact, x)[1][0, kernel.NOW_DEPTH], q, 0.01)
        assert _curl(forces, q)[0] < 1e-8, theta
        assert_allclose(forces(q), exact(q), rtol=1e-12, atol=1e-12 * np.abs(exact(q)).max())


@pytest.mark.parametrize("scene", [_corners_in_each_other, _faces_offset], ids=["turned corners", "faces offset"])
def test_corners_in_each_other_do_work_under_translation(scene):
    """A corner of B inside A and one of A inside B (two turned corners, or two faces pressed
    together along part of their length): k_N·A_c·n has a curl in (x_B, y_B), so moving B round
    a 4 mm square, without turning anything, does net work: more than 1e-4 of the work along
    one side (measured 2e-4 and 2e-3), and the curl at the square's centre times its area to
    1e-3 (Stokes; the curl varies across the square by less than that, so the work is the
    field's, not the quadrature's)."""
    structure, contact, q = scene()
    a, b = (shapely.Polygon(contact.body_poly[k]) for k in (0, 1))
    b = shapely.affinity.translate(b, q[3], q[4])
    assert any(b.contains(shapely.Point(p)) for p in contact.body_poly[0])
    assert any(a.contains(shapely.Point(p)) for p in np.asarray(b.exterior.coords))
    forces = _kernel(structure, contact)
    size = 0.004
    _, jac = _curl(forces, q + [0, 0, 0, size / 2, size / 2, 0])
    work, side = _loop_work(forces, q, 3, 4, size)
    assert abs(work) > 1e-4 * side
    assert_allclose(work, (jac[4, 3] - jac[3, 4]) * size**2, rtol=1e-3)


def test_spinning_corner_impact_does_no_net_work():
    """The free spinning corner impact of tests/test_contact.py (frictionless, no dashpot,
    the slabs turning by up to 0.03 rad each while in contact): along the run's own path q_n
    the work Σ Q(q_n)·(q_{n+1} − q_{n−1})/2 of the kernel's forces, summed as the integrator
    sums it, and that of TurnedExactly, are both below 1e-6 of the kinetic energy (the
    kernel's outlines before: +2.2 %), and the kinetic energy after the impact equals that
    before to 1e-8."""
    from test_contact import _oblique, run

    structure, contact, velocity = _oblique(0.0, 0.0)
    r = run(structure, contact, velocity, duration=0.25, dt=2e-5, stride=1)
    e_k = r.energy[:, 1]
    assert abs(e_k[-1] - e_k[0]) < 1e-8 * e_k[0]
    on = np.flatnonzero(r.contact[:, 0, kernel.NOW_AREA] > 0)
    u = r.displacement
    assert 0.01 < np.abs(u[on][:, [2, 5]]).max() < 0.04
    exact = TurnedExactly(structure, contact)
    path = range(on[0] - 100, on[-1] + 100)
    assert not exact(u[path[0]]).any() and not exact(u[path[-1]]).any()
    work_kernel = sum(contact_force(structure, contact, u[n])[0] @ (u[n + 1] - u[n - 1]) / 2 for n in path)
    work_exact = sum(exact(u[n]) @ (u[n + 1] - u[n - 1]) / 2 for n in path)
    assert abs(work_kernel) < 1e-6 * e_k[0]
    assert abs(work_exact) < 1e-6 * e_k[0]
