"""Free rigid slabs (no columns, no damping) for contact tests at the solver level.

Builds the plain arrays the solver takes, without the model files: a "structure" of N
floors with zero storey stiffness (each floor a free body in plan) and a contact set of
those floors plus fixed obstacles. Ground acceleration acts on every floor as the uniform
body force −m·a_g.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pounding_cli.assembly.polygon import polar_moment_about_centroid, polygon_area, polygon_centroid


def square(size: float, centre=(0.0, 0.0), angle_deg: float = 0.0) -> np.ndarray:
    """A size × size square, counter-clockwise, turned by angle_deg about its centre."""
    h = size / 2
    pts = np.array([(-h, -h), (h, -h), (h, h), (-h, h)])
    a = np.radians(angle_deg)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return pts @ rot.T + np.asarray(centre, dtype=float)


def free_slabs(slabs, density=1000.0, obstacles=(), k_n=1e9, k_t=1e8, mu_s=0.0, mu_k=0.0, c_n=0.0, zeta=0.0, c_t=0.0):
    """(structure, contact) for free slabs of areal density kg/m² against each other (every
    pair) and against every obstacle."""
    n = len(slabs)
    mass, centre = [], []
    for p in slabs:
        area = polygon_area(p)
        m = density * area
        mass += [m, m, density * polar_moment_about_centroid(p)]
        centre.append(polygon_centroid(p))
    structure = SimpleNamespace(
        mass=np.array(mass),
        dof_a0=np.zeros(3 * n),
        dof_a1=np.zeros(3 * n),
        floor_start=np.array([0, n], dtype=np.int64),
        floor_centre=np.array(centre),
        storey_k=np.zeros((n, 6, 6)),
        storey_bottom=np.full(n, -1, dtype=np.int64),
        storey_top=np.arange(n, dtype=np.int64),
        storey_axes=np.tile([1.0, 0.0], (n, 1)),
        column_storey=np.zeros(0, dtype=np.int64),
        column_plan=np.zeros((0, 2)),
    )
    bodies = list(slabs) + list(obstacles)
    nv = max(len(p) for p in bodies)
    poly = np.zeros((len(bodies), nv, 2))
    for k, p in enumerate(bodies):
        poly[k, : len(p)] = p
    centres = np.array(centre + [polygon_centroid(p) for p in obstacles]).reshape(-1, 2)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)] + [
        (i, n + o) for i in range(n) for o in range(len(obstacles))
    ]
    masses = np.array(mass[0::3] + [np.inf] * len(obstacles))
    meff = [masses[i] if not np.isfinite(masses[j]) else masses[i] * masses[j] / (masses[i] + masses[j]) for i, j in pairs]
    m = len(pairs)
    contact = SimpleNamespace(
        body_poly=poly,
        body_nv=np.array([len(p) for p in bodies], dtype=np.int64),
        body_floor=np.array(list(range(n)) + [-1] * len(obstacles), dtype=np.int64),
        body_centre=centres,
        body_radius=np.array([np.max(np.hypot(*(p - c).T)) for p, c in zip(bodies, centres)]),
        pair_a=np.array([p[0] for p in pairs], dtype=np.int64),
        pair_b=np.array([p[1] for p in pairs], dtype=np.int64),
        pair_kn=np.full(m, float(k_n)),
        pair_kt=np.full(m, float(k_t)),
        pair_mu_s=np.full(m, float(mu_s)),
        pair_mu_k=np.full(m, float(mu_k)),
        pair_cn=np.full(m, float(c_n)),
        pair_zeta=np.full(m, float(zeta)),
        pair_ct=np.full(m, float(c_t)),
        pair_meff=np.array(meff, dtype=float),
    )
    return structure, contact


def momenta(structure, displacement: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """(p_x, p_y, L_z about the origin) of every sample: Σ m·v and Σ (J·ω + m·G × v)."""
    m = structure.mass[0::3]
    j = structure.mass[2::3]
    g = structure.floor_centre[None, :, :] + displacement[:, :, :2]
    v = velocity
    px = (m * v[:, :, 0]).sum(axis=1)
    py = (m * v[:, :, 1]).sum(axis=1)
    lz = (j * v[:, :, 2] + m * (g[:, :, 0] * v[:, :, 1] - g[:, :, 1] * v[:, :, 0])).sum(axis=1)
    return np.column_stack([px, py, lz])


def contact_force(structure, contact, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The solver's contact kernel at one configuration q (n_dof,) of the free slabs, at rest:
    (generalized forces on the slabs (n_dof,): F_x, F_y and the moment about each displaced
    mass centre, N and N·m; per-pair values (n_pairs, 6) as layout.NOW_COLUMNS). A fresh
    contact state each call, velocities zero: no dashpot force and no friction increment,
    only the normal law F_N = k_N·A_c at the overlap's centroid (a vanishing step, 1e-12 s:
    the midpoint rule's corrections where points touch or part scale with the step)."""
    from pounding_cli.solver import contact as kernel
    from pounding_cli.solver.integrate import contact_state

    n_dof = structure.mass.size
    u = np.zeros(n_dof + 3)
    u[:n_dof] = q
    still = np.zeros(n_dof + 3)
    state = contact_state(contact, n_dof, sweep=False)
    kernel.contact_forces(0, 1e-12, u, still, still, state)
    forces, now = state.force, state.now
    return forces[:n_dof], now
