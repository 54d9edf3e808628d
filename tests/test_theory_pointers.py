"""docs/theory.md points from each equation to the function that implements it: every such
pointer names a function that exists, and every phase of the time loop is pointed to."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

THEORY = Path(__file__).resolve().parents[1] / "docs" / "theory.md"
MODULES = ("cdm", "hybrid", "exact", "sleep", "contact", "contact_geometry", "broad_phase", "peaks", "hysteresis", "propagator")
PHASES = {
    "cdm": ["_contact_phase", "_velocity_update", "_step_energy", "_step_output", "_position_update", "_advance_awake"],
    "hybrid": ["_state_at_substep", "_free_span", "_propagate_free", "_hand_over_from_exact", "_cdm_substep",
               "_within_substep"],  # fmt: skip
    "exact": ["exact_point", "exact_motion", "enter_cdm", "leave_cdm"],
    "sleep": ["enter_awake", "catch_up", "rebalance"],
    "contact": ["_pair_frame", "_end_episode", "_normal_force", "_tangential_force", "_log_impact"],
}


def _pointers(text: str) -> set[tuple[str, str]]:
    """(module, function) of every `module.function` or `module.py: function` in the text."""
    found = {(m, f) for m, f in re.findall(r"`(?:solver/)?(%s)\.(\w+)`" % "|".join(MODULES), text) if f != "py"}
    found |= {(m, f) for m, f in re.findall(r"`(?:solver/)?(%s)\.py: (\w+)`" % "|".join(MODULES), text)}
    return found


def test_every_pointer_names_a_function_that_exists():
    pointers = _pointers(THEORY.read_text(encoding="utf-8"))
    assert len(pointers) > 30
    missing = [f"{m}.{f}" for m, f in sorted(pointers)
               if not hasattr(importlib.import_module(f"pounding_cli.solver.{m}"), f)]  # fmt: skip
    assert not missing, f"docs/theory.md points to functions that do not exist: {missing}"


def test_every_phase_of_the_loop_is_pointed_to():
    pointers = _pointers(THEORY.read_text(encoding="utf-8"))
    unnamed = [f"{m}.{f}" for m, names in PHASES.items() for f in names if (m, f) not in pointers]
    assert not unnamed, f"phases of the time loop docs/theory.md does not point to: {unnamed}"
