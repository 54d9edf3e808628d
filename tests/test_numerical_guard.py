"""The numerical guard: a NaN or infinite value anywhere in the state stops the run at the step
where it first appears, and the status names that step, its time and the building.

A non-finite value is injected into the compiled loop's inputs (a ground acceleration sample,
a pair's impact stiffness) of an otherwise sound model, and the failing step is predicted
from when that input first enters the equations of motion:
- the ground acceleration is linear between samples, so a NaN at sample j (t_j = j·Δt_g) enters
  every instant t with t/Δt_g in [j − 1, j + 1) (0·NaN is NaN: even where its weight is 0);
- the contact force of a pair enters at the step its impact log says the contact began.
The state at step n + 1 is the first with the NaN when the forces of step n hold it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli import api

from conftest import example_doc, load_doc

NAN_SAMPLE = 101  # t_j = 1.01 s: the NaN enters the ground motion at t = 1.00 s


def _scene(doc):
    scene = api.prepare(load_doc(doc))
    assert scene.ground.dt == 0.01
    return scene


def _wide_gap(**analysis):
    doc = example_doc()
    doc["contact"] = {"enabled": False}
    doc["analysis"].update({"duration": 2.0, **analysis})
    return doc


def test_cdm_stops_at_the_step_after_the_nan_enters_the_ground_motion():
    """Δt = 0.3 ms does not divide the record's 0.01 s: step n has t_n = 0.0003·n, and the first
    with t_n/0.01 ≥ 100 is n = ⌈100/0.03⌉ = 3334 (t = 1.0002 s, weight 0.02 on the NaN). Its
    forces make the state at step 3335 (t = 1.0005 s) NaN."""
    scene = _scene(_wide_gap(dt=0.0003, integrator="cdm"))
    scene.ground.acceleration[NAN_SAMPLE, 0] = np.nan
    result = api.execute(scene)
    assert result.status == (
        "failed: diverged at step 3335 (t = 1.0005 s): the state became NaN or infinite; Δt = 0.0003 s may be "
        "too large; first at building 'left', floor 1 (u_x)"
    )
    # the partial results end at the last output sample before it, all finite (stride 33: n = 3333)
    assert result.time[-1] == pytest.approx(3333 * 0.0003, abs=1e-12)
    for b in result.buildings.values():
        assert np.isfinite(b.displacement).all() and np.isfinite(b.velocity).all()


def test_the_hybrid_stops_at_the_exact_substep_that_made_the_state_nan():
    """The hybrid's exact substeps (length h, a divisor of 0.01 s) end on the sample instants;
    with the NaN at sample 104 the substep ending at t with t/0.01 ≥ 103 (t = 1.03 s, up to the
    rounding of t/0.01, which decides whether it is that substep or the next) takes it in.
    The output interval of 0.05 s puts that between two output samples (1.00 and 1.05 s), where
    the state used to go unchecked."""
    scene = _scene(_wide_gap(output_interval=0.05))
    grid = scene.grid
    assert grid.substep > 0
    h = grid.dt * grid.substep
    scene.ground.acceleration[104, 0] = np.nan
    result = api.execute(scene)
    k = next(k for k in range(10**6) if math.floor((k * h + h) / 0.01) >= 103)  # as the kernel rounds t/Δt_g
    step = (k + 1) * grid.substep
    assert abs((k + 1) * h - 1.03) <= h and step % grid.stride != 0, "between output samples"
    assert result.status.startswith(f"failed: diverged at step {step} (t = {step * grid.dt:.6g} s): the state became "
                                    "NaN or infinite;")  # fmt: skip
    assert result.status.endswith("first at building 'left', floor 1 (u_x)")
    assert result.diagnostics["cdm_steps"] == 0, "no contact: exact substeps throughout"
    assert result.time[-1] == pytest.approx(1.0) and np.isfinite(result.buildings["right"].displacement).all()


@pytest.mark.parametrize("integrator", ["hybrid", "cdm"])
def test_a_nan_contact_force_stops_the_run_and_names_the_building_that_hit(integrator):
    """The right building 2 mm from a wall along its side (the left one 0.5 m away never touches,
    and the wall is out of its reach): a NaN impact
    stiffness of the wall's first pair to touch makes the contact force NaN at the step the
    contact begins (from the impact log of the same run without it); the run stops at the next
    step and names the right building — the left one's DOFs, which come first, stay finite."""
    doc = _wide_gap(duration=4.0, integrator=integrator)
    doc["contact"] = {"enabled": True}
    doc["obstacles"] = [{"name": "wall", "polygon": [[8.5, -1.0], [24.5, -1.0], [24.5, -0.002], [8.5, -0.002]],
                         "elevation": [0.0, 10.0], "material": "concrete"}]  # fmt: skip
    clean = pound.run_model(load_doc(doc))
    first = np.sort(clean.contact.events, order="t_start")[0]
    assert clean.complete and (first["body_a"], first["body_b"]) == ("right", "wall")
    scene = api.prepare(load_doc(doc))
    scene.contact.pair_kn[first["pair"]] = np.nan
    result = api.execute(scene)
    n = round(first["t_start"] / scene.grid.dt)
    assert result.status.startswith(f"failed: diverged at step {n + 1} (t = {(n + 1) * scene.grid.dt:.6g} s): the "
                                    "state became NaN or infinite;")  # fmt: skip
    assert result.status.endswith("first at building 'right', floor 1 (u_x)")
    assert np.isfinite(result.buildings["left"].displacement).all()
