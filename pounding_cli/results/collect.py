"""From the solver's flat arrays to per-building results."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..assembly import BuildingArrays, ContactArrays, System
from ..solver import layout as kernel
from .column_demand import column_demand
from .forces import SystemForces, force_result
from .result import (EVENT_DTYPE, HISTORY_DTYPE, MEMBER_DTYPE, PAIR_DTYPE, BuildingResult, ContactResult, RunResult,
                     YieldingResult)

if TYPE_CHECKING:  # the integrator (and numba) load when a run needs them
    from ..solver.integrate import Response


def yielding_result(bld: BuildingArrays, response: Response, offset: int,
                    dtype: np.dtype = HISTORY_DTYPE["double"]) -> YieldingResult | None:  # fmt: skip
    """Building bld's yielding members, rows offset … of the response's member arrays, their
    histories as `dtype`."""
    n = len(bld.members)
    if n == 0:
        return None
    rows = np.zeros(n, MEMBER_DTYPE)
    for k, m in enumerate(bld.members):
        plan = bld.mass_centre[m.storey] + m.arm_top
        rows[k] = (m.name, m.kind, m.storey + 1, plan[0], plan[1], np.degrees(m.angle), m.stiffness, m.yield_force,
                   m.post_yield_ratio, m.coupled)  # fmt: skip
    cut = slice(offset, offset + n)
    history = response.member_history[:, cut]
    return YieldingResult(
        members=rows,
        deflection=history[:, :, :2].astype(dtype),
        force=history[:, :, 2:].astype(dtype),
        peak=response.peak_member[cut].copy(),
        residual_deflection=response.residual_member[cut].copy(),
    )


def building_result(system: System, b: int, response: Response, column_offset: int, member_offset: int = 0,
                    forces: SystemForces | None = None,
                    dtype: np.dtype = HISTORY_DTYPE["double"]) -> BuildingResult:  # fmt: skip
    """Cut building b's part out of a response, its histories as `dtype` (HISTORY_DTYPE); its
    column instances start at column_offset."""
    bld: BuildingArrays = system.buildings[b]
    floors = system.real_floors(b)  # its local modes' pseudo-floors, after its floors, are not in the results
    dofs = slice(3 * floors.start, 3 * floors.stop)
    n = bld.n_floors
    nt = response.time.size
    floors0 = int(system.floor_start[b])
    peaks = np.full((len(bld.column_lines), n, 3), np.nan)
    for k, inst in enumerate(bld.columns):
        peaks[inst.line, inst.storey, :2] = response.peak_column[column_offset + k]
        peaks[inst.line, inst.storey, 2] = response.peak_storey_rotation[floors0 + inst.storey]
    lines = bld.column_lines
    return BuildingResult(
        name=bld.name,
        displacement=response.displacement[:, dofs].reshape(nt, n, 3).astype(dtype, copy=False),
        velocity=response.velocity[:, dofs].reshape(nt, n, 3).astype(dtype, copy=False),
        acceleration=response.acceleration[:, dofs].reshape(nt, n, 3).astype(dtype, copy=False),
        column_names=[c.name for c in lines],
        column_local=np.array([c.local for c in lines], dtype=float).reshape(-1, 2),
        column_plan=np.array([c.plan for c in lines], dtype=float).reshape(-1, 2),
        column_section=np.array([c.section for c in lines], dtype=float).reshape(-1, 2),
        column_angle=np.array([c.angle for c in lines], dtype=float),
        interstorey_deflection=peaks,
        peak_displacement=response.peak_displacement[dofs].reshape(n, 3),
        peak_acceleration=response.peak_acceleration[dofs].reshape(n, 3),
        elevation=bld.elevation.copy(),
        floor_mass=bld.mass.reshape(n, 3)[:, 1:].copy(),
        mass_centre=bld.mass_centre.copy(),
        periods=bld.modes.periods.copy(),
        participation=bld.modes.participation.copy(),
        rayleigh=(float(bld.rayleigh[0]), float(bld.rayleigh[1])),
        yielding=yielding_result(bld, response, member_offset, dtype),
        isolated=bld.isolated,
        base_elevation=bld.base_elevation,
        forces=force_result(forces, system, b, response, column_offset, dtype) if forces is not None else None,
    )


def contact_result(contact: ContactArrays, response: Response, system: System | None = None) -> ContactResult:
    """Contact histories and the impact log, with the pairs named, and what the slab–storey
    impacts put into the struck columns (with the system)."""
    pairs = np.zeros(contact.n_pairs, PAIR_DTYPE)
    for p, info in enumerate(contact.pairs):
        pairs[p] = (info.body_a, info.floor_a, info.body_b, info.floor_b, info.elevation,
                    contact.pair_kn[p], contact.pair_kt[p], info.storey, info.xi)  # fmt: skip
    h = response.contact
    raw = response.events
    events = np.zeros(raw.shape[0], EVENT_DTYPE)
    for k, row in enumerate(raw):
        info = contact.pairs[int(row[kernel.EV_PAIR])]
        events[k] = (
            info.body_a, info.body_b, info.floor_a, row[kernel.EV_T_START], row[kernel.EV_T_END],
            row[kernel.EV_PEAK_FN], row[kernel.EV_IMPULSE], row[kernel.EV_PEAK_AREA], row[kernel.EV_PEAK_DEPTH],
            row[kernel.EV_X], row[kernel.EV_Y], bool(row[kernel.EV_SLID]), info.floor_b, info.elevation,
            row[kernel.EV_T_PEAK], int(row[kernel.EV_PAIR]), row[kernel.EV_FT_PEAK], row[kernel.EV_NX],
            row[kernel.EV_NY], info.storey, info.xi, row[kernel.EV_T_SLIP], row[kernel.EV_T_STICK],
            int(row[kernel.EV_SLIPS]),
        )  # fmt: skip
    return ContactResult(
        pairs=pairs,
        normal_force=h[:, :, kernel.NOW_FN],
        tangential_force=h[:, :, kernel.NOW_FT],
        area=h[:, :, kernel.NOW_AREA],
        action_point=h[:, :, [kernel.NOW_X, kernel.NOW_Y]],
        depth=h[:, :, kernel.NOW_DEPTH],
        events=events,
        column_demand=(column_demand(system, contact, events, response.time,
                                     response.displacement[:, : system.mass.size].reshape(response.time.size, -1, 3),
                                     getattr(response, "storey_shear_peak", None))
                       if system is not None and contact.storeys else None),  # fmt: skip
    )


def collect(
    system: System,
    response: Response,
    model_json: str,
    input_sha256: str,
    diagnostics: dict[str, Any],
    contact: ContactArrays | None = None,
    forces: SystemForces | None = None,
    precision: str = "double",
) -> RunResult:
    """Assemble a RunResult from the solver's response (with `forces`, results/forces.py, the
    buildings' storey shears and column forces), the buildings' histories in `precision`
    (analysis.history_precision)."""
    dtype = HISTORY_DTYPE[precision]
    buildings = {}
    offset = members = 0
    for b, bld in enumerate(system.buildings):
        buildings[bld.name] = building_result(system, b, response, offset, members, forces, dtype)
        offset += len(bld.columns)
        members += len(bld.members)
    return RunResult(
        time=response.time,
        ground_acceleration=response.ground,
        energy=response.energy,
        buildings=buildings,
        status=response.status,
        model_json=model_json,
        input_sha256=input_sha256,
        diagnostics=diagnostics,
        contact=contact_result(contact, response, system) if contact is not None and contact.n_pairs else None,
    )
