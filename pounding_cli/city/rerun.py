"""After a run whose candidates were pruned by reach: check that no pruned pair could have
touched, and if one could, run again with a reach that holds it (city/reach.py)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable

import numpy as np

from ..plausibility import Notice
from .reach import REACH_FACTOR, check_pruned, measured_excursions

MAX_REACH_RERUNS = 2
"""Runs again with a wider reach at most this many times; then the run is marked failed."""


def within_reach(scene: Any, result: Any, rerun: Callable[[Any], Any]) -> Any:
    """`result` if none of the building pairs `scene` pruned came within their measured
    excursions of touching; else the result of `rerun` on the scene with a reach wide enough
    for every pair that could (with a warning naming them), or, after MAX_REACH_RERUNS,
    `result` marked failed."""
    from ..api import prepare

    contact, buildings = scene.contact, scene.system.buildings
    if contact.near is None:  # nothing pruned: nothing to check (and the diagnostics of before)
        return result
    done = int(result.diagnostics.get("contact_reach_reruns", 0))
    result.diagnostics["contact_reach_m"] = contact.reach
    from ..assembly.levels import outlines

    moved = measured_excursions(result, buildings)
    missed = check_pruned(outlines(buildings), set(contact.near), moved, contact.reach)
    if not missed:
        return result
    i, j, d = min(missed, key=lambda m: m[2] - moved[m[0]] - moved[m[1]])
    what = (f"buildings {buildings[i].name!r} and {buildings[j].name!r}, {d:.3g} m apart at rest, beyond the reach of "
            f"{contact.reach:.3g} m, moved {moved[i]:.3g} m and {moved[j]:.3g} m: they could have touched"
            + (f" (and {len(missed) - 1} more pairs)" if len(missed) > 1 else ""))  # fmt: skip
    if done >= MAX_REACH_RERUNS:
        result.status = f"failed: {what}; give a larger contact.reach"
        return result
    wider = max(2.0 * contact.reach, REACH_FACTOR * float(np.sort(moved)[-2:].sum()))
    notice = Notice(str(scene.loaded.source), "contact.reach", f"{what}; ran again with a reach of {wider:.3g} m")
    model = scene.loaded.model
    widened = model.model_copy(update={"contact": model.contact.model_copy(update={"reach": wider})})
    again = prepare(replace(scene.loaded, model=widened))
    again = replace(again, notices=scene.notices)
    again_result = rerun(again, done + 1)
    again_result.warnings.append(notice.as_dict())
    again_result.diagnostics["wall_time_s"] += result.diagnostics["wall_time_s"]  # every attempt counts
    return again_result
