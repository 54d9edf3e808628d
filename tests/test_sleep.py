"""Per-building stepping (solver/sleep.py): through a contact phase, the buildings that cannot
touch anything are propagated exactly instead of by the CDM at the contact step.

The reference is the same run with every building carried by the CDM (sleep switched off). The
two integrate the same equations; they differ only where a building sleeps, by the CDM's own
truncation error over the steps it no longer takes: the leapfrog's phase error is
(ω·Δt)²/24 per unit of phase, with ω·Δt ≤ 2e-4 for these buildings at the contact step
(ω_max ≈ 60 rad/s, Δt ≈ 2.7 µs), about 2e-9, accumulated over the run's contact phases.
Measured on row_of_5 (python tests/test_sleep.py prints the table): displacements 1.8e-9 of
their largest value, velocities 3.1e-8, peaks ≤ 6.6e-9, impact forces and impulses 4e-9,
impact times 5e-11 s; accelerations and floor contact forces, which pass through the steep
front of an impact, 2.0e-7 and 3.5e-7. The tolerances below hold each a factor of 5 to 30
above these and far below anything a change of the physics would move (a contact step
halved moves the peaks by 1e-5, tests/test_bit_for_bit.py's history).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from pounding_cli.api import execute, prepare
from pounding_cli.bench.run import scene_files
from pounding_cli.solver import integrate

TOLERANCE = {"displacement": 1e-8, "velocity": 3e-7, "acceleration": 2e-6}
PEAK_TOLERANCE = 1e-7
FORCE_TOLERANCE = 1e-7


def _run(name: str, sleep: bool, monkeypatch):
    path = next(p for p in scene_files() if p.stem == name)
    with monkeypatch.context() as m:
        if not sleep:
            m.setattr(integrate, "may_sleep", lambda *args: False)
        return execute(prepare(path))


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    scale = float(np.max(np.abs(a)))
    return float(np.max(np.abs(a - b))) / scale if scale > 0 else float(np.max(np.abs(a - b)))


@pytest.fixture(scope="module")
def row_of_5():
    mp = pytest.MonkeyPatch()
    try:
        return _run("row_of_5", True, mp), _run("row_of_5", False, mp)
    finally:
        mp.undo()


def test_buildings_sleep_in_the_row(row_of_5):
    asleep, awake = row_of_5
    d, ref = asleep.diagnostics, awake.diagnostics
    assert d["sleeps"] > 0 and d["slept_building_steps"] > 0
    # some slept while others pounded and were then struck in the same phase: they woke
    assert d["wakes"] > 0
    assert ref["sleeps"] == ref["wakes"] == ref["slept_building_steps"] == 0
    # the same contact phases: the steps of the CDM are the same, only fewer buildings take them
    assert d["cdm_steps"] == ref["cdm_steps"] and d["exact_substeps"] == ref["exact_substeps"]
    # of the 5 buildings, more than one slept through most of the CDM's steps
    assert d["slept_building_steps"] > 1.0 * d["cdm_steps"]


def test_sleeping_buildings_match_the_run_that_carries_them_all(row_of_5):
    asleep, awake = row_of_5
    assert asleep.buildings.keys() == awake.buildings.keys()
    for name, ref in awake.buildings.items():
        got = asleep.buildings[name]
        for field, tol in TOLERANCE.items():
            assert _relative(getattr(ref, field), getattr(got, field)) <= tol, (name, field)
        for field in ("peak_displacement", "peak_acceleration", "interstorey_deflection"):
            assert _relative(getattr(ref, field), getattr(got, field)) <= PEAK_TOLERANCE, (name, field)
        for field in ("peak_storey_shear", "peak_column_shear", "peak_base_shear"):
            assert _relative(getattr(ref.forces, field), getattr(got.forces, field)) <= PEAK_TOLERANCE, (name, field)
        assert _relative(ref.forces.floor_contact, got.forces.floor_contact) <= 2e-6, name


def test_every_impact_is_found_at_its_time(row_of_5):
    asleep, awake = row_of_5
    a, b = awake.contact.events, asleep.contact.events
    assert len(a) == len(b) >= 30
    assert list(a["pair"]) == list(b["pair"])
    for field in ("t_start", "t_end"):
        assert np.max(np.abs(a[field] - b[field])) <= 1e-9, field  # s
    for field in ("peak_normal_force", "normal_impulse"):
        assert _relative(a[field], b[field]) <= FORCE_TOLERANCE, field


def test_the_energy_account_stays_closed(row_of_5):
    # a sleeping building's work is the exact propagator's, the hand-overs close the CDM's
    # trapezoids (sleep.py): the balance is the run's own (1.02e-8 of the input both ways)
    asleep, awake = row_of_5
    assert asleep.balance_error_ratio <= 1e-6
    assert asleep.balance_error_ratio == pytest.approx(awake.balance_error_ratio, rel=1e-3)
    assert _relative(awake.energy, asleep.energy) <= 1e-7


WALL = """
[[obstacles]]
name = "wall"
polygon = [[-0.47, -1.0], [-0.01, -1.0], [-0.01, 9.0], [-0.47, 9.0]]
elevation = [0.0, 9.0]
material = "concrete"
"""


def test_a_wall_beside_the_row(tmp_path, monkeypatch):
    # an obstacle belongs to no building (it never sleeps): the row's first building, 1 cm from
    # a wall, pounds it while the others sleep, as in the run that carries every building
    path = next(p for p in scene_files() if p.stem == "row_of_5")
    model = tmp_path / "row_and_wall.toml"
    model.write_text(path.read_text(encoding="utf-8") + WALL, encoding="utf-8")
    for record in path.parent.glob("*.mseed"):
        (tmp_path / record.name).symlink_to(record)
    runs = []
    for sleep in (True, False):
        with monkeypatch.context() as m:
            if not sleep:
                m.setattr(integrate, "may_sleep", lambda *args: False)
            runs.append(execute(prepare(model)))
    asleep, awake = runs
    assert asleep.diagnostics["sleeps"] > 0
    walls = [e for e in asleep.contact.events if "wall" in (e["body_a"], e["body_b"])]
    assert walls, "the wall is struck"
    a, b = awake.contact.events, asleep.contact.events
    assert len(a) == len(b)
    assert np.max(np.abs(a["t_start"] - b["t_start"])) <= 1e-9
    assert _relative(a["peak_normal_force"], b["peak_normal_force"]) <= FORCE_TOLERANCE
    for name, ref in awake.buildings.items():
        assert _relative(ref.peak_displacement, asleep.buildings[name].peak_displacement) <= PEAK_TOLERANCE, name


def test_which_building_a_contact_body_moves_with():
    # two 3-floor buildings; bodies: their six slabs, a wall (floor −1) and the storey of
    # building 1 struck beneath its floor 5 (virtual floor n_floors + 1 + 0, floor above: 4)
    from pounding_cli.solver.sleep import awake_record

    awake = awake_record(True, np.array([0, 3, 6]), np.array([0, 0, 1, 2, 3, 4, 5]), np.arange(7),
                         np.array([0, 1, 2, 3, 4, 5, -1, 7]), np.array([4]))  # fmt: skip
    assert list(awake.body_building) == [0, 0, 0, 1, 1, 1, -1, 1]
    assert list(awake.column_start) == [0, 4, 7] and list(awake.gauge_start) == [0, 3, 6]
    assert list(awake.runs[0]) == [0, 6, 0, 7, 0, 6, 0, 2] and awake.n_runs[0] == 1 and awake.n_sleepers[0] == 0


@pytest.mark.parametrize(
    "case, expected",
    [
        ({}, True),
        ({"n_members": 2}, False),  # the members' return map works on the whole structure
        ({"links": 1}, False),  # an isolated building's damping links
        ({"levels": 0}, False),  # no approach levels: contact phases run whole substeps
        ({"n_pairs": 0}, False),
        ({"buildings": 1}, False),
    ],
)
def test_who_may_sleep(case, expected):
    settings = {"n_members": 0, "links": 0, "levels": 3, "n_pairs": 4, "buildings": 3} | case
    propagators = SimpleNamespace(levels=SimpleNamespace(phi=np.zeros((settings["levels"] + 1, 1, 1, 1))))
    structure = SimpleNamespace(damping=SimpleNamespace(link=np.zeros((settings["links"], 6, 6))))
    floor_start = np.arange(settings["buildings"] + 1) * 3
    assert integrate.may_sleep(propagators, settings["n_pairs"], settings["n_members"], structure,
                               floor_start) is expected  # fmt: skip


if __name__ == "__main__":  # the measured differences quoted in the module docstring
    mp = pytest.MonkeyPatch()
    asleep, awake = _run("row_of_5", True, mp), _run("row_of_5", False, mp)
    for field in TOLERANCE:
        print(field, max(_relative(getattr(awake.buildings[n], field), getattr(asleep.buildings[n], field))
                         for n in awake.buildings))  # fmt: skip
