"""An independent exact solution of the linear equations of motion, for tests.

M·ü + C·u̇ + K·u = −M·ι·a_g(t) with a_g piecewise linear between record samples is solved in
state space, x = (u, u̇): ẋ = A·x + B·a_g(t). Over a step h in which a_g is linear, the
exact update is read off the matrix exponential of the augmented matrix
[[A·h, B·h, 0], [0, 0, I], [0, 0, 0]] acting on (x, a_k, a_{k+1} − a_k)
(first-order hold). Uses only scipy and the dense
M, K of the assembly, not the solver's kernels.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg


def exact_response(mass, stiffness, damping, influence, ground, ground_dt, substeps, n_samples, velocities=False):
    """Displacements (n_samples, n_dof) at t = k·ground_dt/substeps, exact for linear a_g
    (and the velocities, the same shape, if `velocities`).

    mass (n,), stiffness and damping (n, n), influence (n, 2) maps ground X, Y to DOFs,
    ground (m, 2) m/s² sampled every ground_dt (zero after the last sample).
    """
    n = mass.size
    h = ground_dt / substeps
    minv = 1.0 / mass
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -minv[:, None] * stiffness
    a[n:, n:] = -minv[:, None] * damping
    b = np.zeros((2 * n, 2))
    b[n:, :] = -influence
    aug = np.zeros((2 * n + 4, 2 * n + 4))
    aug[: 2 * n, : 2 * n] = a * h
    aug[: 2 * n, 2 * n : 2 * n + 2] = b * h
    aug[2 * n : 2 * n + 2, 2 * n + 2 :] = np.eye(2)
    e = scipy.linalg.expm(aug)
    phi, g0, g1 = e[: 2 * n, : 2 * n], e[: 2 * n, 2 * n : 2 * n + 2], e[: 2 * n, 2 * n + 2 :]
    t_fine = np.arange(n_samples) * h
    t_rec = np.arange(ground.shape[0]) * ground_dt
    ag = np.column_stack([np.interp(t_fine, t_rec, ground[:, k], right=0.0) for k in range(2)])
    x = np.zeros(2 * n)
    out = np.empty((n_samples, 2 * n))
    out[0] = 0.0
    for k in range(n_samples - 1):
        x = phi @ x + g0 @ ag[k] + g1 @ (ag[k + 1] - ag[k])
        out[k + 1] = x
    return (out[:, :n], out[:, n:]) if velocities else out[:, :n]
