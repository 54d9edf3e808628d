"""Storey shears and column forces (results/forces.py, assembly/force_gauges.py,
solver/force_peaks.py) against physics checked independently of pound's own assembly.

Tolerances: every check below compares two sums of a few dozen float64 products of the same
stored numbers (displacements, accelerations, velocities), taken in different orders, so they
agree to a few ulps of the largest term: measured 1e-16 to 4e-15 of the scale each states.
1e-12 leaves a thousandfold margin for other machines and scenes and still fails at once on
any error of physics (a missed member, a wrong lever arm, a sign), which moves the residual to
order 1.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from conftest import INPUTS, load_doc, model_doc, square_building

from pounding_cli import api
from pounding_cli.assembly import assemble
from pounding_cli.model import load_model
from pounding_cli.results.equilibrium import about_origin, worst_residual
from pounding_cli.results.hdf5 import read_hdf5, write_hdf5

ROUNDING = 1e-12
E = 21e9  # Pa, conftest's concrete


def run(doc: dict, **analysis):
    doc["analysis"] = {**doc.get("analysis", {}), **analysis}
    return api.run_model(load_doc(doc))


def rotation(phi: float) -> np.ndarray:
    return np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])


def cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """z-component of r × f over the last axis."""
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


# --- a linear building, rotated in plan, eccentric, with rotated rectangular columns ----------
PHI, COLUMN_ANGLE, ORIGIN, ECC, SECTION, H = 30.0, 20.0, (3.0, -2.0), (0.7, -0.4), (0.3, 0.5), 3.0


@pytest.fixture(scope="module")
def linear():
    building = square_building(storeys=2, eccentricity=ECC, origin=ORIGIN, rotation=PHI, section=SECTION)
    building["floors"][0]["column_grid"]["angle"] = COLUMN_ANGLE
    return run(model_doc(building), duration=2.0, column_force_histories=True)


def hand_forces(result):
    """Storey shears and column shears from K·u assembled here, column by column, from the
    columns' positions, E, sections and angles (12EI/h³ per local axis), not by pound's assembly."""
    b = result.buildings["b"]
    u = b.displacement  # (nt, 2, 3) global, at the mass centres
    phi, alpha = math.radians(PHI), math.radians(PHI + COLUMN_ANGLE)
    rot = rotation(phi)
    centre = np.asarray(ORIGIN) + rot @ (np.array([4.0, 4.0]) + ECC)  # the slab's centroid, shifted: both floors
    bx, by = SECTION
    k = np.array([E * by * bx**3 / H**3, E * bx * by**3 / H**3])
    axes = np.array([[math.cos(alpha), math.sin(alpha)], [-math.sin(alpha), math.cos(alpha)]])  # rows: local x, y
    nt = u.shape[0]
    zero = np.zeros((nt, 3))
    storey = np.zeros((nt, 2, 6))
    column = np.full((nt, len(b.column_names), 2, 2), np.nan)
    for line, local in enumerate(b.column_local):
        p = np.asarray(ORIGIN) + rot @ local
        for s in range(2):
            top, bottom = u[:, s], (u[:, s - 1] if s else zero)

            def point(q, lever):
                return q[:, :2] + q[:, 2:3] * np.array([-lever[1], lever[0]])

            delta = point(top, p - centre) - point(bottom, p - centre if s else p)  # the ground does not turn
            f_local = k * (delta @ axes.T)
            f = f_local @ axes
            column[:, line, s] = f_local
            storey[:, s, 3:5] += f
            storey[:, s, 5] += cross(p, f)
            storey[:, s, 2] += cross(p - centre, f)
    storey[:, :, :2] = storey[:, :, 3:5] @ rot  # building components: Rᵀ·V
    return storey, column


def test_linear_forces_equal_k_u_assembled_by_hand(linear):
    storey, column = hand_forces(linear)
    f = linear.buildings["b"].forces
    scale = np.abs(storey).max(axis=(0, 1))
    np.testing.assert_array_less(np.abs(f.storey_shear - storey).max(axis=(0, 1)), ROUNDING * scale)
    np.testing.assert_array_less(np.abs(f.base_shear - storey[:, 0]).max(axis=0), ROUNDING * scale)
    assert np.nanmax(np.abs(f.column_shear - column)) < ROUNDING * np.nanmax(np.abs(column))
    assert np.allclose(f.column_moment, f.column_shear * H / 2, rtol=1e-15, atol=0, equal_nan=True)
    assert scale[2] > 1e-3 * scale[0], "the eccentric building twists: its torque is not zero"


def test_peaks_are_never_below_the_histories(linear):
    f = linear.buildings["b"].forces
    assert np.all(f.peak_storey_shear >= np.abs(f.storey_shear).max(axis=0))
    assert np.all(f.peak_base_shear >= np.abs(f.base_shear).max(axis=0))
    assert np.all(f.peak_column_shear >= np.abs(f.column_shear).max(axis=0))
    np.testing.assert_array_equal(f.peak_column_moment, f.peak_column_shear * H / 2)


def test_peaks_are_the_runs_not_the_outputs():
    """The peaks follow the exact motion between steps (peaks.py), as the deflection peaks do:
    a run that stores every 0.02 s has the peaks of one that stores every 0.0005 s, which are
    above that run's finest history by at most 1 − cos(ω_max·Δ/2) ≈ (ω_max·Δ)²/8 (a crest
    between two samples); while the coarse run's own history misses them."""
    building = square_building(storeys=3, eccentricity=(0.8, 0.3), section=(0.3, 0.45))
    building["floors"][0]["column_grid"]["angle"] = 15.0
    coarse = run(model_doc(building), duration=3.0, output_interval=0.02).buildings["b"]
    fine = run(model_doc(building), duration=3.0, output_interval=0.0005).buildings["b"]
    omega = 2 * math.pi / coarse.periods[-1]
    sampled = (omega * 0.0005) ** 2 / 8
    for name in ("storey_shear", "column_shear"):
        peak, peak_fine = getattr(coarse.forces, f"peak_{name}"), getattr(fine.forces, f"peak_{name}")
        np.testing.assert_allclose(peak, peak_fine, rtol=1e-9, err_msg=name)
    history = np.abs(fine.forces.storey_shear).max(axis=0)
    peak = coarse.forces.peak_storey_shear
    assert np.all(peak >= history * (1 - 1e-12)) and np.all(peak <= history * (1 + sampled) + 1e-9 * peak.max())
    missed = 1 - np.abs(coarse.forces.storey_shear).max(axis=0) / peak
    assert missed.max() > 10 * sampled, "the coarse history's maxima fall short of the peaks"


# --- equilibrium at every output step -----------------------------------------------------


@pytest.fixture(scope="module", params=["paper_pounding", "paper_inelastic", "isolated_moat"])
def scene(request):
    """A shipped scene stored finely enough to catch samples in contact: damping and contact
    (paper_pounding), yielding columns (paper_inelastic), bearings, damping links and a moat."""
    loaded = load_model(INPUTS / f"{request.param}.toml")
    duration, interval = {"paper_pounding": (20.0, 0.0002), "paper_inelastic": (8.0, 0.0005),
                          "isolated_moat": (13.0, 0.0005)}[request.param]  # fmt: skip
    loaded.model.analysis.duration = duration
    loaded.model.analysis.output_interval = interval
    loaded.model.analysis.column_force_histories = True
    return request.param, api.run_model(loaded), assemble(loaded)


def test_storey_shears_balance_the_inertia_damping_and_contact_above(scene):
    """At every output step, storey s's shear (global components, torque about the origin)
    plus Σ over the floors above of M·a_abs + C·v − F_contact is zero (results/equilibrium.py:
    the equation of motion summed over them, where the storeys between them cancel)."""
    name, result, system = scene
    for building, worst in worst_residual(result, system).items():
        assert np.all(worst < ROUNDING), f"{name} {building}: residual/scale per storey {worst}"
    in_contact = sum(int(np.any(b.forces.floor_contact != 0, axis=(1, 2)).sum()) for b in result.buildings.values())
    if name != "paper_inelastic":
        assert in_contact > 0, f"{name}: no stored sample in contact: the check would not reach the contact"


def test_storey_shear_is_the_sum_of_its_column_forces(scene):
    """Σ over a storey's columns (and, for the isolation storey, its bearings) of their local
    shears turned to global axes gives the storey's shear and torque about the origin."""
    name, result, system = scene
    for bld in system.buildings:
        b = result.buildings[bld.name]
        f = b.forces
        nt, n = f.storey_shear.shape[:2]
        total = np.zeros((nt, n, 3))
        for line, plan in enumerate(b.column_plan):
            alpha = bld.rotation + math.radians(b.column_angle[line])
            axes = np.array([[math.cos(alpha), math.sin(alpha)], [-math.sin(alpha), math.cos(alpha)]])
            here = ~np.isnan(f.column_shear[0, line, :, 0])
            force = f.column_shear[:, line, here] @ axes
            total[:, here, :2] += force
            total[:, here, 2] += cross(plan, force)
        if b.yielding is not None:
            for row, member in enumerate(b.yielding.members):
                if member["kind"] != "isolator":
                    continue
                a = math.radians(member["angle"])
                axes = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
                force = b.yielding.force[:, row] @ axes
                total[:, member["storey"] - 1, :2] += force
                total[:, member["storey"] - 1, 2] += cross(np.array([member["X"], member["Y"]]), force)
        scale = np.abs(f.storey_shear[:, :, 3:]).max(axis=(0, 1))
        worst = np.abs(total - f.storey_shear[:, :, 3:]).max(axis=(0, 1)) / scale
        assert np.all(worst < ROUNDING), f"{name} {bld.name}: residual/scale {worst}"


def test_yielding_columns_carry_their_hysteretic_force(scene):
    """A yielding column's shear is its member's force (k·δ − k_h·p), history and peak; its
    peak, followed between steps too, is never below the member's peak over the steps."""
    name, result, _ = scene
    for b in result.buildings.values():
        if b.yielding is None:
            continue
        for row, member in enumerate(b.yielding.members):
            if member["kind"] != "column":
                continue
            line, s = b.column_names.index(member["name"]), member["storey"] - 1
            v = b.forces.column_shear[:, line, s]
            force = b.yielding.force[:, row]
            assert np.abs(v - force).max() < ROUNDING * np.abs(force).max()
            peak = b.forces.peak_column_shear[line, s]
            assert np.all(peak >= b.yielding.peak[row, 3:5] * (1 - ROUNDING))


def test_peaks_are_never_below_the_stored_samples(scene):
    """With yielding columns, bearings and contact too, the peaks (the loop's, the plastic part
    from the plastic correction g) are at least the largest value of the finely stored history
    (from the members' stored forces): both are the same forces. (Not how far above: the
    plastic and contact parts make crests sharper than the structure's ω_max would; a run of
    paper_inelastic stored every 50 µs meets the peaks to 1.3e-7.)"""
    name, result, system = scene
    for b in result.buildings.values():
        f = b.forces
        for peak, history in ((f.peak_storey_shear, f.storey_shear), (f.peak_column_shear, f.column_shear)):
            present = ~np.isnan(peak)  # a column line absent from a storey (an isolation storey's): NaN
            largest = np.abs(history[:, present]).max(axis=0)
            noise = ROUNDING * np.nanmax(peak)  # a symmetric building's torques: rounding about zero
            assert np.all(peak[present] >= largest - noise), name


def test_undamped_base_shear_alone_balances_the_inertia():
    """No damping, no contact: at every output step the base shear (global, torque about the
    origin) is −Σ m·a_abs of the floors (masses and J of a uniform 8 m slab, by hand)."""
    building = square_building(storeys=3, eccentricity=(0.6, -0.9), origin=(5.0, 7.0), rotation=25.0)
    building["damping"] = {"ratios": [0.0, 0.0]}
    b = run(model_doc(building), duration=4.0).buildings["b"]
    m = 1000.0 * 64.0
    j = m * (8.0**2 + 8.0**2) / 12
    inertia = np.stack([m * b.acceleration[..., 0], m * b.acceleration[..., 1], j * b.acceleration[..., 2]], axis=-1)
    centre = np.tile(np.asarray((5.0, 7.0)) + rotation(math.radians(25.0)) @ (np.array([4.0, 4.0]) + (0.6, -0.9)), (3, 1))
    total = about_origin(inertia, centre).sum(axis=1)
    scale = np.abs(about_origin(inertia, centre)).sum(axis=1).max(axis=0)
    worst = np.abs(b.forces.base_shear[:, 3:] + total).max(axis=0) / scale
    assert np.all(worst < ROUNDING), worst
    assert np.all(b.forces.floor_contact == 0)


# --- where they appear --------------------------------------------------------------------


def test_forces_round_trip_through_hdf5_with_units_and_dimensions(linear, tmp_path):
    path = write_hdf5(linear, tmp_path / "run.h5")
    back = read_hdf5(path).buildings["b"].forces
    f = linear.buildings["b"].forces
    for field in ("storey_shear", "base_shear", "floor_contact", "peak_storey_shear", "peak_base_shear",
                  "peak_column_shear", "peak_column_moment", "column_shear", "column_moment"):  # fmt: skip
        np.testing.assert_array_equal(getattr(back, field), getattr(f, field), err_msg=field)
    with h5py.File(path) as h:
        g = h["buildings/b"]
        assert g["forces/storey_shear"].attrs["units"] == "N, N, N*m, N, N, N*m"
        assert g["peaks/column_moment"].attrs["units"] == "N*m"
        names = [d.label or (d[0].name.rsplit("/", 1)[-1] if len(d) else "") for d in g["forces/column_shear"].dims]
        assert names == ["time", "column", "storey", "column_axis"]


def test_column_force_histories_only_when_asked():
    building = square_building()
    f = run(model_doc(building), duration=0.5).buildings["b"].forces
    assert f.column_shear is None and f.column_moment is None
    assert f.peak_column_shear.shape == (9, 1, 2) and np.all(f.peak_column_shear > 0)


@pytest.fixture(scope="module")
def linear_file(linear, tmp_path_factory):
    return write_hdf5(linear, tmp_path_factory.mktemp("forces") / "linear.h5")


def test_report_document_tables_and_plot(linear_file, linear):
    from pounding_cli.report import open_run, run_tables, summary
    from pounding_cli.report.shear_profiles import shear_figure

    f = linear.buildings["b"].forces
    doc = summary(linear_file, column="C9")
    forces = doc["buildings"][0]["forces"]
    assert [forces["base_shear"][k] for k in ("x_N", "y_N", "torque_Nm", "X_N", "Y_N", "torque_origin_Nm")] == \
        f.peak_base_shear.tolist()  # fmt: skip
    assert forces["columns"][0]["moment_Nm"] == f.peak_column_moment[8].tolist()  # C9, the ninth line
    assert forces["max_column_shear_N"] == np.nanmax(f.peak_column_shear)
    titles = [t.title for t in run_tables(doc)]
    assert any(t.startswith("Peak storey shears: b (storey 1: the base shear") for t in titles)
    assert any(t.startswith("Peak column forces: b, column C9") for t in titles)
    fig = shear_figure([open_run(linear_file)])
    for ax, c in zip(fig.axes, range(3)):
        np.testing.assert_array_equal(ax.lines[0].get_xdata(), f.peak_storey_shear[:, c] / 1e3)


def test_export_writes_the_forces_with_units(linear_file, linear, tmp_path):
    import csv

    from pounding_cli.export import export_csv

    f = linear.buildings["b"].forces
    written = {w["quantity"]: w for w in export_csv(linear_file, tmp_path, ["forces"])}
    assert sorted(written) == ["column_force_peaks", "column_forces", "storey_shear", "storey_shear_peaks"]
    with open(written["storey_shear"]["file"], newline="") as file:
        rows = list(csv.reader(file))
    assert rows[0] == ["time [s]", "building", "storey", "V_x [N]", "V_y [N]", "T [N*m]", "V_X [N]", "V_Y [N]",
                       "T_O [N*m]"]  # fmt: skip
    values = np.array([[float(v) for v in row[3:]] for row in rows[1:]]).reshape(f.storey_shear.shape)
    np.testing.assert_array_equal(values, f.storey_shear)
    assert written["column_forces"]["rows"] == f.storey_shear.shape[0] * 9 * 2
    assert written["column_force_peaks"]["rows"] == 9 * 2


def test_sweep_summary_has_the_force_columns(linear_file, linear):
    from pounding_cli.sweep.summary import case_results

    f = linear.buildings["b"].forces
    row = case_results(linear_file)
    assert [row[f"{k}[b]"] for k in ("peak_base_shear_x_N", "peak_base_shear_y_N", "peak_base_torque_Nm")] == \
        f.peak_base_shear[:3].tolist()  # fmt: skip
    assert row["max_column_shear_N[b]"] == np.nanmax(f.peak_column_shear)
