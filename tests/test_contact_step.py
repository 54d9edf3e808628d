"""The automatic contact step follows the contacts a scene is likely to make
(assembly/contact.py: likely_contact_line, omega_step), and a run that meets a stiffer contact
repeats itself at the step that contact needs (api.execute)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from shapely import affinity
from shapely.geometry import Polygon

from pounding_cli.api import execute, prepare
from pounding_cli.assembly.contact import likely_contact_line
from pounding_cli.solver.tunables import CONTACT_DT_FRACTION, MAX_RERUNS, RERUN_MARGIN, STEP_BOUND
from pounding_cli.bench.metrics import compare

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "pounding_cli" / "bench" / "scenes"
INPUTS = ROOT / "inputs"


def _pressed_line(a: Polygon, b: Polygon, depth: float) -> float:
    """Shapely's contact line of a moved along −x into b until they overlap `depth` deep
    along x: the distance between the two points where the boundaries cross."""
    gap = b.bounds[0] - a.bounds[2]
    moved = affinity.translate(a, xoff=gap + depth)
    crossing = moved.boundary.intersection(b.boundary)
    points = np.array([[p.x, p.y] for p in getattr(crossing, "geoms", [crossing])])
    return float(np.max(np.hypot(*(points[:, None, :] - points[None, :, :]).reshape(-1, 2).T)))


@pytest.mark.parametrize("turn", [1.0, 2.0, 5.0, 20.0, 44.0])
def test_likely_line_bounds_a_turned_corner_pressed_into_a_face(turn):
    """A square turned by φ, its corner pressed δ = 1 mm into a face: the true contact line is
    δ·(cot φ + tan φ); the estimate takes the longer edge's δ·cot φ twice, so it lies between
    the true line and twice it (2cos²φ of it)."""
    square = affinity.rotate(Polygon([(0, 0), (8, 0), (8, 8), (0, 8)]), turn, origin="centroid")
    face = Polygon([(20, -10), (36, -10), (36, 18), (20, 18)])
    depth = 1e-3
    true_line = _pressed_line(square, face, depth)
    phi = np.radians(turn)
    assert true_line == pytest.approx(depth * (1 / np.tan(phi) + np.tan(phi)), rel=1e-6)
    guess = likely_contact_line(np.array(square.exterior.coords[:-1]), np.array(face.exterior.coords[:-1]), depth)
    assert true_line <= guess <= 2.0 * true_line
    assert guess == pytest.approx(2.0 * np.cos(phi) ** 2 * true_line, rel=1e-6)


def test_likely_line_of_parallel_faces_is_their_shorter_edge_twice():
    """Parallel faces touch along their whole common length whatever the depth: the estimate
    is (twice) the shorter edge, which contact_arrays caps at the smaller diameter."""
    a = np.array([[0.0, 0.0], [8.0, 0.0], [8.0, 6.0], [0.0, 6.0]])
    b = np.array([[8.05, -1.0], [20.0, -1.0], [20.0, 9.0], [8.05, 9.0]])
    assert likely_contact_line(a, b, 1e-3) == pytest.approx(2 * 8.0)
    assert likely_contact_line(a, b, 1e-9) == pytest.approx(2 * 8.0)


def test_corner_scene_steps_by_its_likely_contacts_at_the_same_peaks():
    """The corner scene (a building turned 2°, corner impacts): the automatic contact step
    follows k_T (its corner contacts' k_N·ℓ stays below it), 7× the step the outlines' upper
    bound (k_N × the slab's diagonal) would take; no contact it meets is stiffer, so it runs
    once; and its peaks agree with the run at the upper bound's step to 1e-5 (measured
    1.9e-6 and 4e-8 against the bench's CDM reference: both far below the scene's 2.4e-4
    sensitivity to its input, docs/bench/bench.md)."""
    scene = prepare(SCENES / "corner.toml")
    contact = scene.contact
    assert contact.omega_step == pytest.approx(np.sqrt(contact.pair_kt * contact.pair_mobility).max(), rel=1e-12)
    assert contact.omega_step / contact.omega_max == pytest.approx(0.140, abs=0.001)
    likely = execute(scene)
    assert likely.diagnostics["contact_reruns"] == 0
    assert likely.diagnostics["contact_omega_seen"] <= likely.diagnostics["contact_omega_step"] * (1 + 1e-9)
    upper = execute(dataclasses.replace(scene, grid=scene.regrid(contact.omega_max)))
    # each step is rounded to divide the substep, up to 1/8 finer (timestep.py)
    assert likely.diagnostics["dt"] / upper.diagnostics["dt"] == pytest.approx(contact.omega_max / contact.omega_step,
                                                                                rel=0.125)  # fmt: skip
    assert likely.contact.impact_count == upper.contact.impact_count
    errors = compare(likely, upper)
    assert errors.peak_deflection < 1e-5 and errors.peak_force < 1e-5


def test_a_run_that_meets_a_stiffer_contact_repeats_at_its_step():
    """The paper's buildings face to face, told to expect contacts 5× softer than they are:
    the first run meets the face contact, and the run is repeated at the step of the stiffest
    contact it met; the result is the run prepared at that step, bit for bit. The repeated
    run meets the same contacts on its finer grid: the stiffest of them within 1e-6 (measured
    1.1e-7: the longest contact line sampled at other instants), far inside RERUN_MARGIN."""
    scene = prepare(INPUTS / "paper_pounding.toml")
    contact = scene.contact
    soft = 0.2 * contact.omega_max
    told = dataclasses.replace(scene, contact=dataclasses.replace(contact, omega_step=soft), grid=scene.regrid(soft))
    result = execute(told)
    d = result.diagnostics
    assert d["contact_reruns"] == 1
    seen = d["contact_omega_seen"]
    assert seen > RERUN_MARGIN * soft
    assert d["contact_omega_step"] == pytest.approx(seen, rel=1e-6)
    direct = execute(dataclasses.replace(scene, grid=scene.regrid(d["contact_omega_step"]), regrid=None))
    assert direct.diagnostics["dt"] == d["dt"]
    for name, building in result.buildings.items():
        np.testing.assert_array_equal(building.interstorey_deflection, direct.buildings[name].interstorey_deflection)
    assert result.contact.peak_force == direct.contact.peak_force
    assert d["wall_time_s"] > direct.diagnostics["wall_time_s"] * 1.01  # both attempts counted


def test_validate_says_which_contacts_the_step_follows():
    """`pound validate`: the likely contacts' ω beside the upper bound, and the Δt line says
    the automatic step follows them (the numbers are the JSON's)."""
    import json

    from typer.testing import CliRunner

    from pounding_cli.cli import app

    runner = CliRunner()
    path = str(SCENES / "corner.toml")
    info = json.loads(runner.invoke(app, ["validate", path, "--json"]).stdout)
    c, a = info["contact"], info["analysis"]
    assert c["omega_likely_rad_s"] == pytest.approx(0.140 * c["omega_max_rad_s"], rel=0.01)
    assert a["contact_step_limit_s"] == pytest.approx(2 / c["omega_likely_rad_s"], rel=1e-12)
    assert a["dt_s"] <= a["dt_auto_fraction"] * a["contact_step_limit_s"]
    lines = runner.invoke(app, ["validate", path], env={"COLUMNS": "80"}).stdout.splitlines()
    assert (f"  likely contacts (by the angles between the slabs' edges): ω_contact = {c['omega_likely_rad_s']:.4g} "
            f"rad/s, 2/ω_contact = {a['contact_step_limit_s']:.4g} s") in lines  # fmt: skip
    (dt_line,) = [ln for ln in lines if ln.startswith("  Δt = ")]
    assert f"0.00625 × 2/ω_contact of the likely contacts — the contact governs ({a['contact_step_limit_s']:.4g} s" in dt_line


def test_a_given_step_is_never_repeated():
    """Δt given in the model: the run keeps it, whatever contacts it meets."""
    from pounding_cli.model import read_document, validate_model

    doc = read_document(INPUTS / "paper_pounding.toml")
    doc["analysis"]["dt"] = 5e-6
    scene = prepare(validate_model(doc, INPUTS / "paper_pounding.toml"))
    assert scene.regrid is None


def test_the_step_bound_keeps_the_contact_step_below_half_the_stability_limit():
    assert CONTACT_DT_FRACTION / STEP_BOUND == pytest.approx(0.5)
    assert MAX_RERUNS >= 1
