"""`pound report --plots`: every plot renders from the shipped examples, with the expected axes,
labels and series (checked on the matplotlib Figure objects), and the files are written."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.report import open_run
from pounding_cli.report.energy import energy_figure
from pounding_cli.report.geometry import moved, nice_magnification, plan_geometry
from pounding_cli.report.ground import ground_figure
from pounding_cli.report.histories import displacement_figure
from pounding_cli.report.impacts import impact_figure
from pounding_cli.report.plan import contact_normal, peak_instant, plan_figure
from pounding_cli.report.plots import write_plots
from pounding_cli.report.profiles import profile_figure

from conftest import EXAMPLE, INPUTS, ROOT

runner = CliRunner()


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The pounding example and the wide-gap example (no contact), run once."""
    folder = tmp_path_factory.mktemp("plots")
    out = {}
    for name, model in (("pounding", INPUTS / "paper_pounding.toml"), ("wide", EXAMPLE)):
        assert pound.run_model(model, output=folder / f"{name}.h5").complete
        out[name] = open_run(folder / f"{name}.h5")
    return out


def _visible(fig):
    return [ax for ax in fig.axes if ax.get_visible()]


def _labels(ax):
    return [line.get_label() for line in ax.get_lines() if not line.get_label().startswith("_")]


def test_ground_motion(runs):
    run = runs["pounding"]
    fig = ground_figure(run)
    axes = _visible(fig)
    assert [ax.get_ylabel() for ax in axes] == ["a_X (g)", "a_Y (g)"]
    assert axes[-1].get_xlabel() == "time (s)"
    trace = axes[0].get_lines()[0]
    np.testing.assert_array_equal(trace.get_xdata(), run.result.time)
    np.testing.assert_allclose(trace.get_ydata(), run.result.ground_acceleration[:, 0] / 9.80665)
    assert "impacts (log)" in _labels(axes[0])  # the one impact is marked
    assert "Ridgecrest" in fig.get_suptitle()


def test_displacement_histories_of_chosen_floors(runs):
    run = runs["pounding"]
    fig = displacement_figure(run)
    axes = _visible(fig)
    assert [ax.get_ylabel() for ax in axes] == ["u_x (mm)", "u_y (mm)", "θ_z (mrad)"]
    assert _labels(axes[0])[:2] == ["left floor 4", "right floor 3"]  # default: each roof
    fig = displacement_figure(run, [("left", 2)])
    line = fig.axes[1].get_lines()[0]
    np.testing.assert_allclose(line.get_ydata(), 1e3 * run.result.buildings["left"].displacement[:, 1, 1])


def test_profiles_are_the_papers_figures(runs):
    run = runs["pounding"]
    fig = profile_figure([run], column="left:C9")
    axes = _visible(fig)
    assert [ax.get_xlabel() for ax in axes] == ["peak Δx (mm)", "peak Δy (mm)", "peak Δθ (mrad)"]
    assert axes[0].get_ylabel() == "storey"
    c9 = run.result.buildings["left"].column("C9")
    for k, ax in enumerate(axes):
        (line,) = ax.get_lines()
        np.testing.assert_allclose(line.get_xdata(), 1e3 * c9[:, k])
        np.testing.assert_array_equal(line.get_ydata(), [1, 2, 3, 4])


def test_profiles_of_several_runs_share_one_figure(runs):
    fig = profile_figure([runs["pounding"], runs["wide"]], column="left:C9")
    assert _labels(fig.axes[0]) == ["pounding: left C9", "wide: left C9"]
    pounding, wide = (line.get_xdata() for line in fig.axes[0].get_lines())
    assert pounding[3] != wide[3]  # the impact at floor 3 changes the top storey
    fig = profile_figure([runs["pounding"]])  # no column: the largest over each storey's columns
    assert _labels(fig.axes[0]) == ["left (largest over the columns)", "right (largest over the columns)"]
    np.testing.assert_allclose(
        fig.axes[0].get_lines()[1].get_xdata(),
        1e3 * np.nanmax(runs["pounding"].result.buildings["right"].interstorey_deflection[:, :, 0], axis=0),
    )


def test_impacts_show_histories_and_the_log(runs):
    run = runs["pounding"]
    events = run.result.contact.events
    fig = impact_figure(run)
    axes = fig.axes
    assert len(axes) == 4  # force over area; on the left the episodes ± 1 s, on the right the largest
    assert axes[0].get_ylabel() == "normal force F_N (kN)" and axes[2].get_ylabel() == "overlap area (cm²)"
    labels = _labels(axes[0])
    assert labels == ["left 3 – right 3 (every 0.01 s)", "impact log: peak of each episode (1)"]
    stems = [line for line in axes[0].get_lines() if line.get_label().startswith("impact log")][0]
    np.testing.assert_allclose(stems.get_xdata(), events["t_peak"])
    np.testing.assert_allclose(stems.get_ydata(), events["peak_normal_force"] / 1e3)
    lo, hi = axes[1].get_xlim()  # the right column zooms on the largest episode
    assert lo < events["t_peak"][0] < hi and hi - lo < 0.2
    fig = impact_figure(runs["wide"])
    assert [t.get_text() for t in fig.axes[0].texts] == ["no impacts"]  # 0.5 m apart: candidates that never touch


def test_energy_stack(runs):
    run = runs["pounding"]
    fig = energy_figure(run)
    top, bottom = fig.axes
    assert top.get_ylabel() == "energy (kJ)" and bottom.get_ylabel() == "error (% of max input)"
    stacked = [c.get_label() for c in top.collections]
    assert stacked == ["damping", "contact", "strain", "kinetic"]  # hysteretic is 0 and left out
    (line,) = [ln for ln in top.get_lines() if ln.get_label() == "input"]
    np.testing.assert_allclose(line.get_ydata(), run.result.energy_column("input") / 1e3)
    assert f"{100 * run.result.balance_error_ratio:.3g} %" in fig.get_suptitle()


def test_plan_view_at_the_peak_impact(runs):
    run = runs["pounding"]
    fig = plan_figure(run)
    axes = _visible(fig)
    assert len(axes) == 4  # levels at 3, 6, 9 and 12 m
    assert [ax.get_title() for ax in axes] == ["level 1: 3 m", "level 2: 6 m", "level 3: 9 m (contact)", "level 4: 12 m"]
    assert [len(ax.patches) for ax in axes] == [2, 2, 2, 1]
    event = run.result.contact.events[0]
    assert f"t = {event['t_peak']:.4f} s" in fig.get_suptitle() and "displacements × 10" in fig.get_suptitle()
    contact = axes[2]
    assert any(p.get_edgecolor()[:3] == (0.8392156862745098, 0.15294117647058825, 0.1568627450980392)
               for p in contact.patches)  # fmt: skip
    arrows = [a for a in contact.texts if a.arrow_patch is not None]
    assert len(arrows) == 2  # F_N and F_T, both from the impact log (the sample misses the impact)
    (start, tip_n), (_, tip_t) = [(np.array(a.xyann), np.array(a.xy)) for a in arrows]
    # drawn along the logged normal n (from the left building into the right) and t = ẑ × n,
    # lengths in the ratio of the logged forces (to the rounding of the drawing: 1e-9)
    n = np.array([event["normal_x"], event["normal_y"]])
    np.testing.assert_allclose(n, [1.0, 0.0], atol=0.02)
    np.testing.assert_allclose((tip_n - start) / np.hypot(*(tip_n - start)), n, atol=1e-9)
    f_n, f_t = event["peak_normal_force"], event["tangential_force_at_peak"]
    np.testing.assert_allclose(tip_t - start, (tip_n - start) @ n * (f_t / f_n) * np.array([-n[1], n[0]]), atol=1e-9)
    labels = _labels(contact)
    assert f"F_N = {f_n / 1e6:.3g} MN" in labels and f"F_T = {f_t / 1e6:.3g} MN" in labels
    assert "F_N = 16.5 MN" in labels and abs(f_t) > 0.1 * f_n, "friction matters in this impact"
    star = [ln for ln in contact.get_lines() if ln.get_label() == "action point"][0]
    assert abs(star.get_xdata()[0] - 8.05) < 0.6 and abs(star.get_ydata()[0] - 4.05) < 0.1


def test_plan_view_without_impacts(runs):
    fig = plan_figure(runs["wide"], magnify=50, levels=[4])
    assert len(_visible(fig)) == 1
    assert "no impacts" in fig.get_suptitle() and "× 50" in fig.get_suptitle()


def test_plan_uses_sampled_contacts_when_the_output_catches_them(runs, tmp_path):
    from pounding_cli.model import read_document, validate_model

    doc = read_document(INPUTS / "paper_pounding.toml")
    doc["analysis"].update(output_interval=0.0005, duration=15.0)
    pound.run_model(validate_model(doc, INPUTS / "fine.toml"), output=tmp_path / "fine.h5")
    run = open_run(tmp_path / "fine.h5")
    instant = peak_instant(run, plan_geometry(run))
    assert instant.source == "histories" and instant.contacts[0].f_tangential is not None
    fig = plan_figure(run, levels=[3])
    assert len([a for a in fig.axes[0].texts if a.arrow_patch is not None]) == 2  # F_N and F_T
    assert any(lab.startswith("F_T = ") for lab in _labels(fig.axes[0]))


def test_geometry_rebuilds_the_slabs(runs):
    run = runs["pounding"]
    geometry = plan_geometry(run)
    assert geometry.levels == [3.0, 6.0, 9.0, 12.0]
    right = geometry.slab("right", 1)
    np.testing.assert_allclose(right.outline, [[8.05, 0], [24.05, 0], [24.05, 8], [8.05, 8]])
    np.testing.assert_allclose(right.centre, run.result.buildings["right"].mass_centre[0])
    turned = moved(right, np.array([0.1, 0.0, np.pi / 2]))
    np.testing.assert_allclose(turned[0], [16.05 + 4 + 0.1, 4 - 8])  # the corner turned 90° about (16.05, 4)
    assert nice_magnification(run, geometry) == 10


def test_contact_normal():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    np.testing.assert_allclose(contact_normal(square, square + [0.9, 0.0]), [1, 0], atol=1e-12)  # face to face
    corner = contact_normal(square, square + [0.9, 0.2])  # crossings (1, 0.2) and (0.9, 1): the normal tilts
    np.testing.assert_allclose(corner, np.array([0.8, 0.1]) / np.hypot(0.8, 0.1), atol=1e-12)
    np.testing.assert_allclose(contact_normal(square, square + [1.5, 0.0]), [1, 0], atol=1e-12)  # apart
    np.testing.assert_allclose(contact_normal(square + [0, 1.2], square), [0, -1], atol=1e-12)  # B below A


def test_write_plots(runs, tmp_path):
    files = write_plots([runs["pounding"]], tmp_path / "png")
    assert sorted(p.name for p in files) == sorted(
        f"{n}.png" for n in ("ground", "displacement", "profiles", "storey_shear", "impacts", "energy", "plan"))
    assert all(p.read_bytes().startswith(b"\x89PNG") for p in files)


@pytest.mark.parametrize("fmt", ["svg", "pdf"])
def test_vector_formats(runs, tmp_path, fmt):
    from pounding_cli.report.style import save_as

    path = save_as(profile_figure([runs["pounding"]], "left:C9"), tmp_path, "profiles", fmt)
    assert path.read_bytes().startswith(b"%PDF" if fmt == "pdf" else b"<?xml")


def test_cli_plots_of_several_runs(runs, tmp_path):
    paths = [str(runs[name].path) for name in ("pounding", "wide")]
    r = runner.invoke(app, ["report", *paths, "--plots", str(tmp_path / "out"),
                            "--column", "left:C9", "--floor", "left:2", "--magnify", "20"])  # fmt: skip
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert "profiles.png" in names and "pounding-plan.png" in names and "wide-ground.png" in names
    assert len(names) == 12  # 5 per run, and the profiles and storey shears of both on one figure each
    assert "wrote " in r.stderr


def test_cli_plot_errors(runs, tmp_path):
    path = str(runs["pounding"].path)
    for args, words in ((["--format", "jpg"], "unknown plot format 'jpg'"),
                        (["--floor", "middle:2"], "no building 'middle'"),
                        (["--floor", "left:9"], "has floors 1 to 4, not 9")):  # fmt: skip
        r = runner.invoke(app, ["report", path, "--plots", str(tmp_path / "p"), *args])
        assert r.exit_code == 2, args
        assert words in r.stderr
    r = runner.invoke(app, ["report", path, "--plots", str(tmp_path / "no" / "such" / "folder")])
    assert r.exit_code == 2 and "does not exist" in r.stderr


def _images_script():
    """docs/make_report_images.py as a module."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_report_images", ROOT / "docs" / "make_report_images.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_image_check_names_what_changed_in_a_figure(runs):
    """The content `make_report_images.py --check` compares: a relabelled axis and an added
    series are reported, naming the image, the axes and the field; an image no longer drawn too."""
    script = _images_script()
    fig = impact_figure(runs["pounding"])
    before = script.signature(fig)
    json.dumps(before)  # stored as JSON
    assert [ax["ylabel"] for ax in before["axes"]][:2] == [fig.axes[0].get_ylabel(), fig.axes[1].get_ylabel()]
    lines = before["axes"][1]["lines"]
    fig.axes[0].set_ylabel("force")
    fig.axes[1].plot([0.0, 1.0], [0.0, 1.0])
    assert script.differences({"report-impacts.png": before}, {"report-impacts.png": script.signature(fig)}) == [
        f"report-impacts.png: axes[0].ylabel: {before['axes'][0]['ylabel']!r} in the docs, 'force' now",
        f"report-impacts.png: axes[1].lines: {lines} in the docs, {lines + 1} now",
    ]
    assert script.differences({"report-impacts.png": before}, {}) == ["report-impacts.png: no longer drawn"]
