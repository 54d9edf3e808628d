"""The equilibrium check of the storey shears (docs/validation.md, "Forces").

The equation of motion of floor j, M·a_abs + C·v + (K·u − g) − F_contact = 0, summed over the
floors above storey s: the storeys between them cancel (each pushes its two floors equally
and oppositely, its torques balanced about any one point), and what is left of K·u − g is
storey s's own shear on the floor above it. So at every stored sample

    V_s + Σ_{j ≥ s} (M·a_abs + C·v − F_contact)_j = 0

in global components with the torques about the global origin (a floor's own torque about
its mass centre G plus G × its force). Everything in it is stored (accelerations, velocities,
the floors' contact forces, the storey shears) but C, which the assembly gives.
"""

from __future__ import annotations

import numpy as np


def about_origin(force: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Floor forces (…, n_floors, 3) as F_X, F_Y and the torque about each floor's mass centre
    `centre` (n_floors, 2) to F_X, F_Y and the torque about the global origin."""
    out = force.copy()
    out[..., 2] += centre[:, 0] * force[..., 1] - centre[:, 1] * force[..., 0]
    return out


def storey_residuals(b, damping: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """(residual (nt, n_storeys, 3), scale (n_storeys, 3)) of building result `b` with its dense
    damping matrix C (3N × 3N, BuildingArrays.damping): V_s + Σ above of M·a + C·v − F_contact,
    and the largest Σ above of |M·a| + |M·a + C·v − F_contact| over the run, per component."""
    nt, n = b.acceleration.shape[:2]
    m = np.column_stack([b.floor_mass[:, 0], b.floor_mass])  # m, m, J per floor
    inertia = about_origin(m * b.acceleration, b.mass_centre)
    cv = (damping @ b.velocity.reshape(nt, -1).T).T.reshape(nt, n, 3)
    net = about_origin(m * b.acceleration + cv - np.asarray(b.forces.floor_contact), b.mass_centre)
    above = np.cumsum(net[:, ::-1], axis=1)[:, ::-1]  # Σ over the floors j ≥ s
    size = np.cumsum((np.abs(net) + np.abs(inertia))[:, ::-1], axis=1)[:, ::-1].max(axis=0)
    return b.forces.storey_shear[:, :, 3:] + above, size


def worst_residual(result, system) -> dict[str, np.ndarray]:  # type: ignore[no-untyped-def]
    """Per building of `result` (assembled as `system`): the largest |residual| / scale over the
    run of each storey and component (n_storeys, 3)."""
    out = {}
    for bld in system.buildings:
        residual, size = storey_residuals(result.buildings[bld.name], bld.damping)
        out[bld.name] = np.abs(residual).max(axis=0) / size
    return out
