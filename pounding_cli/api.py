"""The Python API: everything the CLI does, a script can do by import.

    import pounding_cli as pound
    model = pound.load_model("inputs/paper_wide_gap.toml")
    print(pound.describe(model)["buildings"][0]["periods_s"])
    result = pound.run_model(model, output="out.h5")
    result.buildings["left"].column("C9")      # peak interstorey deflections, (storeys, 3)
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

import numpy as np

from . import __version__, limits, plausibility
from .assembly import (
    ContactArrays,
    GroundMotion,
    System,
    TimeGrid,
    assemble,
    contact_arrays,
    ground_motion,
    time_grid,
)
from .assembly.contact import observed_pair_omega
from .assembly.levels import scene_unmet_neighbours
from .assembly.local_modes import with_local_modes
from .assembly.origin import back_to_global, check_resolution, local_origin, reference_point, scene_points
from .assembly.timestep import governing_rule, stability_limit
from .assembly.damping import modal_damping_ratios
from .assembly.force_gauges import force_gauges
from .city.reach import scene_reach
from .city.rerun import within_reach
from .errors import AnalysisFailed, InputError
from .gap.rest import clearance
from .interrupts import InterruptedAfterWriting, settle, terminate_as_interrupt
from .outputs import claim, output_file, refuse_inputs
from .plausibility import Notice
from .model import Analysis, LoadedModel, load_model
from .model.placement import stored_json
from .results import RunResult, collect, write_hdf5
from .results.forces import system_forces
from .results.result import HISTORY_DTYPE
from .solver.tunables import MAX_RERUNS, RERUN_MARGIN

G = 9.80665


def _loaded(model: str | Path | LoadedModel) -> LoadedModel:
    return model if isinstance(model, LoadedModel) else load_model(model)


@dataclass(frozen=True)
class Scene:
    """A model made ready to run: structure, contact candidates, ground motion, time grid."""

    loaded: LoadedModel
    system: System
    contact: ContactArrays
    ground: GroundMotion
    grid: TimeGrid
    regrid: Callable[[float], TimeGrid] | None = None  # the grid for a likely contact ω (rad/s): Δt auto
    notices: tuple[Notice, ...] = ()  # plausibility warnings (pounding_cli.plausibility)


def prepare(model: str | Path | LoadedModel) -> Scene:
    """Validate, assemble, read the record and choose the time grid (no integration)."""
    loaded = _loaded(model)
    for b, building in enumerate(loaded.model.buildings):
        limits.check_storeys(sum(f.repeat for f in building.floors), loaded.source, f"buildings[{b}].floors")
    setup = setup_counts(loaded)
    limits.check_setup(setup, loaded.source)  # from the counts, before anything is assembled
    # extreme inputs (a length of 1e300 m) overflow on the way; what comes out is checked
    # (periods, time step, record) and refused with a message, so numpy need not warn
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        system = assemble(loaded)
        limits.check_structure(system, loaded.source)
        ground = ground_motion(loaded)
        contact = contact_within_reach(loaded, system, ground)
        system, contact = with_local_modes(system, contact, loaded)
        check_resolution(scene_points(loaded.model, system, contact), str(loaded.source))
        grid, regrid = scene_grid(loaded.model.analysis, str(loaded.source), system, contact, ground)
    scene = Scene(loaded, system, contact, ground, grid, regrid)
    scene = replace(scene, notices=tuple(plausibility.notices(scene)))  # before the limits: they blame them
    setup = replace(setup, pairs=contact.n_pairs, exact=grid.substep > 0)
    limits.check_run(resource_run(scene), resource_size(scene), loaded.source, setup,
                     grid.free_steps(ground.dt) if grid.substep else 0)  # fmt: skip
    return scene


def contact_within_reach(loaded: LoadedModel, system: System, ground: GroundMotion) -> ContactArrays:
    """The contact candidates of the buildings within reach of each other (city/reach.py)."""
    reach, near = scene_reach(loaded.model, system.buildings, ground.acceleration, ground.dt)
    contact = contact_arrays(loaded, system.buildings, None if near is None else set(near))
    return replace(contact, reach=reach.distance, reach_source=reach.source, near=near)


def setup_counts(loaded: LoadedModel) -> limits.Setup:
    """The model's size from its counts alone (nothing generated or assembled): storeys and
    column instances per building, contact candidates, whether the exact integrator may run."""
    from .assembly.levels import LEVEL_TOLERANCE

    model = loaded.model
    storeys, columns, levels, owners = [], [], [], []
    for b, building in enumerate(model.buildings):
        heights = [f.height for f in building.floors for _ in range(f.repeat)]
        if building.isolation is not None:
            heights.insert(0, building.isolation.height)
        storeys.append(len(heights))
        columns.append(sum(f.repeat * f.column_count() for f in building.floors))
        levels.append(np.cumsum(heights))
        owners.append(np.full(len(heights), b))
    pairs = 0
    if model.contact.enabled and levels:
        z, owner = np.concatenate(levels), np.concatenate(owners)
        order = np.argsort(z, kind="stable")
        lo = np.searchsorted(z[order], z - LEVEL_TOLERANCE, side="left")
        hi = np.searchsorted(z[order], z + LEVEL_TOLERANCE, side="right")
        pairs = int(sum(np.count_nonzero(owner[order[a:c]] > owner[i]) for i, (a, c) in enumerate(zip(lo, hi))))
        for obstacle in model.all_obstacles():
            pairs += int(np.count_nonzero([obstacle.spans(float(h), LEVEL_TOLERANCE) for h in z]))
    exact = model.analysis.integrator != "cdm"
    return limits.Setup(tuple(storeys), tuple(columns), exact, pairs)


def scene_grid(
    analysis: Analysis, source: str, system: System, contact: ContactArrays, ground: GroundMotion,
    dt_fraction: float | None = None, sampling_scale: float = 1.0, dt_scale: float = 1.0,
) -> tuple[TimeGrid, Callable[[float], TimeGrid] | None]:
    """The time grid of an analysis (timestep.time_grid; dt_fraction, sampling_scale and
    dt_scale as there, for `pound bench`), its automatic contact step following the likely contacts
    (contact.omega_step); and, where that step is automatic and contact is possible, the
    function that makes the grid for another contact ω (rad/s), with which execute repeats a
    run that met a stiffer contact (None otherwise)."""
    rate = system.fastest_rate()[0]

    def regrid(omega_step: float) -> TimeGrid:
        return time_grid(
            analysis, system.omega_max, ground.duration, source, contact.omega_max, ground.dt, dt_fraction,
            sampling_scale, yielding=system.members.top.size > 0, dt_scale=dt_scale, omega_contact_step=omega_step,
            fastest_rate=rate,
        )  # fmt: skip

    automatic = analysis.dt == "auto" and dt_fraction is None and contact.n_pairs > 0
    return regrid(contact.omega_step), regrid if automatic else None


def resource_size(scene: Scene) -> limits.Size:
    """What the scene stores at each output sample (for the resource limits)."""
    analysis = scene.loaded.model.analysis
    forces = limits.force_values(scene.system.buildings, analysis.column_force_histories)
    return limits.Size(scene.system.n_dof, scene.contact.n_pairs, int(scene.system.members.top.size), *forces,
                       building_item=HISTORY_DTYPE[analysis.history_precision].itemsize)  # fmt: skip


def resource_run(scene: Scene) -> limits.Run:
    """The scene's time grid and what set it, as the resource limits need them."""
    analysis, grid, system = scene.loaded.model.analysis, scene.grid, scene.system
    omegas = [float(b.modes.omega[-1]) for b in system.buildings]
    b = int(np.argmax(omegas))
    rate, rb, mode, zeta = system.fastest_rate()
    overdamped = (rb, system.buildings[rb].name, mode, zeta, rate) if rate > 1.000001 * max(omegas) else None
    field = scene.contact.stiffness_field(scene.contact.cause_step)
    pair = scene.contact.cause_step[0]
    names = [b.name for b in system.buildings]
    bodies = ((scene.contact.pairs[pair].body_a, scene.contact.pairs[pair].body_b) if pair >= 0 else ())
    return limits.Run(
        dt=grid.dt, n_steps=grid.n_steps, n_outputs=grid.n_outputs, output_interval=grid.output_interval,
        duration=grid.duration, record_duration=scene.ground.duration,
        given_dt=None if analysis.dt == "auto" else float(analysis.dt), given_duration=analysis.duration,
        given_output_interval=analysis.output_interval,
        auto_dt=_auto_step(grid, system),
        structure_limit=grid.stability_limit, contact_limit=grid.contact_limit,
        stiffest=(b, system.buildings[b].name),
        overdamped=overdamped, contact_field=field,
        contact_auto=field.startswith("contact.") and getattr(scene.loaded.model.contact, field[8:]) == "auto",
        contact_buildings=tuple(names.index(n) for n in bodies if n in names),
        suspects=tuple((n.field, n.message) for n in scene.notices if n.shortens_step),
    )  # fmt: skip


def _auto_step(grid: TimeGrid, system: System) -> float:
    """The step `dt = "auto"` chooses for this grid's limits, s (before fitting it to the output)."""
    which, fraction = governing_rule(grid.stability_limit, grid.contact_step_limit, system.members.top.size > 0)
    return fraction * (grid.contact_step_limit if which == "contact" else grid.stability_limit)


def check_output_path(path: Path, force: bool = False) -> None:
    """Before any work: refuse a folder, an existing file (unless force) and an unwritable
    place; create a missing folder."""
    if path.is_dir():
        raise InputError("is a folder; give a file name for the results, e.g. out.h5", file=path)
    if path.exists() and not force:
        raise InputError("exists; choose another name or pass --force to overwrite it", file=path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder {str(path.parent)!r} ({exc.strerror})", file=path) from None
    if not os.access(path.parent, os.W_OK):
        raise InputError(f"the folder {str(path.parent)!r} is not writable", file=path)


def run_inputs(scene: Scene) -> list[tuple[Path, str]]:
    """Every file a run reads, with what it is: the model, its record definition file, the
    record files of its components (an output must be none of them)."""
    from .assembly.ground import resolve_record

    out = [(Path(scene.loaded.source), "the model of this run")]
    record, origin, record_file = resolve_record(scene.loaded)
    if record_file is not None:
        out.append((Path(record_file), "the record definition of this run"))
    out += [(origin.resolve(c.file), f"the record file of component {name} of this run")
            for name, c in record.components().items()]  # fmt: skip
    return out


def default_output(model: str | Path | LoadedModel) -> Path:
    """The model's name with .h5, in the current folder."""
    source = model.source if isinstance(model, LoadedModel) else Path(model)
    return Path(Path(source).name).with_suffix(".h5")


def input_sha256(loaded: LoadedModel, ground: GroundMotion) -> str:
    """Hash of what determines the result: resolved model, record file bytes, pound version."""
    payload = {
        "model": json.loads(stored_json(loaded.model)),
        "records": ground.file_sha256,
        "pound_version": __version__,
    }
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


def describe(model: str | Path | LoadedModel) -> dict[str, Any]:
    """What a model resolves to: masses, periods, damping, record, time step (JSON-ready)."""
    return describe_scene(prepare(model))


def describe_scene(scene: Scene) -> dict[str, Any]:
    """describe() of a prepared scene."""
    loaded, system, ground, grid = scene.loaded, scene.system, scene.ground, scene.grid
    m = loaded.model
    yielding = system.members.top.size > 0
    rule = governing_rule(grid.stability_limit, grid.contact_step_limit, yielding)
    buildings = []
    for bld, spec in zip(system.buildings, m.buildings):
        n = min(6, bld.modes.omega.size)
        anchor = bld.rayleigh_modes or bld.modes
        masses = bld.mass.reshape(-1, 3)
        buildings.append(
            {
                "name": bld.name,
                "storeys": bld.n_floors,
                "height_m": bld.height,
                "base_elevation_m": bld.base_elevation,
                "origin_m": list(spec.origin),
                "rotation_deg": spec.rotation,
                "place": spec.place.model_dump() if spec.place is not None else None,
                "total_mass_kg": float(masses[:, 0].sum()),
                "floor_masses_kg": masses[:, 0].tolist(),
                "rotational_inertia_kgm2": masses[:, 2].tolist(),
                "columns": len(bld.column_lines),
                "isolators": sum(mb.kind == "isolator" for mb in bld.members),
                "yielding_columns": sum(mb.kind == "column" for mb in bld.members),
                "periods_s": bld.modes.periods[:n].tolist(),
                "participating_mass_ratio_x_y_theta": bld.modes.participation[:n].tolist(),
                "damping_ratios": modal_damping_ratios(bld.damping, bld.modes.shapes[:, :n],
                                                       bld.modes.omega[:n]).tolist(),  # fmt: skip
                "rayleigh": {
                    "modes": list(spec.damping.modes),
                    "ratios": list(spec.damping.ratios),
                    "of": "superstructure on a fixed base" if bld.isolated else "building",
                    "anchor_periods_s": [float(anchor.periods[k - 1]) for k in spec.damping.modes],
                    "a0_per_s": bld.rayleigh[0],
                    "a1_s": bld.rayleigh[1],
                },
                "isolation": _isolation(spec, bld),
                "omega_max_rad_s": float(bld.modes.omega[-1]),
                "dt_limit_s": stability_limit(float(bld.modes.omega[-1])),
                "moat": _moat(spec, m),
            }
        )
    contact = scene.contact
    multiples = phase_step_multiples(scene)
    return {
        "file": str(loaded.source),
        "title": m.title,
        "buildings": buildings,
        "bearings": [_bearing(name, bearing) for name, bearing in m.bearings.items()],
        "contact": {
            "enabled": m.contact.enabled,
            "pairs": [
                {
                    "body_a": p.body_a,
                    "floor_a": p.floor_a,
                    "body_b": p.body_b,
                    "floor_b": p.floor_b,
                    "kind": p.kind,
                    **({"storey_b": p.storey, "xi": p.xi} if p.storey else {}),
                    "elevation_m": p.elevation,
                    **clearance(contact.body_poly[contact.pair_a[i], : contact.body_nv[contact.pair_a[i]]],
                                contact.body_poly[contact.pair_b[i], : contact.body_nv[contact.pair_b[i]]]).as_dict(),
                    "k_normal_N_per_m2": float(contact.pair_kn[i]),
                    "k_tangential_N_per_m": float(contact.pair_kt[i]),
                    **pair_damping_and_friction(contact, i),
                    "omega_likely_rad_s": float(contact.pair_omega[i]),
                    "phase_step_multiple": float(multiples[i]),
                }
                for i, p in enumerate(contact.pairs)
            ],
            "reach_m": contact.reach if np.isfinite(contact.reach) else None,
            "reach_source": contact.reach_source,
            "pruned": contact.near is not None,
            "storey_crossings": [
                {
                    "body_a": system.buildings[c.building].name,
                    "floor_a": c.floor + 1,
                    "body_b": system.buildings[c.struck].name,
                    "storey_b": c.storey,
                    "kind": "slab-storey",
                    "elevation_m": c.elevation,
                    "xi": c.xi,
                    "storey_height_m": c.height,
                    **clearance(system.buildings[c.building].slabs[c.floor],
                                system.buildings[c.struck].slabs[c.storey - 1]).as_dict(),
                    "simulated": True,
                    "struck_columns": [system.buildings[c.struck].column_lines[system.buildings[c.struck].columns[i].line].name
                                       for i in body.columns],
                    "contact_line_m": body.line,
                    "local_compliance_m_per_N": body.compliance_normal,
                    "local_modes": body.modes,
                    "struck_columns_mass_kg": body.bundle_mass,
                }
                for c, body in zip(contact.crossings, contact.storeys)
            ],
            "massless_storeys": sum(1 for body in contact.storeys if not body.modes),
            "local_modes": [
                {"building": system.buildings[lm.building].name, "storey": lm.storey, "mode": lm.number,
                 "columns": [system.buildings[lm.building].column_lines[system.buildings[lm.building].columns[i].line].name
                             for i in lm.columns],
                 "mass_kg": lm.mass, "omega_rad_s": lm.omega, "weights": list(lm.weights)}
                for lm in system.local_modes
            ],
            "unmet_neighbours": [
                {"building_a": system.buildings[i].name, "building_b": system.buildings[j].name, "distance_m": d}
                for i, j, d in scene_unmet_neighbours(scene)
            ],
            "friction_static": m.contact.friction_static,
            "friction_kinetic": m.contact.friction_kinetic,
            "omega_max_rad_s": contact.omega_max,
            "omega_likely_rad_s": contact.omega_step,
            "dt_limit_s": grid.contact_limit if contact.n_pairs else None,
        },
        "excitation": {
            "record": ground.record.name if ground.record is not None else "",
            "record_file": str(ground.record_file) if ground.record_file is not None else None,
            "components": list(m.excitation.components),
            "angle_deg": m.excitation.angle,
            "scale": m.excitation.scale,
            "processing": ground.record.processing.steps() if ground.record is not None else [],
            "record_scale_factor": ground.record_factor,
            "directions_X_Y": {name: list(d) for name, d in ground.directions.items()},
            "dt_s": ground.dt,
            "duration_s": ground.duration,
            "pga_g": {
                "X": float(np.abs(ground.acceleration[:, 0]).max() / G),
                "Y": float(np.abs(ground.acceleration[:, 1]).max() / G),
            },
            "notes": list(ground.notes),
        },
        "analysis": {
            "integrator": grid.integrator,
            "dt_s": grid.dt,
            "dt_auto": m.analysis.dt == "auto",
            "dt_auto_fraction": rule[1],
            "dt_limited_by": rule[0],
            "yield_dt_s": grid.yield_dt if grid.substep and yielding else None,
            "stability_limit_s": grid.stability_limit,
            "contact_limit_s": grid.contact_limit if scene.contact.n_pairs else None,
            "contact_step_limit_s": grid.contact_step_limit if scene.contact.n_pairs else None,
            "substep_s": grid.dt * grid.substep if grid.substep else None,
            "cdm_steps_per_substep": grid.substep or None,
            "steps": grid.free_steps(ground.dt),
            "substeps": grid.n_steps // grid.substep if grid.substep else None,
            "steps_of_dt": grid.n_steps,
            "output_interval_s": grid.output_interval,
            "duration_s": grid.duration,
            "outputs": grid.n_outputs,
        },
        "warnings": [n.as_dict() for n in scene.notices],
    }


def phase_step_multiples(scene: Scene) -> np.ndarray:
    """(n_pairs,) how many contact steps long the CDM's step may be in a contact phase where
    that pair is the stiffest that may touch (solver/step_levels.py): by the pair's own likely
    ω, where the step is automatic, the integrator the hybrid and no member yields; else 1."""
    from .solver.step_plan import approach_levels, phase_plan

    grid, contact, system = scene.grid, scene.contact, scene.system
    ones = np.ones(contact.n_pairs)
    if scene.regrid is None or not grid.substep or system.members.top.size:
        return ones
    fine = 2 ** approach_levels(grid.substep, 3 * max(b.n_floors for b in system.buildings), len(system.buildings))
    sub_y = grid.yield_substep if 0 < grid.yield_substep < grid.substep else grid.substep
    ratio = pair_step_ratios(grid, contact.pair_omega) if fine > 1 else None
    counts, level = phase_plan(grid.substep, sub_y, fine, ratio, contact.n_pairs)
    return counts[0] / np.asarray(counts, dtype=float)[level]


def pair_step_ratios(grid: TimeGrid, pair_omega: np.ndarray) -> np.ndarray:
    """(n_pairs,) how many times longer than the grid's contact step each pair's own likely
    contact (pair_omega, rad/s) lets the step be: max(1, ω_step/ω_p)."""
    with np.errstate(divide="ignore"):
        return np.maximum(1.0, grid.contact_step_omega / pair_omega)


def _isolation(building: Any, bld: Any) -> dict[str, Any] | None:
    """An isolated building's isolation system: its viscous damping ratio and the isolated
    period 2π/ω_b on the bearings' post-yield stiffness at which it holds."""
    if building.isolation is None:
        return None
    sum_k2 = sum(mb.stiffness[0] * mb.post_yield_ratio[0] for mb in bld.members if mb.kind == "isolator")
    total = float(bld.mass[0::3].sum())
    return {
        "damping_ratio": building.isolation.damping_ratio,
        "isolated_period_s": float(2 * np.pi * np.sqrt(total / sum_k2)) if sum_k2 > 0 else None,
    }


def _moat(building: Any, model: Any) -> dict[str, Any] | None:
    """An isolated building's moat wall: its gap, thickness and wall segments (the contact
    pairs they are in carry their resolved impact parameters)."""
    iso = building.isolation
    if iso is None or iso.moat is None:
        return None
    walls = [o.name for o in model.all_obstacles() if o.name.startswith(f"{building.name}.moat")]
    return {"gap_m": iso.moat.gap, "thickness_m": iso.moat.thickness, "walls": walls,
            "overrides": iso.moat.overrides()}  # fmt: skip


def pair_damping_and_friction(contact: ContactArrays, i: int) -> dict[str, Any]:
    """Friction and dashpots of contact pair i as resolved: [contact]'s, or an obstacle's or
    moat wall's own."""
    from .assembly.contact import restitution_of

    zeta = float(contact.pair_zeta[i])
    return {
        "friction_static": float(contact.pair_mu_s[i]),
        "friction_kinetic": float(contact.pair_mu_k[i]),
        "restitution": restitution_of(zeta) if zeta > 0 else None,
        "damping_ratio_normal": zeta,
        "damping_normal_N_s_per_m": float(contact.pair_cn[i]),
        "damping_tangential_N_s_per_m": float(contact.pair_ct[i]),
    }


def _bearing(name: str, bearing: Any) -> dict[str, Any]:
    """A bearing type's bilinear law as resolved from the constants given."""
    c = bearing.constants()
    return {
        "name": name,
        "given": list(bearing.given()),
        "initial_stiffness_N_per_m": c.k1,
        "post_yield_stiffness_N_per_m": c.k2,
        "characteristic_strength_N": c.q,
        "yield_force_N": c.fy,
        "yield_displacement_m": c.dy,
        "interaction": bearing.interaction,
    }


def run_model(
    model: str | Path | LoadedModel,
    output: str | Path | None = None,
    progress: Callable[[int, int], None] | None = None,
    force: bool = False,
    strict: bool = False,
    warn: Callable[[Notice], None] | None = None,
) -> RunResult:
    """Run one analysis; write the HDF5 file if `output` is given (also for a failed run,
    marked by its status). Check `result.complete`.

    Plausibility warnings (pounding_cli.plausibility) are passed to `warn` before the run
    and kept in `result.warnings` and the file; with `strict` they are an InputError
    instead, before anything runs or is written.

    `output` ending in "/" (or naming a folder) is a folder: the file is the model's name
    with .h5 inside it. An output that is one of the run's inputs is refused, with --force
    too; the output name is claimed for the whole run, so that a second run writing it
    meanwhile is refused naming this one (outputs.claim). SIGTERM, like Ctrl-C, stops the
    run from the start: before the time loop nothing is written, during it the partial
    results are, marked; once the result file has its final name, SIGTERM ends the process
    by the signal (interrupts)."""
    with terminate_as_interrupt():
        scene = prepare(model)
        if strict and scene.notices:
            raise plausibility.strict_error(list(scene.notices))
        for notice in scene.notices if warn is not None else ():
            warn(notice)
        if output is None:
            return execute(scene, None, progress)
        path, _ = output_file(output, default_output(scene.loaded).name)
        refuse_inputs(path, run_inputs(scene))
        check_output_path(path, force=True)  # the folder made and writable; the name is checked once claimed
        with claim(path):
            check_output_path(path, force)
            return execute(scene, path, progress)


def stiffer_than_stepped(met: np.ndarray, grid: TimeGrid, response: Any) -> np.ndarray:
    """(n_pairs,) bool: the pairs whose contacts met an ω (`met`, rad/s) more than RERUN_MARGIN
    above what the longest step they took follows (the contact step's ω over the pair's step
    ratio, solver Response.pair_dt_ratio)."""
    ratio = response.pair_dt_ratio if response.pair_dt_ratio is not None else np.ones(met.size)
    return met > RERUN_MARGIN * grid.contact_step_omega / ratio


def where_it_failed(system: System, dof: int) -> str:
    """'first at building 'left', floor 3 (u_x)' for a global DOF index."""
    floor = dof // 3
    b = int(np.searchsorted(system.floor_start, floor, side="right")) - 1
    level = floor - int(system.floor_start[b]) + 1
    axis = ("u_x", "u_y", "θ")[dof % 3]
    if system.mode_floor is not None and floor in system.mode_floor:  # a struck bundle's local mode
        mode = system.local_modes[int(np.flatnonzero(system.mode_floor == floor)[0])]
        return (f"first at building {system.buildings[b].name!r}, local mode {mode.number} of the columns struck in "
                f"storey {mode.storey} ({axis})")  # fmt: skip
    return f"first at building {system.buildings[b].name!r}, floor {level} ({axis})"


def execute(
    scene: Scene, output: str | Path | None = None, progress: Callable[[int, int], None] | None = None,
    reach_reruns: int = 0,
) -> RunResult:
    """Integrate a prepared scene (its time grid may be replaced, as `pound bench` does).

    With Δt = "auto" the contact step follows the contacts the scene is likely to make
    (assembly/contact.py: omega_step). When the run meets a contact stiffer than that by more
    than RERUN_MARGIN (observed_pair_omega), it is repeated at the step that contact needs,
    up to MAX_RERUNS times, then at the outlines' upper bound; the wall and compile times
    count every attempt. Where candidates were pruned by reach, a run in which a pruned pair
    could have touched is repeated with a wider reach (city/rerun.py; `reach_reruns`: the
    attempts so far).

    With Δt = "auto", each contact phase of the hybrid takes the longest step that the pairs
    which may touch in it allow, each pair's by its own likely ω (contact.pair_omega;
    solver/step_levels.py); a pair that met a contact stiffer than its step allows by more than
    RERUN_MARGIN is given the ω it met, and the run repeated likewise."""
    loaded, system, ground, grid = scene.loaded, scene.system, scene.ground, scene.grid
    t0 = time.perf_counter()
    ref = reference_point(system, scene.contact)  # far from the origin: computed about a local one
    local_system, local_contact = local_origin(system, scene.contact, ref)
    gauges = force_gauges(local_system, ref)

    from .solver import simulate  # the integrator (numba, the kernels) loads here, not at import

    def integrate(grid: TimeGrid, pair_omega: np.ndarray | None) -> Any:
        ratio = pair_step_ratios(grid, pair_omega) if pair_omega is not None else None
        return back_to_global(simulate(
            local_system, ground.acceleration, ground.dt, grid.dt, grid.stride, grid.n_steps, progress,
            contact=local_contact if scene.contact.n_pairs else None, substep=grid.substep,
            yield_substep=grid.yield_substep, gauges=gauges, pair_step_ratio=ratio,
        ), ref)  # fmt: skip

    pair_omega = scene.contact.pair_omega.copy() if scene.regrid is not None else None
    response = integrate(grid, pair_omega)
    wall_time, compile_time = response.wall_time, response.compile_time
    met = observed_pair_omega(scene.contact, response.events)
    seen = float(met.max(initial=0.0))
    reruns = 0
    while scene.regrid is not None and reruns <= MAX_RERUNS and stiffer_than_stepped(met, grid, response).any():
        reruns += 1
        if seen > RERUN_MARGIN * grid.contact_step_omega or reruns > MAX_RERUNS:
            grid = scene.regrid(scene.contact.omega_max if reruns > MAX_RERUNS else min(seen, scene.contact.omega_max))
        pair_omega = None if reruns > MAX_RERUNS else np.maximum(pair_omega, met)
        response = integrate(grid, pair_omega)
        wall_time += response.wall_time
        compile_time += response.compile_time
        met = np.maximum(met, observed_pair_omega(scene.contact, response.events))
        seen = float(met.max(initial=0.0))
    diagnostics = {
        "integrator": grid.integrator,
        "dt": grid.dt,
        "substep": grid.dt * grid.substep,
        "yield_dt": grid.yield_dt,
        "exact_substeps": response.exact_substeps,
        "exact_steps_of_dt": response.exact_steps_of_dt,
        "cdm_steps": response.cdm_steps,
        "slept_building_steps": response.slept_building_steps,
        "sleeps": response.sleeps,
        "wakes": response.wakes,
        "switches": response.switches,
        "step_changes": response.step_changes,
        "dt_auto": loaded.model.analysis.dt == "auto",
        "stability_limit": grid.stability_limit,
        "output_interval": grid.output_interval,
        "steps": response.steps,
        "contact_steps": response.contact_steps,
        "contact_pairs": scene.contact.n_pairs,
        "storey_pairs": len(scene.contact.storeys),
        "impacts": response.events_total,
        "impacts_logged": int(response.events.shape[0]),
        "n_dof": system.n_dof,
        "contact_omega_step": grid.contact_step_omega,
        "contact_omega_seen": seen,
        "contact_reruns": reruns,
        "wall_time_s": wall_time,
        "compile_time_s": compile_time,
        "us_per_step": 1e6 * wall_time / max(response.steps, 1),
        "run_time_s": time.perf_counter() - t0,
        "record_notes": "; ".join(ground.notes),
    }
    settle(response.status)  # a stop request the time loop did not see stops the run here
    if response.failure_dof >= 0:
        response.status += "; " + where_it_failed(system, response.failure_dof)
    forces = system_forces(gauges, local_system, response, loaded.model.analysis.column_force_histories)
    result = collect(
        system, response, stored_json(loaded.model), input_sha256(loaded, ground), diagnostics, scene.contact,
        forces, loaded.model.analysis.history_precision,
    )
    result.diagnostics["balance_error_ratio"] = result.balance_error_ratio
    result.warnings = [n.as_dict() for n in scene.notices]
    if scene.contact.near is not None:
        result.diagnostics["contact_reach_reruns"] = reach_reruns
        result = within_reach(scene, result, lambda again, n: execute(again, None, progress, n))
    if output is not None:
        write_results(result, Path(output))
    return result


def write_results(result: RunResult, output: Path) -> None:
    """Write a run's HDF5 file. A file that cannot be written (disk full, no permission, the
    folder gone) is an InputError, exit 2: nothing is written, so there are no partial results
    to mark (exit 1 promises them). Interrupted while writing: AnalysisFailed, exit 1."""
    try:
        write_hdf5(result, output)
    except InputError as exc:
        raise InputError(
            f"{exc.message}; the analysis ran ({result.status}) but its results were not written: make room or "
            "give another output file, and run again",
            file=exc.file,
        ) from None
    except InterruptedAfterWriting:
        raise  # the file has its final name: not "nothing was written"
    except KeyboardInterrupt:
        raise AnalysisFailed(f"{output}: interrupted while writing the results; nothing was written") from None
