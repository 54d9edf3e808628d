"""Storey shears and column forces of a building: histories at the output interval, from the
stored floor motion and members' forces, and the time loop's exact running peaks.

The forces are the gauges of assembly/force_gauges.py: each a linear combination of a storey's
deflection (Ã_x, Ã_y, Δθ) less its yielding members' plastic part k_h ⊙ p, which a member's
stored deflection δ and force f give as k·δ − f (hysteresis.py: f = k·δ − k_h·p). The
histories use the same weights as the peaks, so a peak is never below its history.

Conventions (docs/user-guide.md, "Forces"):
- storey shear: the resultant of the forces the storey's columns (or bearings) carry, V = Σ k·δ
  (positive along their deflection, top minus bottom; the columns push the floor above by −V):
  STOREY_COMPONENTS, along building x, y with the torque about the mass centre of the floor
  above, and along global X, Y with the torque about the global origin;
- base shear: the shear of the storey on the building's ground (its lowest storey, or its
  isolation storey: a building stands on one);
- column shear: along the column's local x and y; end moment M = V·h/2 of a column fixed at
  both ends, [..., 0] from the shear along local x (bending about local y), [..., 1] from y.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assembly.force_gauges import N_STOREY, ForceGauges
from .result import HISTORY_DTYPE, ForceResult


def storey_deflections(gauges: ForceGauges, displacement: np.ndarray, bottom: np.ndarray,
                       top: np.ndarray) -> np.ndarray:  # fmt: skip
    """(nt, n_storeys, 3) the storeys' deflections from the floor DOFs (nt, n_dof) of the
    whole system, bottom −1 the ground."""
    nt = displacement.shape[0]
    padded = np.concatenate([displacement, np.zeros((nt, 3))], axis=1)
    floors = padded.reshape(nt, -1, 3)
    q = np.concatenate([floors[:, bottom], floors[:, top]], axis=2)  # bottom −1: the zero row
    return np.einsum("sij,tsj->tsi", gauges.deflection_map, q)


def plastic_forces(member_history: np.ndarray | None, k0: np.ndarray, nt: int) -> np.ndarray:
    """(nt, n_members, 2) k_h ⊙ p = k·δ − f of every yielding member, N."""
    if member_history is None:
        return np.zeros((nt, 0, 2))
    return k0 * member_history[:, :, :2] - member_history[:, :, 2:]


def plastic_resultants(gauges: ForceGauges, plastic: np.ndarray, member_storey: np.ndarray,
                       n_storeys: int) -> np.ndarray:  # fmt: skip
    """(nt, n_storeys, 3) P_s: each storey's members' plastic forces (nt, n_members, 2) on the
    floor above as F_X, F_Y and the torque about the plan origin (force_peaks.plastic_resultants
    gets the same from the floors' plastic correction)."""
    out = np.zeros((plastic.shape[0], n_storeys, 3))
    if plastic.shape[1]:
        np.add.at(out, (slice(None), member_storey), np.einsum("mij,tmj->tmi", gauges.member_resultant, plastic))
    return out


def storey_shears(gauges: ForceGauges, deflection: np.ndarray, resultant: np.ndarray) -> np.ndarray:
    """(nt, n_storeys, 6) every storey's STOREY_COMPONENTS from the storeys' deflections and
    plastic resultants (nt, n_storeys, 3 each)."""
    rows = gauges.storey_gauge[:, None] + np.arange(N_STOREY)  # (n_storeys, 6) gauges
    return (np.einsum("tsj,sij->tsi", deflection, gauges.weight[rows])
            - np.einsum("tsj,sij->tsi", resultant, gauges.plastic_weight[rows]))  # fmt: skip


def column_shears(gauges: ForceGauges, deflection: np.ndarray, plastic: np.ndarray,
                  column_storey: np.ndarray) -> np.ndarray:  # fmt: skip
    """(nt, n_columns, 2) every column instance's shear along its local x, y, N."""
    out = np.einsum("tkj,kij->tki", deflection[:, column_storey], gauges.column_weight)
    for k in np.flatnonzero(gauges.column_member >= 0):
        out[:, k] -= plastic[:, gauges.column_member[k]]
    return out


def column_peaks(gauges: ForceGauges, response) -> np.ndarray:  # type: ignore[no-untyped-def]
    """(n_columns, 2) every column instance's peak |shear| along its local x, y, N: its gauges'
    where it has them (and a yielding column's member's, |f| at every state), else k × its
    deflection's peak (its local axes are the building's)."""
    peaks = gauges.column_stiffness * response.peak_column
    for k in np.flatnonzero(gauges.column_gauge >= 0):
        peaks[k] = response.peak_gauge[gauges.column_gauge[k] : gauges.column_gauge[k] + 2]
        if gauges.column_member[k] >= 0:
            peaks[k] = np.maximum(peaks[k], response.peak_member[gauges.column_member[k], 3:5])
    return peaks


def by_line(bld, values: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    """(…, n_columns, 2) per column instance of building bld into (…, n_lines, n_storeys, 2),
    NaN where a line has no column in a storey."""
    out = np.full(values.shape[:-2] + (len(bld.column_lines), bld.n_floors, 2), np.nan)
    for k, inst in enumerate(bld.columns):
        out[..., inst.line, inst.storey, :] = values[..., k, :]
    return out


@dataclass(frozen=True)
class SystemForces:
    """What every building's forces are cut from: the storeys' deflections, the members'
    plastic forces and the gauges."""

    gauges: ForceGauges
    deflection: np.ndarray  # (nt, n_storeys, 3)
    plastic: np.ndarray  # (nt, n_members, 2) k_h ⊙ p
    storey_shear: np.ndarray  # (nt, n_storeys, 6)
    histories: bool  # column force histories asked for


def system_forces(gauges: ForceGauges, system, response, histories: bool) -> SystemForces:  # type: ignore[no-untyped-def]
    """The storeys' deflections and members' plastic forces at the output samples."""
    deflection = storey_deflections(gauges, response.displacement, system.storey_bottom, system.storey_top)
    plastic = plastic_forces(response.member_history, system.members.k0, deflection.shape[0])
    resultant = plastic_resultants(gauges, plastic, system.members.top, system.storey_top.size)
    return SystemForces(gauges, deflection, plastic, storey_shears(gauges, deflection, resultant), histories)


def force_result(forces: SystemForces, system, b: int, response, column_offset: int,  # type: ignore[no-untyped-def]
                 dtype: np.dtype = HISTORY_DTYPE["double"]) -> ForceResult:  # fmt: skip
    """Building b's forces, the histories as `dtype`; its column instances start at
    column_offset. A building stands on one storey (its lowest, or its isolation storey): its
    base shear and that storey's are one."""
    bld = system.buildings[b]
    gauges = forces.gauges
    storeys = system.real_floors(b)  # storey s is beneath floor s (its local modes' pseudo-floors after them)
    cols = slice(column_offset, column_offset + len(bld.columns))
    g0 = gauges.storey_gauge[storeys]
    shear = forces.storey_shear[:, storeys].astype(dtype, copy=False)
    peak_storey = response.peak_gauge[g0[:, None] + np.arange(N_STOREY)]
    base = int(np.flatnonzero(system.storey_bottom[storeys] < 0)[0])
    heights = gauges.column_height[cols, None]
    peak_col = by_line(bld, column_peaks(gauges, response)[cols])
    nt = response.time.size
    result = ForceResult(
        storey_shear=shear,
        base_shear=shear[:, base].copy(),
        floor_contact=response.floor_contact[:, 3 * storeys.start : 3 * storeys.stop].reshape(nt, bld.n_floors, 3),
        peak_storey_shear=peak_storey,
        peak_base_shear=peak_storey[base].copy(),
        peak_column_shear=peak_col,
        peak_column_moment=peak_col * by_line(bld, np.repeat(0.5 * heights, 2, axis=1)),
    )
    if forces.histories:
        v = column_shears(gauges, forces.deflection, forces.plastic, system.column_storey)[:, cols]
        result.column_shear = by_line(bld, v).astype(dtype, copy=False)
        result.column_moment = by_line(bld, v * (0.5 * heights)).astype(dtype, copy=False)
    return result
