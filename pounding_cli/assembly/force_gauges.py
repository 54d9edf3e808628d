"""Storey shears and column forces as linear "gauges" of the storey deflections.

A storey's columns (and bearings) deflect by what its storey deflection (Ã_x, Ã_y, Δθ) in
building axes says (peaks.storey_deflection): a column at P deflects by Ã + Δθ·(ξ, η), with
(ξ, η) the building-axes components of ẑ×P (integrate.peak_geometry). So every force of a
shear-type storey is a linear combination of those three numbers, plus, where members yield,
a part carried by their plastic deflections p (hysteresis.py: a member's force is k·δ − k_h·p).
A gauge is such a combination:

    value = w · (Ã_x, Ã_y, Δθ) − k_h,a·p_a of its member along axis a (a column's)
                               − c · P_s (a storey's)

with w in N/m, N/m, N/rad (N·m/m, N·m/rad for a torque), P_s the resultant of the plastic
forces k_h ⊙ p of storey s's members on the floor above (F_X, F_Y and the torque about the
plan origin) and c dimensionless (m for a torque). The time loop gets P_s of every storey at
once from the plastic correction g on the floors (hysteresis.py): summed over the floors from
storey s's up, the storeys above cancel (a member pushes its top and bottom floors equally and
oppositely at one point) and storey s's own is left (force_peaks.plastic_resultants).
The time loop follows the gauges' running peaks exactly, between steps too (peaks.py), and the
results compute their histories from the stored deflections and members' forces with the same
weights (results/forces.py).

Per storey, STOREY_COMPONENTS: the resultant of its columns' forces, the storey shear V (the
force the columns carry, positive along the deflection: the force they exert on the floor above
is −V) along the building's x and y and its torque about the mass centre of the floor above
(at rest), then the same resultant along global X and Y with its torque about the global
origin. Per column, its shear along its local x and y (section widths b_x, b_y). A column whose
local axes are the building's and that stays linear needs no gauge of its own: its shear is
k·(its deflection), whose running peak the loop already follows (peaks.update_peaks).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .system import System

STOREY_COMPONENTS = ("V_x", "V_y", "T", "V_X", "V_Y", "T_O")
"""A storey's shear along building x, y (N) and torque about the mass centre of the floor above
(N·m); along global X, Y (N) and torque about the global origin (N·m)."""
STOREY_UNITS = ("N", "N", "N·m", "N", "N", "N·m")
N_STOREY = len(STOREY_COMPONENTS)


@dataclass(frozen=True)
class ForceGauges:
    """The gauges the time loop follows (listed storey by storey) and the weights of every
    storey's and column's forces."""

    storey: np.ndarray  # (n_g,) int64 global storey of each gauge
    weight: np.ndarray  # (n_g, 3) on the storey deflection (Ã_x, Ã_y, Δθ)
    first: np.ndarray  # (n_storeys + 1,) int64 the storeys' first gauges
    member: np.ndarray  # (n_g,) int64 a column gauge's yielding member, −1: none
    member_axis: np.ndarray  # (n_g,) int64 the local axis of its plastic force k_h·p subtracted
    plastic_weight: np.ndarray  # (n_g, 3) a storey gauge's on its plastic resultant P_s, subtracted
    storey_above: np.ndarray  # (n_storeys,) int64 the storey on top of each (same building), −1: none
    member_resultant: np.ndarray  # (n_members, 3, 2) a member's (k_h,x·p_x, k_h,y·p_y) to its share of P_s
    storey_gauge: np.ndarray  # (n_storeys,) int64 gauge of each storey's first component
    column_gauge: np.ndarray  # (n_columns,) int64 gauge of each column's local-x shear, −1: none
    column_weight: np.ndarray  # (n_columns, 2, 3) every column's local shears on its storey's deflection
    column_stiffness: np.ndarray  # (n_columns, 2) k along local x, y, N/m
    column_member: np.ndarray  # (n_columns,) int64 global yielding member of each column, −1: linear
    column_height: np.ndarray  # (n_columns,) m
    deflection_map: np.ndarray  # (n_storeys, 3, 6) (Ã_x, Ã_y, Δθ) of each storey from its (q_bottom, q_top)


def deflection_map(system: System, s: int) -> np.ndarray:
    """(3, 6): storey s's deflection (Ã_x, Ã_y, Δθ) in building axes from the DOFs of its bottom
    and top floors (zero for the ground), as peaks.storey_deflection computes it."""
    c, sn = system.storey_axes[s]
    bottom = system.storey_bottom[s]
    bx, by = system.floor_centre[bottom] if bottom >= 0 else (0.0, 0.0)
    tx, ty = system.floor_centre[system.storey_top[s]]
    a = np.array([[-1.0, 0.0, -by, 1.0, 0.0, ty], [0.0, -1.0, bx, 0.0, 1.0, -tx], [0, 0, -1.0, 0, 0, 1.0]])
    return np.array([[c, sn, 0.0], [-sn, c, 0.0], [0.0, 0.0, 1.0]]) @ a


def storey_force_rows(system: System, s: int, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(weights (N_STOREY, 3) on storey s's deflection, P (N_STOREY, 3) taking the force on its
    top floor (F_X, F_Y, torque about its mass centre) to the STOREY_COMPONENTS). The system's
    plan positions are relative to `origin` (global, m); T_O is about the global origin."""
    c, sn = system.storey_axes[s]
    gx, gy = system.floor_centre[system.storey_top[s]]
    top_motion = np.array([[c, -sn, -gy], [sn, c, gx], [0.0, 0.0, 1.0]])  # q_top of a unit deflection, bottom held
    force = system.storey_k[s, 3:, 3:] @ top_motion
    gx, gy = gx + origin[0], gy + origin[1]
    to_components = np.array([[c, sn, 0.0], [-sn, c, 0.0], [0.0, 0.0, 1.0],
                              [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-gy, gx, 1.0]])  # fmt: skip
    return to_components @ force, to_components


def member_force_columns(system: System, m: int) -> np.ndarray:
    """(3, 2): member m's force on its top floor (F_X, F_Y, torque about its mass centre) per
    unit local force (f_x, f_y) (hysteresis.scatter_member)."""
    c, sn = system.members.axes[m]
    ax, ay = system.members.arm_top[m]
    return np.array([[c, -sn], [sn, c], [ax * sn - ay * c, ax * c + ay * sn]])


def about_plan_origin(centre: np.ndarray) -> np.ndarray:
    """(3, 3): a force (F_X, F_Y, torque about the point `centre`) to (F_X, F_Y, torque about
    the plan origin)."""
    return np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-centre[1], centre[0], 1.0]])


def column_weights(system: System) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(weights (n_columns, 2, 3), stiffness (n_columns, 2), member, height, aligned): every
    column instance's local shears f_i = k_i·e_i·(Ã + Δθ·(ξ, η)) on its storey's deflection
    (e_i its local axes in building axes), its global member (−1: linear), its storey height,
    and whether its local axes are the building's."""
    weights, stiffness, member, height, aligned = [], [], [], [], []
    members0 = 0
    for bld in system.buildings:
        phi = bld.rotation
        for inst in bld.columns:
            plan = system.column_plan[len(weights)]  # as the time loop has it (integrate.peak_geometry)
            c, sn = np.cos(phi), np.sin(phi)
            xi, eta = -c * plan[1] + sn * plan[0], sn * plan[1] + c * plan[0]
            rel = inst.angle - phi
            axes = np.array([[np.cos(rel), np.sin(rel)], [-np.sin(rel), np.cos(rel)]])
            k = np.asarray(inst.stiffness, dtype=float)
            weights.append(k[:, None] * np.column_stack([axes, axes @ (xi, eta)]))
            stiffness.append(k)
            member.append(members0 + inst.member if inst.member >= 0 else -1)
            height.append(inst.height)
            aligned.append(rel == 0.0)
        members0 += len(bld.members)
    n = len(weights)
    return (np.asarray(weights, dtype=float).reshape(n, 2, 3), np.asarray(stiffness, dtype=float).reshape(n, 2),
            np.asarray(member, dtype=np.int64), np.asarray(height, dtype=float), np.asarray(aligned, dtype=bool))  # fmt: skip


def force_gauges(system: System, origin: np.ndarray | None = None) -> ForceGauges:
    """The gauges of a system: N_STOREY per storey, and two per column whose shears its
    deflection peaks do not give (rotated in plan, or yielding). The system's plan positions
    are relative to `origin` (global, m; the time loop's local origin, assembly/origin.py)."""
    origin = np.zeros(2) if origin is None else np.asarray(origin, dtype=float)
    col_w, col_k, col_member, col_h, aligned = column_weights(system)
    storey, weight, member, member_axis, plastic_weight, first = [], [], [], [], [], [0]
    storey_gauge = np.zeros(system.storey_top.size, dtype=np.int64)
    column_gauge = np.full(system.column_storey.size, -1, dtype=np.int64)
    for s in range(system.storey_top.size):
        rows, to_components = storey_force_rows(system, s, origin)
        from_origin = np.linalg.inv(about_plan_origin(system.floor_centre[system.storey_top[s]]))
        storey_gauge[s] = len(storey)
        storey += [s] * N_STOREY
        weight += list(rows)
        member += [-1] * N_STOREY
        member_axis += [0] * N_STOREY
        plastic_weight += list(to_components @ from_origin)
        for k in np.flatnonzero(system.column_storey == s):
            if aligned[k] and col_member[k] < 0:
                continue
            column_gauge[k] = len(storey)
            storey += [s, s]
            weight += list(col_w[k])
            member += [int(col_member[k])] * 2
            member_axis += [0, 1]
            plastic_weight += [np.zeros(3), np.zeros(3)]
        first.append(len(storey))
    n_g = len(storey)
    bottom, top = system.storey_bottom, system.storey_top
    above = np.full(top.size, -1, dtype=np.int64)
    for s in range(top.size - 1):
        if bottom[s + 1] == top[s]:
            above[s] = s + 1
    resultant = [about_plan_origin(system.floor_centre[system.members.top[m]]) @ member_force_columns(system, m)
                 for m in range(system.members.n)]  # fmt: skip
    return ForceGauges(
        storey=np.asarray(storey, dtype=np.int64),
        weight=np.asarray(weight, dtype=float).reshape(n_g, 3),
        first=np.asarray(first, dtype=np.int64),
        member=np.asarray(member, dtype=np.int64),
        member_axis=np.asarray(member_axis, dtype=np.int64),
        plastic_weight=np.asarray(plastic_weight, dtype=float).reshape(n_g, 3),
        storey_above=above,
        member_resultant=np.asarray(resultant, dtype=float).reshape(-1, 3, 2),
        storey_gauge=storey_gauge,
        column_gauge=column_gauge,
        column_weight=col_w,
        column_stiffness=col_k,
        column_member=col_member,
        column_height=col_h,
        deflection_map=np.array([deflection_map(system, s) for s in range(system.storey_top.size)]).reshape(-1, 3, 6),
    )
