"""Slab–storey pounding (issue 23, slice 2): the struck storey as a body interpolated between
two floors, the struck columns' local flexibility in series with the overlap law, and the runs
that use them. Each check is against something written independently of the code under test:
the transpose of the map (virtual work), a finite-element static solution, the energy balance,
and the slab–slab contact that a slab–storey contact must become at the floors."""

from __future__ import annotations

from pathlib import Path

import numba
import numpy as np
import pytest

from pounding_cli.api import prepare, run_model
from pounding_cli.assembly.storey_contact import point_load_factor, storey_shape
from pounding_cli.solver.records import StoreyBodies
from pounding_cli.solver.storey_bodies import extend, hand_back

from conftest import load_doc, model_doc, square_building
from fe_frame import static_point_load

ROOT = Path(__file__).parents[1]


@numba.njit
def _extend(x, storeys, out):
    extend(x, storeys, out)


@numba.njit
def _hand_back(force, storeys, n):
    hand_back(force, storeys, n)


def test_handing_forces_back_is_the_transpose_of_the_storeys_motion() -> None:
    """Virtual work: for any floor motion x and any generalized forces Q on the virtual floors,
    Q·(extend x)[virtual] = (hand_back Q)·x, with and without the struck columns' local modes
    moving the outlines. Both sides are sums of a few dozen products of O(1) numbers: equal to
    1e-12 relative (rounding)."""
    rng = np.random.default_rng(23)
    n_floors, n_s = 7, 5
    n = 3 * n_floors + 3
    below = np.array([n_floors, 0, 2, 4, 5], dtype=np.int64)  # the first: the ground's slot
    above = np.array([1, 1, 3, 5, 6], dtype=np.int64)
    shape = np.array([storey_shape(xi) for xi in rng.uniform(0.05, 0.95, n_s)])
    arm = rng.normal(0, 3, (n_s, 2))
    # local modes (assembly/local_modes.py): 0, 2, 1, 3 and 0 on the five bodies, on pseudo-floors 2, 4 and 6
    first = np.array([0, 0, 2, 3, 6, 6], dtype=np.int64)
    storeys = StoreyBodies(below, above, shape, arm, np.zeros(n + 3 * n_s), np.zeros(n + 3 * n_s), np.zeros(n + 3 * n_s),
                           first, np.array([2, 4, 6, 2, 4, 6], dtype=np.int64), rng.normal(0, 1, 6),
                           rng.normal(0, 0.5, (6, 2)), rng.normal(0, 3, (6, 4)), np.zeros((6, 2, 2)), np.zeros((6, 2)),
                           np.arange(n_s, dtype=np.int64), np.zeros((n_s, 2)), np.ones(n_s), np.zeros((n_s, 2, 2)),
                           np.zeros((n_s, 2, 2)), np.zeros((n_s, 2)), np.full(n_s, -1, dtype=np.int64), np.zeros((0, 14)))  # fmt: skip
    for _ in range(20):
        x = rng.normal(0, 1, n)
        x[-3:] = 0.0  # the ground
        extended = np.zeros(n + 3 * n_s)
        _extend(x, storeys, extended)
        assert np.array_equal(extended[:n], x)
        q = rng.normal(0, 1, 3 * n_s)
        force = np.zeros(n + 3 * n_s)
        force[n:] = q
        _hand_back(force, storeys, n)
        assert np.all(force[n:] == 0.0)
        assert force[-3 - 3 * n_s : n].tolist() == [0.0, 0.0, 0.0]  # nothing to the ground
        assert q @ extended[n:] == pytest.approx(force[:n] @ x, rel=1e-12, abs=1e-12)


def test_the_storeys_outline_moves_with_the_fixed_fixed_shape() -> None:
    """At ξ the outline translates by (1 − s)·u_below + s·u_above with s = 3ξ² − 2ξ³, and a
    turn θ of the floor below moves it as a rigid arm d = G_above − G_below would: checked
    against those formulas at the floors' mass centres, to 1e-15 m."""
    storeys = StoreyBodies(np.array([0]), np.array([1]), np.array([storey_shape(0.3)]), np.array([[1.5, -2.0]]),
                           *(np.zeros(9 + 3) for _ in range(3)), np.zeros(2, dtype=np.int64),
                           np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, 2)), np.zeros((0, 4)),
                           np.zeros((0, 2, 2)), np.zeros((0, 2)), np.zeros(1, dtype=np.int64), np.zeros((1, 2)),
                           np.ones(1), np.zeros((1, 2, 2)), np.zeros((1, 2, 2)), np.zeros((1, 2)),
                           np.full(1, -1, dtype=np.int64),
                           np.zeros((0, 14)))  # fmt: skip
    x = np.array([0.01, -0.02, 0.001, 0.03, 0.04, -0.002, 0.0, 0.0, 0.0])
    out = np.zeros(12)
    _extend(x, storeys, out)
    s = 3 * 0.3**2 - 2 * 0.3**3
    expect_x = (1 - s) * (0.01 - 0.001 * -2.0) + s * 0.03
    expect_y = (1 - s) * (-0.02 + 0.001 * 1.5) + s * 0.04
    assert out[9:] == pytest.approx([expect_x, expect_y, (1 - s) * 0.001 + s * -0.002], abs=1e-15)


@pytest.mark.parametrize("xi", [0.1, 0.25, 0.5, 0.9])
def test_local_flexibility_is_the_clamped_columns_point_load_deflection(xi: float) -> None:
    """The compliance pound puts in series with the overlap law, point_load_factor(ξ)/(12EI/h³),
    against the deflection under a unit point load of a clamped–clamped column of 16 Hermite
    elements (tests/fe_frame.py, exact for a point load at a node): 1e-10 relative."""
    ei, h = 21e9 * 0.35**4 / 12, 3.5
    pound = point_load_factor(xi) / (12 * ei / h**3)
    assert pound == pytest.approx(static_point_load(ei, h, xi, 16)["deflection"], rel=1e-10)


@pytest.mark.parametrize("xi", [0.1, 0.25, 0.5, 0.9])
def test_fixed_end_forces_are_the_clamped_columns(xi: float) -> None:
    """The impact's share of a struck column's end shears and moments (fixed–fixed point load,
    column_demand.fixed_end_forces) against the support reactions of a clamped column of 16
    Hermite elements under the same load (tests/fe_frame.py: exact for a load at a node), and
    the moment under the load against statics (M_load = V_bottom·a − M_bottom): 1e-10 relative."""
    from pounding_cli.results.column_demand import fixed_end_forces

    ei, h, p = 21e9 * 0.35**4 / 12, 3.5, 1.0e5
    v_bottom, v_top, m_bottom, m_top, m_load = fixed_end_forces(p, xi * h, h)
    fe = static_point_load(ei, h, xi, 16, P=p)
    assert (abs(fe["V_bottom"]), abs(fe["V_top"])) == pytest.approx((v_bottom, v_top), rel=1e-10)
    assert (abs(fe["M_bottom"]), abs(fe["M_top"])) == pytest.approx((m_bottom, m_top), rel=1e-10)
    assert v_bottom + v_top == pytest.approx(p, rel=1e-14)
    assert m_load == pytest.approx(v_bottom * xi * h - m_bottom, rel=1e-10)


def test_the_struck_columns_and_their_series_law_in_the_shipped_example() -> None:
    """inputs/mismatched_floors.toml: the low building's roof (9 m) strikes the tall building's
    façade x = 8 m in storey 3 (7–10.5 m) at ξ = 4/7, along its whole 8 m, where columns C7–C9
    (30 × 30 cm, E = 21 GPa) stand. Their point-load stiffnesses add, in series with k_N·L: the
    pair's k_N is (1/k_N,auto + C·L)⁻¹, from the hand formulas to 1e-12. (The tall building's floor
    2 at 7 m and the low one's floor 2 at 6 m strike each other's storeys, one interface seen
    from both slabs: each of those two pairs has half the law.)"""
    import tomllib

    from pounding_cli.assembly.contact import impact_stiffness
    from pounding_cli.model import Material

    doc = tomllib.loads((ROOT / "inputs" / "mismatched_floors.toml").read_text())
    scene = prepare(load_doc(doc))
    contact = scene.contact
    index = next(i for i, p in enumerate(contact.pairs) if p.body_a == "low" and p.floor_a == 3)
    info = contact.pairs[index]
    assert (info.kind, info.body_b, info.storey, info.xi) == ("slab-storey", "tall", 3, pytest.approx(4 / 7, abs=1e-12))
    body = contact.storeys[index - (contact.n_pairs - len(contact.storeys))]
    tall = scene.system.buildings[0]
    assert sorted(tall.column_lines[tall.columns[i].line].name for i in body.columns) == ["C7", "C8", "C9"]
    assert body.line == pytest.approx(8.0, abs=1e-12)
    xi = 4 / 7
    k_column = 21e9 * 0.30**4 / 3.5**3  # 12EI/h³ with I = b⁴/12
    compliance = 4 * xi**3 * (1 - xi) ** 3 / (3 * k_column)
    assert body.compliance_normal == pytest.approx(compliance, rel=1e-12)
    concrete = Material(elastic_modulus=21e9, poisson_ratio=0.2)
    k_n, _ = impact_stiffness(concrete, concrete)
    assert contact.pair_kn[index] == pytest.approx(1 / (1 / k_n + compliance * 8.0), rel=1e-12)
    shared = [i for i, p in enumerate(contact.pairs) if (p.body_a, p.floor_a) in {("tall", 2), ("low", 2)}]
    assert len(shared) == 2
    for i in shared:
        body = contact.storeys[i - (contact.n_pairs - len(contact.storeys))]
        assert contact.pair_kn[i] == pytest.approx(1 / (2 / k_n + body.compliance_normal * body.line), rel=1e-12)


def test_the_shipped_example_pounds_slab_to_storey_with_a_closed_energy_balance() -> None:
    """The shipped example finds its impacts where the issue says (the low roof into the tall
    building's storey 3 at ξ = 0.571; the tall building's floor 2 into the low one's storey 3 at
    ξ = 1/3), and the energy balance (input = kinetic + strain + damping + contact work, the
    struck storeys' forces handed to the floors by the transpose of their motion) closes to
    1e-6 of the input, as for every other contact scene."""
    import tomllib

    doc = tomllib.loads((ROOT / "inputs" / "mismatched_floors.toml").read_text())
    result = run_model(load_doc(doc), output=None)
    events = result.contact.events
    assert events.size >= 5
    struck = {(e["body_b"], int(e["storey_b"]), round(float(e["xi"]), 3)) for e in events}
    assert struck == {("tall", 3, 0.571), ("low", 3, 0.333)}
    assert abs(result.diagnostics["balance_error_ratio"]) <= 1e-6


def _aligned_and_shifted(shift: float) -> tuple[dict, dict]:
    """The paper's pair of 4 and 3 storeys 1 cm apart (3 m storeys), and the same with the right
    building raised by `shift` m: its slabs then strike the left one's storeys just above its
    floors, and the left's strike its storeys just below its floors."""
    docs = []
    for dz in (0.0, shift):
        left = square_building("left", storeys=4)
        right = square_building("right", storeys=3, origin=(8.01, 0.0))
        right["base_elevation"] = dz
        docs.append(model_doc(left, right, duration=12.0, dt=2e-5))
    return docs[0], docs[1]


@pytest.mark.parametrize("shift", [2e-3, -2e-3])
def test_slab_to_storey_becomes_slab_to_slab_at_the_floors(shift: float) -> None:
    """Continuity: 2 mm off the floors (ξ = 1 − 6.7e-4 and 6.7e-4), the two slab–storey
    contacts at each level (each slab into the other's storey, sharing the interface's law)
    act as the one slab–slab contact of aligned floors: s(ξ) differs from 1 or 0 by 3ξ'² =
    1.3e-6 and the columns' point-load compliance is 4ξ'³ ≈ 1e-9 of the storey's, so on one
    fixed time grid the impulses, peak forces and peak displacements agree to 1e-4 relative
    (measured: ≤ 7e-6 raised, ≤ 2.2e-5 lowered; what remains is the 2 mm the slabs' contact
    moved and the weights 1 − s ≈ 1.3e-6 of the floors' turns)."""
    aligned, shifted = (run_model(load_doc(d), output=None) for d in _aligned_and_shifted(shift))
    # raised, every level has two (each slab inside the other's storey); lowered, the right
    # building's roof lies 2 mm below the left's floor 3, which is above its roof: one there
    assert aligned.diagnostics["storey_pairs"] == 0 and shifted.diagnostics["storey_pairs"] == (6 if shift > 0 else 5)
    one, two = aligned.contact.events, shifted.contact.events
    assert one.size > 0 and two.size >= one.size
    for e in one:  # the parts of each episode (one per slab–storey pair) start together and add up to it
        level = two[np.abs(two["elevation"] - e["elevation"]) < 0.01]
        halves = level[np.abs(level["t_start"] - e["t_start"]) < 1e-3]
        assert halves.size == (2 if shift > 0 or e["elevation"] < 8.0 else 1)
        assert np.sum(halves["normal_impulse"]) == pytest.approx(e["normal_impulse"], rel=1e-4)
        assert np.sum(halves["peak_normal_force"]) == pytest.approx(e["peak_normal_force"], rel=1e-4)
    for name in ("left", "right"):
        a, s = aligned.buildings[name], shifted.buildings[name]
        assert s.peak_displacement == pytest.approx(a.peak_displacement, rel=1e-4, abs=1e-9)


@pytest.mark.parametrize("capacity", [[0.0, 1e5], [1e5]])
def test_a_shear_capacity_that_is_not_two_positive_forces_is_refused(tmp_path, capacity) -> None:
    """shear_capacity is [V_x, V_y] in N, each > 0: anything else exits 2 naming the file and the field."""
    import json
    import subprocess
    import sys
    import tomllib

    doc = tomllib.loads((ROOT / "inputs" / "mismatched_floors.toml").read_text())
    doc["buildings"][0]["floors"][0]["column_grid"]["shear_capacity"] = capacity
    for component in doc["excitation"]["record"].values():
        if isinstance(component, dict):
            component["file"] = str(ROOT / "inputs" / component["file"])
    path = tmp_path / "model.json"
    path.write_text(json.dumps(doc))
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "validate", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert str(path) in proc.stderr and "buildings[0].floors[0].column_grid.shear_capacity" in proc.stderr


def test_the_plan_view_moves_a_struck_storey_as_the_solver_does(tmp_path) -> None:
    """The report's struck-storey outline (report/geometry.storey_displacement_at) moves as the
    solver's virtual floor (solver/storey_bodies.extend) for the stored floor motion at a sample:
    both are (1 − s)·T·q_below + s·q_above, written twice (to 1e-15 m)."""
    import tomllib

    from pounding_cli.report import open_run
    from pounding_cli.report.geometry import plan_geometry, storey_displacement_at
    from pounding_cli.solver.integrate import storey_bodies

    doc = tomllib.loads((ROOT / "inputs" / "mismatched_floors.toml").read_text())
    doc["analysis"]["duration"] = 14.0
    run_model(load_doc(doc), output=tmp_path / "m.h5")
    run = open_run(tmp_path / "m.h5")
    geometry = plan_geometry(run)
    scene = prepare(load_doc(doc))
    sample = int(round(13.85 / run.result.time[1]))  # during the impacts
    t = float(run.result.time[sample])
    x = np.concatenate([b.displacement[sample].ravel() for b in run.result.buildings.values()] + [np.zeros(3)])
    storeys = storey_bodies(scene.contact, x.size - 3)
    out = np.zeros(storeys.u.size)
    _extend(x, storeys, out)
    for k, body in enumerate(scene.contact.storeys):
        name = scene.system.buildings[body.crossing.struck].name
        report = storey_displacement_at(run, geometry, name, body.crossing.storey, body.crossing.xi, t)
        assert report == pytest.approx(out[x.size + 3 * k : x.size + 3 * k + 3], abs=1e-15)


def test_the_report_flags_struck_columns_past_their_capacity(tmp_path) -> None:
    """`pound report` lists each column struck between its floors once, with the largest of its
    rows of /impacts/column_demand (recomputed here from the rows), and flags a ratio ≥ 1."""
    import tomllib

    from typer.testing import CliRunner

    from pounding_cli.cli import app
    from pounding_cli.report import summary

    doc = tomllib.loads((ROOT / "inputs" / "mismatched_floors.toml").read_text())
    doc["analysis"]["duration"] = 16.0
    result = run_model(load_doc(doc), output=tmp_path / "m.h5")
    rows = result.contact.column_demand
    struck = summary(tmp_path / "m.h5")["impacts"]["struck_columns"]
    assert sorted((c["building"], c["column"]) for c in struck) == sorted({(str(r["building"]), str(r["column"])) for r in rows})
    for c in struck:
        mine = rows[(rows["building"] == c["building"]) & (rows["column"] == c["column"])]
        whole = max(abs(mine[f"shear_{e}_{a}"]).max() for e in ("bottom", "top") for a in "xy")
        assert c["shear_N"] == whole and c["impacts"] == mine.size
        if c["building"] == "tall":  # 150 kN given
            assert c["ratio"] == pytest.approx(float(np.max(mine["ratio"])), rel=1e-15) and c["exceeds"] == (c["ratio"] >= 1)
        else:
            assert c["ratio"] is None and c["capacity_N"] is None
    text = CliRunner().invoke(app, ["report", str(tmp_path / "m.h5")]).stdout
    assert "Columns struck between floors" in text and "≥ 1 !" in text
    assert "inertia is not in it" in text  # the demands' limit is said where they are read
