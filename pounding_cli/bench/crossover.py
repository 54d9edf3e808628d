"""Where sweep and prune starts to pay: the contact kernels' cost per call, both broad phases.

`python -m pounding_cli.bench.crossover` prints, for the shipped scenes with contact and rows
of 2–40 buildings, the cost of one contact step (contact_forces) and of one "may a contact
begin within the horizon" check (contact_possible_within) with every pair tested and with
sweep and prune, on the states of the first 0.8 s of a CDM run (Δt = 2·10⁻⁵ s, every 20th
step). Times are thread CPU time, the best of several repeats (the machine is shared), ns per
call. tunables.SWEEP_PAIRS_PER_MEMBER is chosen from this table.
"""

from __future__ import annotations

import copy
import sys
import time
from dataclasses import dataclass

import numpy as np

from ..api import Scene, prepare
from ..model import read_document, validate_model
from ..solver import simulate
from ..solver.broad_phase import sweep_arrays
from ..solver.contact import contact_forces, contact_possible_within
from ..solver.integrate import bounding_boxes, contact_state
from .run import scene_files
from .stability import _row

ROWS = (2, 3, 4, 5, 6, 8, 10, 20, 40)
SCENES = ("paper_pounding", "corner", "isolated")
DT = 2e-5
EVERY = 20  # steps between the states measured
STEPS = 40_000  # 0.8 s
CALL_TIME = 0.02  # s: each timed call passes over the states as often as fills this (the
# dispatch of a compiled function taking these many arrays costs about a millisecond)


@dataclass(frozen=True)
class Crossover:
    scene: str
    pairs: int
    members: int  # bodies of the sweep groups (an obstacle once per level it spans)
    contact_all_ns: float
    contact_sweep_ns: float
    horizon_all_ns: float
    horizon_sweep_ns: float


def _drivers():
    """Compiled loops calling the two kernels on every state (made on first use: numba's
    compilation is not needed for the rest of the bench)."""
    from numba import njit

    @njit
    def contact_loop(passes, states, dt, contact, v):
        total = 0
        for _ in range(passes):
            for k in range(states.shape[0]):
                total += contact_forces(k, dt, states[k], v, v, contact)
        return total

    @njit
    def horizon_loop(passes, states, horizon, contact, v):
        total = 0
        for _ in range(passes):
            for k in range(states.shape[0]):
                total += contact_possible_within(horizon, states[k], v, v, contact)
        return total

    return contact_loop, horizon_loop


def _states(scene: Scene) -> np.ndarray:
    """Displacements (n_states, n_dof + 3) every EVERY steps of a CDM run of STEPS steps."""
    response = simulate(scene.system, scene.ground.acceleration, scene.ground.dt, DT, EVERY, STEPS,
                        contact=scene.contact)  # fmt: skip
    n_dof = scene.system.n_dof
    states = np.zeros((response.displacement.shape[0], n_dof + 3))
    states[:, :n_dof] = response.displacement
    return states


def _best_ns(loops, n_states: int, repeats: int) -> list[float]:
    """ns per state of each loop(passes), the best of `repeats` calls of about CALL_TIME each,
    the loops taking turns (so that all see the same spells of a busy machine)."""
    passes = []
    for loop in loops:
        t0 = time.thread_time()
        loop(1)
        passes.append(max(1, int(CALL_TIME / max(time.thread_time() - t0, 1e-6))))
    best = [np.inf] * len(loops)
    for _ in range(repeats):
        for k, loop in enumerate(loops):
            t0 = time.thread_time()
            loop(passes[k])
            best[k] = min(best[k], time.thread_time() - t0)
    return [1e9 * b / (n_states * p) for b, p in zip(best, passes)]


def measure(name: str, scene: Scene, repeats: int = 20) -> Crossover:
    contact_loop, horizon_loop = _drivers()
    c = scene.contact
    states = _states(scene)
    zero = np.zeros(states.shape[1])
    loops = []
    for sweep in (False, True):
        record = contact_state(c, states.shape[1] - 3, sweep)

        def contact(passes, record=record):
            record.n_events[0] = 0  # impacts logged
            contact_loop(passes, states, DT, record, zero)

        def horizon(passes, record=record):
            horizon_loop(passes, states, 2e-3, record, zero)

        loops += [contact, horizon]
    contact_all, horizon_all, contact_sweep, horizon_sweep = _best_ns(loops, states.shape[0], repeats)
    members = sweep_arrays(c.pair_a, c.pair_b, c.body_floor, bounding_boxes(c), True).group_body.size
    return Crossover(name, c.n_pairs, members, contact_all, contact_sweep, horizon_all, horizon_sweep)


EVERY_PAIR = 1e6
"""contact.reach (m) beyond any row here: every two floors at one level stay candidates
(city/reach.py would drop those of buildings far apart), as this bench measures the broad
phases against them."""


def scenes(rows: tuple[int, ...] = ROWS, names: tuple[str, ...] = SCENES):
    """(name, prepared scene) of the shipped scenes named and rows of buildings."""
    files = {p.stem: p for p in scene_files()}
    for name in names:
        yield name, prepare(files[name])
    for n in rows:
        doc = _row(n)(copy.deepcopy(read_document(files["row_of_5"])))
        doc.setdefault("contact", {})["reach"] = EVERY_PAIR  # the broad phase's cost against every pair of a level
        yield f"row of {n}", prepare(validate_model(doc, files["row_of_5"]))


def markdown(points: list[Crossover]) -> str:
    lines = ["| scene | candidate pairs | group members | pairs per member | contact step, all pairs (ns) | "
             "sweep and prune (ns) | ratio | horizon check, all pairs (ns) | sweep and prune (ns) | ratio |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]  # fmt: skip
    for p in points:
        lines.append(f"| {p.scene} | {p.pairs} | {p.members} | {p.pairs / p.members:.2f} | {p.contact_all_ns:.0f} | "
                     f"{p.contact_sweep_ns:.0f} | {p.contact_sweep_ns / p.contact_all_ns:.2f} | {p.horizon_all_ns:.0f} | "
                     f"{p.horizon_sweep_ns:.0f} | {p.horizon_sweep_ns / p.horizon_all_ns:.2f} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def main() -> None:
    points = []
    for name, scene in scenes():
        print(name, file=sys.stderr, flush=True)
        points.append(measure(name, scene))
    print(markdown(points), end="")


if __name__ == "__main__":
    main()
