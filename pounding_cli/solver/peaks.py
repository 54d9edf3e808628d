"""Running peaks of the response: column deflections, storey twists, floor displacements and
accelerations.

Peaks are taken at every state the integrator reaches (update_peaks). Where it reaches them
by exact propagation the steps are long (ω_max·h up to 0.4) and a peak falling between two
states would be missed by up to 1 − cos(ω·h/2) ≈ (ω·h)²/8 of its size. There the motion
between the states is smooth and both ends carry exact displacements and velocities, so
peaks_between also takes the largest value of the cubic Hermite interpolant of each
deflection, displacement and absolute acceleration over the step: its error is (ω·h)⁴/384
of the amplitude, 4·10⁻⁶ at ω·h = 0.2, 6.7·10⁻⁵ over the hybrid's double substeps (0.4).
"""

from __future__ import annotations

import math

import numpy as np

from .jit import kernel

HERMITE_ARM = 4.0 / 27.0
"""The largest value of the Hermite basis functions s(1 − s)² and s²(1 − s) on [0, 1]: the
cubic through (q₀, q̇₀) and (q₁, q̇₁) over a step h stays within max(|q₀|, |q₁|) +
HERMITE_ARM·h·(|q̇₀| + |q̇₁|), which lets most steps skip the search for its maximum."""


@kernel(inline="always")
def storey_deflection(u, t, b, c, sn, centre):
    """Storey deflection (Ã_x, Ã_y, Δθ) in building axes (cos φ, sin φ) = (c, sn), between
    floor t and floor b (the ground row of u for the first storey), from the floor motion u
    (or from the floor velocities: the map is linear). See update_peaks."""
    ax = u[3 * t] + u[3 * t + 2] * centre[t, 1] - u[3 * b] - u[3 * b + 2] * centre[b, 1]
    ay = u[3 * t + 1] - u[3 * t + 2] * centre[t, 0] - u[3 * b + 1] + u[3 * b + 2] * centre[b, 0]
    return c * ax + sn * ay, c * ay - sn * ax, u[3 * t + 2] - u[3 * b + 2]


@kernel
def update_peaks(u, acc_abs, n_dof, storey_bottom, storey_top, storey_axes, centre,
                 col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc):  # fmt: skip
    """Running maxima at the state u: column deflections in building axes, storey twist,
    floor motion.

    A point P of a floor with mass centre G moves by u + θ·ẑ×(P − G), so a column at P of
    storey s deflects by A + Δθ·ẑ×P with A = (u_t + θ_t·ẑ×(−G_t)) − (u_b + θ_b·ẑ×(−G_b)).
    In building axes (cos φ, sin φ) the deflection is Ã + Δθ·(ξ, η) with
    ξ = −cos φ·P_y + sin φ·P_x and η = sin φ·P_y + cos φ·P_x (col_arm holds ξ, η).
    storey_work (n_storeys, 3) receives Ã_x, Ã_y, Δθ of each storey.
    """
    for s in range(storey_top.size):
        dx, dy, rot = storey_deflection(u, storey_top[s], storey_bottom[s], storey_axes[s, 0], storey_axes[s, 1],
                                        centre)  # fmt: skip
        storey_work[s, 0] = dx
        storey_work[s, 1] = dy
        storey_work[s, 2] = rot
        if abs(rot) > peak_rot[s]:
            peak_rot[s] = abs(rot)
    for k in range(col_storey.size):
        s = col_storey[k]
        lx = abs(storey_work[s, 0] + storey_work[s, 2] * col_arm[k, 0])
        ly = abs(storey_work[s, 1] + storey_work[s, 2] * col_arm[k, 1])
        if lx > peak_col[k, 0]:
            peak_col[k, 0] = lx
        if ly > peak_col[k, 1]:
            peak_col[k, 1] = ly
    for d in range(n_dof):
        if abs(u[d]) > peak_disp[d]:
            peak_disp[d] = abs(u[d])
        if abs(acc_abs[d]) > peak_acc[d]:
            peak_acc[d] = abs(acc_abs[d])


@kernel(inline="always")
def hermite_peak(q0, m0, q1, m1, h, peak):
    """The larger of `peak` and |q| at the stationary points inside (0, h) of the cubic q(τ)
    with q(0) = q0, q̇(0) = m0, q(h) = q1, q̇(h) = m1 (values and rates in the same unit, h
    in s). The ends themselves are update_peaks' business."""
    if max(abs(q0), abs(q1)) + HERMITE_ARM * h * (abs(m0) + abs(m1)) <= peak:
        return peak
    # q(s·h) = q0 + c·s + b·s² + a·s³ on s ∈ [0, 1]
    c = h * m0
    b = 3.0 * (q1 - q0) - h * (2.0 * m0 + m1)
    a = 2.0 * (q0 - q1) + h * (m0 + m1)
    # q' = 3a·s² + 2b·s + c: roots by the cancellation-free quadratic formula
    qa = 3.0 * a
    qb = 2.0 * b
    best = peak
    disc = qb * qb - 4.0 * qa * c
    if disc < 0.0:
        return best
    w = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))
    for k in range(2):
        if k == 0:
            if qa == 0.0:
                continue
            s = w / qa
        else:
            if w == 0.0:
                continue
            s = c / w
        if 0.0 < s < 1.0:
            value = abs(q0 + s * (c + s * (b + s * a)))
            if value > best:
                best = value
    return best


# columns of peaks_between's per-storey array `between`: the previous exact state's storey
# deflections (Ã_x, Ã_y, Δθ) and rates, the storey's largest column arms |ξ|, |η| (m) and a
# lower bound of its columns' running peaks along x, y (m)
BT_VALUE, BT_RATE, BT_ARM, BT_LOWEST = 0, 3, 6, 8
BT_COLUMNS = 10


def between_arrays(col_storey: np.ndarray, col_arm: np.ndarray, n_storeys: int) -> tuple[np.ndarray, np.ndarray]:
    """peaks_between's per-storey array (with the column arms filled in) and the storeys'
    first columns: storey s has columns first[s] … first[s + 1] − 1 (the assembly lists
    columns storey by storey)."""
    if np.any(np.diff(col_storey) < 0):
        raise ValueError("columns must be listed storey by storey")
    between = np.zeros((n_storeys, BT_COLUMNS))
    for axis in range(2):
        np.maximum.at(between[:, BT_ARM + axis], col_storey, np.abs(col_arm[:, axis]))
    first = np.searchsorted(col_storey, np.arange(n_storeys + 1)).astype(np.int64)
    return between, first


@kernel
def peaks_between(h, smooth, u, v, a_abs, jerk, n_dof, storey_bottom, storey_top, storey_axes, centre, col_arm,
                  first, storey_work, kept, between, peak_col, peak_rot, peak_disp, peak_acc):  # fmt: skip
    """After update_peaks at an exact state (u, v) with absolute accelerations a_abs and their
    rates `jerk`: if `smooth`, the step of h s since the previous exact state was itself
    exact, and the running peaks of the column deflections, storey twists, floor displacements
    and absolute floor accelerations rise to the largest values of their cubic Hermite
    interpolants over it; then the state becomes the previous exact state.

    storey_work holds the storey deflections at u (update_peaks has just filled it); kept
    (4, n_dof + 3) the previous state's u, v, a_abs and jerk; between (n_storeys, BT_COLUMNS) what the BT_
    columns say; first the storeys' first columns (between_arrays). A storey's columns are
    looked at only where HERMITE_ARM's bound for the whole storey (its deflection plus its
    largest arm times its twist) passes the lowest of their peaks: most steps of most storeys
    are settled by that one comparison."""
    for s in range(storey_top.size):
        rx, ry, rt = storey_deflection(v, storey_top[s], storey_bottom[s], storey_axes[s, 0], storey_axes[s, 1],
                                       centre)  # fmt: skip
        if smooth:
            peak_rot[s] = hermite_peak(between[s, BT_VALUE + 2], between[s, BT_RATE + 2], storey_work[s, 2], rt, h,
                                       peak_rot[s])  # fmt: skip
            twist = max(abs(between[s, BT_VALUE + 2]), abs(storey_work[s, 2]))
            twist_rate = abs(between[s, BT_RATE + 2]) + abs(rt)
            for axis in range(2):
                r1 = rx if axis == 0 else ry
                arm = between[s, BT_ARM + axis]
                q0 = between[s, BT_VALUE + axis]
                m0 = between[s, BT_RATE + axis]
                q1 = storey_work[s, axis]
                reach = (max(abs(q0), abs(q1)) + arm * twist
                         + HERMITE_ARM * h * (abs(m0) + abs(r1) + arm * twist_rate))  # fmt: skip
                if reach <= between[s, BT_LOWEST + axis]:
                    continue
                lowest = np.inf
                for k in range(first[s], first[s + 1]):
                    a = col_arm[k, axis]
                    peak = hermite_peak(q0 + between[s, BT_VALUE + 2] * a, m0 + between[s, BT_RATE + 2] * a,
                                        q1 + storey_work[s, 2] * a, r1 + rt * a, h, peak_col[k, axis])  # fmt: skip
                    peak_col[k, axis] = peak
                    lowest = min(lowest, peak)
                between[s, BT_LOWEST + axis] = lowest
        for j in range(3):
            between[s, BT_VALUE + j] = storey_work[s, j]
        between[s, BT_RATE] = rx
        between[s, BT_RATE + 1] = ry
        between[s, BT_RATE + 2] = rt
    if smooth:
        for d in range(n_dof):
            peak_disp[d] = hermite_peak(kept[0, d], kept[1, d], u[d], v[d], h, peak_disp[d])
            peak_acc[d] = hermite_peak(kept[2, d], kept[3, d], a_abs[d], jerk[d], h, peak_acc[d])
    for d in range(n_dof):
        kept[0, d] = u[d]
        kept[1, d] = v[d]
        kept[2, d] = a_abs[d]
        kept[3, d] = jerk[d]
