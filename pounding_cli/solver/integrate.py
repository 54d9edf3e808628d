"""Driving the compiled time loop: prepare the step matrices, run in chunks (so progress can
be shown and Ctrl-C honoured between chunks), and collect the response.

The solver takes plain arrays (any object with the attributes of :class:`StructureArrays`);
it never imports pydantic, h5py or obspy.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from . import cdm

DIVERGENCE_LIMIT = 100.0
"""A relative displacement beyond this many metres means the run has diverged."""


class StructureArrays(Protocol):
    """What the solver needs of a structure (see pounding_cli.assembly.system.System)."""

    mass: np.ndarray
    dof_a0: np.ndarray
    storey_k: np.ndarray
    storey_bottom: np.ndarray
    storey_top: np.ndarray
    storey_a1: np.ndarray
    floor_start: np.ndarray
    column_storey: np.ndarray
    column_arm_bottom: np.ndarray
    column_arm_top: np.ndarray
    column_axes: np.ndarray


@dataclass
class Response:
    """What a run produced. Histories are at the output interval, peaks over every step."""

    time: np.ndarray  # (n_out,) s
    displacement: np.ndarray  # (n_out, n_dof) relative to the ground, m / rad
    velocity: np.ndarray  # (n_out, n_dof) relative to the ground, m/s / rad/s
    acceleration: np.ndarray  # (n_out, n_dof) absolute, m/s² / rad/s²
    ground: np.ndarray  # (n_out, 2) ground acceleration X, Y, m/s²
    energy: np.ndarray  # (n_out, 7) J, columns cdm.ENERGY_NAMES
    peak_column: np.ndarray  # (n_columns, 2) peak |Δu| along building x, y, m
    peak_storey_rotation: np.ndarray  # (n_storeys,) peak |Δθ|, rad
    peak_displacement: np.ndarray  # (n_dof,) peak |u|
    peak_acceleration: np.ndarray  # (n_dof,) peak absolute |a|
    dt: float
    steps: int  # steps done
    wall_time: float  # s, time loop only
    status: str  # "complete" or "failed: …"


def step_matrices(structure: StructureArrays, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(B⁻¹ blocks padded to (n_b, n_max, n_max), DOF start, DOF count) with B = M/Δt + C/2."""
    starts = 3 * np.asarray(structure.floor_start[:-1], dtype=np.int64)
    counts = 3 * np.diff(structure.floor_start).astype(np.int64)
    n_max = int(counts.max())
    binv = np.zeros((starts.size, n_max, n_max))
    ones = np.ones(structure.storey_k.shape[0])
    for b, (d0, n) in enumerate(zip(starts, counts)):
        k = _dense_block(structure, d0, n, ones)
        m = structure.mass[d0 : d0 + n]
        a1 = _block_a1(structure, d0)
        c = np.diag(structure.dof_a0[d0 : d0 + n] * m) + a1 * k
        binv[b, :n, :n] = np.linalg.inv(np.diag(m / dt) + c / 2)
    return binv, starts, counts


def _block_a1(structure: StructureArrays, d0: int) -> float:
    """Rayleigh a1 of the building whose DOFs start at d0 (its storeys share one a1)."""
    first_storey = int(np.flatnonzero(structure.storey_top == d0 // 3)[0])
    return float(structure.storey_a1[first_storey])


def _dense_block(structure: StructureArrays, d0: int, n: int, weight: np.ndarray) -> np.ndarray:
    """Dense K of the DOFs d0 … d0+n−1 by applying the storey kernel to unit vectors."""
    total = structure.mass.size
    k = np.empty((n, n))
    x, out = np.zeros(total), np.empty(total)
    for j in range(n):
        x[:] = 0.0
        x[d0 + j] = 1.0
        cdm.storey_matvec(x, structure.storey_k, structure.storey_bottom, structure.storey_top, weight, out)
        k[:, j] = out[d0 : d0 + n]
    return k


def simulate(
    structure: StructureArrays,
    ground: np.ndarray,
    ground_dt: float,
    dt: float,
    stride: int,
    n_steps: int,
    progress: Callable[[int, int], None] | None = None,
    chunk: int = 20_000,
) -> Response:
    """Integrate from rest over n_steps steps of dt; ground is (n, 2) m/s² every ground_dt."""
    n_dof = structure.mass.size
    n_out = n_steps // stride + 1
    binv, starts, counts = step_matrices(structure, dt)
    u = np.zeros(n_dof)
    # v_{-1/2} = v_0 − Δt/2·a_0 with a_0 = −ι·a_g(0) from rest (classical CDM start)
    v_half = np.zeros(n_dof)
    v_half[0::3] = 0.5 * dt * ground[0, 0]
    v_half[1::3] = 0.5 * dt * ground[0, 1]
    acc = np.zeros(4)
    n_col = structure.column_storey.size
    peaks = (np.zeros((n_col, 2)), np.zeros(structure.storey_k.shape[0]), np.zeros(n_dof), np.zeros(n_dof))
    outs = [np.full((n_out, n_dof), np.nan) for _ in range(3)]
    out_ground = np.full((n_out, 2), np.nan)
    out_energy = np.full((n_out, 7), np.nan)
    work = [np.zeros(n_dof) for _ in range(6)]
    chunk = max(stride, chunk - chunk % stride)
    status, done = cdm.STATUS_OK, 0
    wall = 0.0
    try:
        while done <= n_steps and status == cdm.STATUS_OK:
            stop = min(done + chunk, n_steps + 1)
            t0 = time.perf_counter()
            status, done = cdm.advance(
                done, stop, dt, stride, DIVERGENCE_LIMIT,
                structure.mass, structure.dof_a0, structure.storey_k, structure.storey_bottom,
                structure.storey_top, structure.storey_a1, binv, starts, counts,
                ground, ground_dt,
                structure.column_storey, structure.column_arm_bottom, structure.column_arm_top,
                structure.column_axes,
                u, v_half, acc, *peaks, *outs, out_ground, out_energy, *work,
            )  # fmt: skip
            wall += time.perf_counter() - t0
            if progress is not None:
                progress(min(done, n_steps), n_steps)
            if done > n_steps:
                break
    except KeyboardInterrupt:
        status = -1
    if status == cdm.STATUS_OK:
        text, valid = "complete", n_out
    elif status == cdm.STATUS_DIVERGED:
        t_fail = (done - 1) * dt
        text = (
            f"failed: diverged at t = {t_fail:.4g} s (a displacement exceeded "
            f"{DIVERGENCE_LIMIT:g} m or became NaN); Δt = {dt:.3g} s may be too large"
        )
        valid = (done - 1) // stride
    else:
        text = "failed: interrupted"
        valid = int(np.count_nonzero(~np.isnan(out_energy[:, 0])))
    cut = slice(0, valid)
    return Response(
        time=np.arange(valid) * stride * dt,
        displacement=outs[0][cut],
        velocity=outs[1][cut],
        acceleration=outs[2][cut],
        ground=out_ground[cut],
        energy=out_energy[cut],
        peak_column=peaks[0],
        peak_storey_rotation=peaks[1],
        peak_displacement=peaks[2],
        peak_acceleration=peaks[3],
        dt=dt,
        steps=min(done, n_steps),
        wall_time=wall,
        status=text,
    )
