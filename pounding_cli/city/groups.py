"""Independent groups: buildings that cannot reach each other, directly or through
neighbours, are separate problems (issue 30).

The groups are the connected components of the "may touch" graph, whose edges are the
building pairs within reach (city/reach.py). Each group runs as a model of its own (its
buildings, the same record, analysis and contact settings), on local processes or a Dask
cluster (the sweeps' executors), and the results are merged into one RunResult: the
buildings in the model's order, the contact candidates and impacts of every group (pair
numbers renumbered), and the energies summed (independent systems' energies add).
A group's time step is its own: the stiffest contact it can make sets it, not another
group's. After the merge, the check of city/rerun.py runs across groups: two buildings of
different groups must not have come within their measured excursions of touching.
"""

from __future__ import annotations

import copy
import re
from dataclasses import replace
from pathlib import Path
from typing import Any, Callable, Iterable

import numpy as np

from ..plausibility import Notice
from ..results.result import CONTACT_HISTORIES, ContactResult, RunResult
from ..results.sparse import SparseColumns


def components(n: int, pairs: Iterable[tuple[int, int]]) -> list[list[int]]:
    """The connected components of the graph on n buildings with edges `pairs`, each sorted,
    ordered by their first building."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    edges = np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    groups: dict[int, list[int]] = {}
    for k, g in enumerate(label):
        groups.setdefault(int(g), []).append(k)
    return sorted(groups.values(), key=lambda g: g[0])


def group_labels(n: int, groups: list[list[int]]) -> np.ndarray:
    """(n,) the group of each building."""
    label = np.empty(n, dtype=np.int64)
    for g, members in enumerate(groups):
        label[members] = g
    return label


def group_document(document: dict[str, Any], members: list[int], reach: float) -> dict[str, Any]:
    """The model document of one group: its buildings only, with the scene's reach fixed (so
    that the group prunes as the whole scene would)."""
    doc = {key: copy.deepcopy(value) for key, value in document.items() if key != "buildings"}
    doc["buildings"] = [copy.deepcopy(document["buildings"][k]) for k in members]  # not all of them: O(N) a group
    doc.setdefault("contact", {})["reach"] = reach
    return doc


def run_group(document: dict[str, Any], source: str, members: list[int], strict: bool = False
              ) -> tuple[RunResult | None, list[Notice], Notice | None]:  # fmt: skip
    """Validate, prepare and run one group's model (in a worker process): (its result, its
    plausibility warnings, what refused it), fields named as in the whole model
    (whole_model_notice), its contact histories sparse (with_sparse_contact). A group its own
    set-up refuses (an InputError: the resource limits) does not run: (None, [], that
    refusal). With `strict`, a group with warnings does not run either (None): the whole run
    is refused, as `pound run --strict` refuses it."""
    from ..api import execute, prepare
    from ..errors import InputError
    from ..model import validate_model
    from ..results.grouped_file import with_sparse_contact

    try:
        scene = prepare(validate_model(document, Path(source)))
    except InputError as refused:  # the parent raises it (exit 2)
        return None, [], whole_model_notice(Notice(refused.file or source, refused.field or "", refused.message),
                                            members)  # fmt: skip
    found = [whole_model_notice(n, members) for n in scene.notices]
    if strict and found:
        return None, found, None
    return with_sparse_contact(execute(scene)), found, None


def whole_model_notice(notice: Notice, members: list[int]) -> Notice:
    """A group's notice with its field named in the whole model: the group's document holds
    buildings `members` of it, in that order, so its `buildings[k]` is the model's
    `buildings[members[k]]`; other fields (materials, contact, excitation) are the model's."""
    match = re.match(r"buildings\[(\d+)\]", notice.field)
    if match is None:
        return notice
    field = f"buildings[{members[int(match.group(1))]}]" + notice.field[match.end():]
    return replace(notice, field=field)


def merge(results: list[RunResult], order: list[str], model_json: str, input_sha256: str,
          warnings: list[Notice]) -> RunResult:  # fmt: skip
    """One RunResult of the groups' results as GroupedFile.add leaves them (their contact
    histories SparseColumns, their buildings' histories in the file): buildings in `order`,
    contacts of all groups, and the scene's `warnings` (run_groups': a group's own name its
    fields in the group's document)."""
    first = results[0]
    buildings = {}
    for r in results:
        buildings.update(r.buildings)
    failed = [r.status for r in results if not r.complete]
    diagnostics = dict(first.diagnostics)
    for key in ("steps", "contact_steps", "cdm_steps", "exact_substeps", "slept_building_steps", "sleeps", "wakes",
                "contact_pairs", "storey_pairs", "impacts", "impacts_logged", "n_dof", "wall_time_s", "compile_time_s",
                "contact_reach_reruns", "step_changes"):  # fmt: skip
        if all(key in r.diagnostics for r in results):
            diagnostics[key] = sum(r.diagnostics[key] for r in results)
    diagnostics["dt"] = min(r.diagnostics["dt"] for r in results)
    diagnostics["groups"] = len(results)
    return RunResult(
        time=first.time, ground_acceleration=first.ground_acceleration,
        energy=np.sum([r.energy for r in results], axis=0),
        buildings={name: buildings[name] for name in order},
        status=failed[0] if failed else "complete", model_json=model_json, input_sha256=input_sha256,
        diagnostics=diagnostics, contact=_merge_contact([r.contact for r in results]),
        warnings=[n.as_dict() for n in warnings],
    )  # fmt: skip


def _merge_contact(parts: list[ContactResult]) -> ContactResult:
    offsets = np.cumsum([0] + [c.pairs.size for c in parts])
    events = []
    for c, offset in zip(parts, offsets):
        e = c.events.copy()
        e["pair"] += offset
        events.append(e)
    events_all = np.concatenate(events)
    events_all = events_all[np.argsort(events_all["t_start"], kind="stable")]

    return ContactResult(
        pairs=np.concatenate([c.pairs for c in parts]), events=events_all,
        column_demand=np.concatenate([c.column_demand for c in parts]),
        **{name: SparseColumns.side_by_side([getattr(c, name) for c in parts]) for name in CONTACT_HISTORIES},
    )  # fmt: skip


def run_groups(document: dict[str, Any], source: str, groups: list[list[int]], reach: float,
               submit: Callable[[list[tuple[Any, Callable[..., Any], tuple[Any, ...]]]], Iterable[tuple[Any, bool, Any]]],
               strict: bool = False, progress: Callable[[int, int], None] | None = None,
               keep: Callable[[RunResult], RunResult] = lambda r: r) -> tuple[list[RunResult], list[Notice]]:  # fmt: skip
    """Run every group through `submit` (an executor's run: tasks in, (key, ok, value) out):
    the results in group order, each as `keep` returns it when its group ends (GroupedFile.add
    writes it and keeps what the merge needs), and the plausibility warnings of all groups
    (run_group), each once, in the order of the groups. A group that could not run is an
    AnalysisFailed naming it and the reason, one its set-up refused the InputError it gave (exit 2); with `strict`,
    warnings are the InputError `pound run --strict` gives, once every group has answered (the
    groups without any may have run by then; nothing is written). `progress(done, total)` hears
    of each group as it answers."""
    from ..errors import AnalysisFailed, InputError
    from ..plausibility import strict_error

    tasks = [(k, run_group, (group_document(document, g, reach), source, g, strict)) for k, g in enumerate(groups)]
    out: dict[int, tuple[RunResult | None, list[Notice], Notice | None]] = {}
    for key, ok, value in submit(tasks):
        if not ok:
            raise AnalysisFailed(f"group {key + 1} of {len(groups)} (buildings {', '.join(document['buildings'][k]['name'] for k in groups[key][:3])}"
                                 f"{', …' if len(groups[key]) > 3 else ''}) could not run: {value}")  # fmt: skip
        result, said, refused = value
        out[key] = (keep(result) if result is not None else None, said, refused)
        if progress is not None:
            progress(len(out), len(groups))
    answers = [out[k] for k in range(len(groups))]
    for _, _, refused in answers:
        if refused is not None:
            raise InputError(refused.message, file=refused.file, field=refused.field or None)
    found = list(dict.fromkeys(n for _, said, _ in answers for n in said))
    if strict and found:
        raise strict_error(found)
    return [result for result, _, _ in answers], found  # type: ignore[misc]


def split_allowed(model) -> bool:  # type: ignore[no-untyped-def]
    """Whether a model's buildings can run apart: no obstacles (fixed bodies shared by all)
    and no building placed relative to another."""
    return not model.all_obstacles() and all(getattr(b, "place", None) is None for b in model.buildings)



