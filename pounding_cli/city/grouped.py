"""`pound run --jobs N` / `--scheduler URL`: a scene of independent groups (city/groups.py)
run group by group on local processes or a Dask cluster, merged into one result file."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..results.result import RunResult


def run_in_groups(model: str | Path, output: Path, jobs: int | None = None, scheduler: str | None = None,
                  scheduler_file: str | None = None, force: bool = False, strict: bool = False,
                  warn: Callable[[Any], None] | None = None,
                  progress: Callable[[int, int], None] | None = None) -> RunResult:  # fmt: skip
    """Run `model` as its independent groups in parallel and write one HDF5 file; a model of
    one group (or one that cannot be split: obstacles, buildings placed by others) runs as
    `pound run` does. The groups' plausibility warnings go to `warn` (named as in the whole
    model; with `strict`, an InputError, nothing written); `progress(done, total)` hears of
    each group as it ends (of a scene run whole, of its steps, as for `pound run`). After the
    merge, buildings of different groups must not have come within their measured excursions
    of touching; if two could have, the scene runs again whole, with a reach that holds them,
    and says so. Each group's buildings go into the file as the group ends
    (results/grouped_file.py): the result returned holds the peaks, impact log, energies and
    diagnostics, its histories no samples (read them from the file: read_hdf5)."""
    from ..api import check_output_path, input_sha256, run_model
    from ..atomic import Abandon
    from ..assembly import assemble, ground_motion
    from ..assembly.levels import outlines
    from ..model import load_model, read_document
    from ..model.placement import stored_json
    from ..plausibility import Notice
    from .groups import components, group_labels, merge, run_groups, split_allowed
    from .reach import REACH_FACTOR, check_pruned, measured_excursions, scene_reach
    from ..results.grouped_file import contact_without_samples, grouped_file
    from ..sweep.run import open_executor

    loaded = load_model(model)
    if not split_allowed(loaded.model):
        return run_model(loaded, output, force=force, strict=strict, warn=warn, progress=progress)
    system = assemble(loaded)
    ground = ground_motion(loaded)
    reach, near = scene_reach(loaded.model, system.buildings, ground.acceleration, ground.dt)
    groups = components(len(system.buildings), near) if near is not None else [list(range(len(system.buildings)))]
    if len(groups) == 1:
        return run_model(loaded, output, force=force, strict=strict, warn=warn, progress=progress)
    check_group_memory(loaded, system, ground.duration, near, groups)
    check_output_path(output, force)
    names = [b.name for b in system.buildings]
    label = group_labels(len(names), groups)
    shapes = outlines(system.buildings)
    try:
        with grouped_file(output, names) as stream:
            with open_executor(jobs, scheduler, scheduler_file) as executor:
                results, found = run_groups(read_document(loaded.source), str(loaded.source), groups, reach.distance,
                                            executor.run, strict, progress, keep=stream.add)  # fmt: skip
            for notice in found if warn is not None else ():
                warn(notice)
            merged = merge(results, names, stored_json(loaded.model), input_sha256(loaded, ground), found)
            moved = measured_excursions(merged, system.buildings)
            same = {(i, j) for i, j in near or ()} | _same_group_pairs(shapes, label, float(np.sort(moved)[-2:].sum()))
            missed = check_pruned(shapes, same, moved, reach.distance)
            if missed:
                raise Abandon  # the file is removed; the scene runs again whole
            merged.diagnostics["contact_reach_m"] = reach.distance
            stream.finish(merged)
    except Abandon:
        i, j, d = missed[0]
        wider = max(2.0 * reach.distance, REACH_FACTOR * float(np.sort(moved)[-2:].sum()))
        notice = Notice(str(loaded.source), "contact.reach",
                        f"buildings {names[i]!r} and {names[j]!r} of different groups, {d:.3g} m apart, moved "
                        f"{moved[i]:.3g} m and {moved[j]:.3g} m: they could have touched; ran the scene again whole "
                        f"with a reach of {wider:.3g} m")  # fmt: skip
        if warn is not None:
            warn(notice)
        contact = loaded.model.contact.model_copy(update={"reach": wider})
        again = replace(loaded, model=loaded.model.model_copy(update={"contact": contact}))
        result = run_model(again, output, force=True, strict=strict, warn=warn, progress=progress)
        result.warnings.append(notice.as_dict())
        return result
    merged.contact = contact_without_samples(merged.contact)
    merged.output = output
    return merged


def check_group_memory(loaded: Any, system: Any, record_duration: float, near: frozenset | None,
                       groups: list[list[int]]) -> None:  # type: ignore[type-arg]  # fmt: skip
    """Refuse, before any group runs, a scene whose largest group's results would not fit in
    memory while they are written: the resource limits' estimate (limits.memory_bytes) of that
    group's histories, with its slab–slab candidates within reach counted from the floors'
    levels (slab–storey ones are few beside them), plus the energies kept of every group until
    the end (results/grouped_file.py: the rest of a group's histories is in the file by then)."""
    from ..assembly.contact import _near_level_pairs
    from ..errors import InputError
    from ..limits import Size, _gib, force_values, max_memory_bytes, memory_bytes

    analysis = loaded.model.analysis
    duration = analysis.duration if analysis.duration is not None else record_duration
    samples = int(duration / analysis.output_interval) + 1
    from .groups import group_labels

    members = np.bincount(system.members.building, minlength=len(system.buildings))
    label = group_labels(len(system.buildings), groups)
    within = [set() for _ in groups]  # type: list[set[tuple[int, int]]]
    for i, j in near or ():
        within[label[i]].add((i, j))
    sizes = [Size(sum(3 * system.buildings[k].n_floors for k in group), len(_near_level_pairs(system.buildings, pairs)),
                  int(members[group].sum()),
                  *force_values([system.buildings[k] for k in group], analysis.column_force_histories))
             for group, pairs in zip(groups, within)]  # fmt: skip
    largest = max(range(len(groups)), key=lambda g: memory_bytes(sizes[g], samples))
    size = sizes[largest]
    estimate, most = memory_bytes(size, samples) + 8 * 7 * samples * len(groups), max_memory_bytes()
    if estimate > most:
        raise InputError(
            f"the results of the largest of its {len(groups)} independent groups ({len(groups[largest])} buildings) "
            f"would hold about {_gib(estimate)} while they are written ({samples:.3g} samples every "
            f"{analysis.output_interval:.3g} s × {size.per_sample} bytes: {size.n_dof} DOFs, about {size.n_pairs} "
            f"contact pairs), more than the limit of {_gib(most)} (POUND_MAX_MEMORY_GB); store less often (a larger "
            "output interval) or shorten the analysis",
            file=loaded.source,
            field="analysis.output_interval",
        )


def _same_group_pairs(shapes: list, label: np.ndarray, distance: float) -> set[tuple[int, int]]:  # type: ignore[type-arg]
    """Pairs of buildings of one group within `distance` (m): the check across groups skips them
    (within a group, each group's own run checked its pruned pairs)."""
    from ..assembly.levels import near_pairs

    if not math.isfinite(distance) or distance <= 0:
        return set()
    return {(i, j) for i, j in near_pairs(shapes, distance) if label[i] == label[j]}
