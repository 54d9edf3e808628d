"""`pound bench`: the table, its files and plot, and the default's accuracy (no timings are
asserted: they are ratios from one run, reported, not tested)."""

from __future__ import annotations

import h5py
import pytest
from typer.testing import CliRunner

from pounding_cli.bench import bench, scene_files
from pounding_cli.bench.report import markdown, plot, table_rows, write_hdf5
from pounding_cli.bench.run import QUICK_SETTINGS
from pounding_cli.cli import app


@pytest.fixture(scope="module")
def reports():
    models = [p for p in scene_files() if p.stem in ("linear", "paper_pounding")]
    return bench(models, QUICK_SETTINGS, repeats=1, reference_divisor=2, duration=15.0)


@pytest.mark.slow
def test_default_is_accurate_against_the_reference(reports):
    """The default (hybrid) against CDM at a quarter of its step: peak deflections within 1 %
    (the reference's own change on halving is reported beside it), the same impacts, the
    balance closed to 1e-3."""
    for report in reports:
        default = next(r for r in report.rows if r.setting.default)
        assert default.errors.peak_deflection < 1e-2, report.scene
        assert default.errors.impact_count == 0, report.scene
        assert default.errors.peak_force < 1e-2, report.scene
        assert default.errors.energy_balance < 1e-3, report.scene
    pounding = next(r for r in reports if r.scene == "paper_pounding")
    assert any(r.contact_steps > 0 for r in pounding.rows), "the scene must pound within 15 s"


@pytest.mark.slow
def test_outputs(reports, tmp_path):
    rows = table_rows(reports)
    assert len(rows) == 2 * len(QUICK_SETTINGS)
    assert sum(r["default"] for r in rows) == 2
    text = markdown(reports)
    assert "halving its Δt changes" in text and "| **hybrid (default)** |" in text
    write_hdf5(reports, tmp_path / "bench.h5")
    with h5py.File(tmp_path / "bench.h5") as f:
        table = f["bench"][()]
        assert table.shape == (len(rows),)
        assert {"wall_time_s", "peak_deflection_error", "on_front"} <= set(table.dtype.names)
    fig = plot(reports, tmp_path / "bench.png")
    axes = [a for a in fig.axes if a.get_visible()]
    assert [a.get_title() for a in axes] == ["linear", "paper_pounding"]
    for a in axes:
        assert a.get_xscale() == "log" and a.get_yscale() == "log"
        assert a.get_xlabel() == "solver time (s)"
        assert len(a.get_lines()) == 3  # hybrid, cdm, the default's star
    assert (tmp_path / "bench.png").stat().st_size > 10_000


def test_bench_command_refuses_a_bad_scene(tmp_path):
    r = CliRunner().invoke(app, ["bench", "--scene", str(tmp_path / "missing.toml"), "--out", str(tmp_path)])
    assert r.exit_code == 2
    assert "no such file" in r.stderr


def test_scene_record_is_the_shipped_record():
    """The bench scenes carry their own copy of the shipped record (package data, so that an
    installed pound can bench); it must be the same bytes as inputs/records."""
    from conftest import INPUTS

    packaged = next(p for p in scene_files()).parent / "ridgecrest2019_ccc.mseed"
    assert packaged.read_bytes() == (INPUTS / "records" / "ridgecrest2019_ccc.mseed").read_bytes()


def test_every_scene_validates():
    from pounding_cli.model import load_model

    names = [p.stem for p in scene_files()]
    assert names == ["corner", "inelastic", "isolated", "linear", "mismatched_floors", "paper_pounding", "row_of_5",
                     "stiff_contact"]
    for path in scene_files():
        load_model(path)


def test_yielding_scenes_have_members_and_their_error(tmp_path):
    """The inelastic and isolated scenes load with their yielding members, and the bench
    compares the members' peaks (a cheap check: the first 4.5 s, by which the bearings and
    the left building's columns have yielded, a coarse reference, one setting)."""
    from pounding_cli.api import prepare, execute
    from pounding_cli.bench.metrics import compare
    from pounding_cli.bench.run import SETTINGS, with_setting

    paths = {p.stem: p for p in scene_files()}
    default = next(s for s in SETTINGS if s.default)
    reports = bench([paths["isolated"], paths["inelastic"]], (default,), repeats=1, reference_divisor=1, duration=4.5)
    for report, members in zip(reports, (9, 81)):
        assert report.convergence.members == members, report.scene
        e = report.rows[0].errors
        assert e.members == members
        assert 0.0 < e.member_deflection < 1e-2 and 0.0 <= e.ductility < 1e-2, (report.scene, e)
    rows = table_rows(reports)
    assert [r["yielding_members"] for r in rows] == [9, 81]
    assert all(r["member_deflection_error"] > 0 for r in rows)
    text = markdown(reports)
    assert "| member deflection error | ductility error |" in text and "yielding members' peak deflections" in text
    write_hdf5(reports, tmp_path / "bench.h5")
    with h5py.File(tmp_path / "bench.h5") as f:
        table = f["bench"][()]
        assert list(table["yielding_members"]) == [9, 81]
        assert (table["member_deflection_error"] > 0).all()
    fig = plot(reports, tmp_path / "bench.png")
    axes = [a for a in fig.axes if a.get_visible()]
    assert [len(a.get_lines()) for a in axes] == [3, 3]  # hybrid deflection, hybrid member |δ|, the star
    # the members' peaks really yielded, and a run compared with itself has no error
    scene = with_setting(prepare(paths["isolated"]), default, 4.5)
    run = execute(scene)
    assert run.buildings["isolated"].yielding.ductility.max() > 1.0
    same = compare(run, run)
    assert same.members == 9 and same.member_deflection == 0.0 and same.ductility == 0.0


def test_member_errors_are_zero_without_members():
    from pounding_cli.api import prepare, execute
    from pounding_cli.bench.metrics import compare
    from pounding_cli.bench.run import SETTINGS, with_setting

    path = next(p for p in scene_files() if p.stem == "linear")
    run = execute(with_setting(prepare(path), next(s for s in SETTINGS if s.default), 1.0))
    e = compare(run, run)
    assert (e.members, e.member_deflection, e.ductility) == (0, 0.0, 0.0)


def test_crossover_measures_both_broad_phases(monkeypatch):
    """`python -m pounding_cli.bench.crossover`: a row of three buildings, a short run."""
    from pounding_cli.bench import crossover

    monkeypatch.setattr(crossover, "STEPS", 400)
    name, scene = next(crossover.scenes(rows=(3,), names=()))
    point = crossover.measure(name, scene, repeats=1)
    assert (point.pairs, point.members) == (9, 9)
    assert min(point.contact_all_ns, point.contact_sweep_ns, point.horizon_all_ns, point.horizon_sweep_ns) > 0
    assert "| row of 3 | 9 | 9 | 1.00 |" in crossover.markdown([point])


def test_input_sensitivity_of_a_linear_scene_is_the_perturbation_itself():
    """A linear scene without contact scales with its input: the record × (1 + 1e-4) moves
    every peak by exactly 1e-4 of itself (1e-6 relative: the difference of two peaks 1e-4
    apart keeps ~12 digits), and the error floor is the larger of that and the reference's
    own halving change. The floor and the sensitivity reach the Markdown, JSON and HDF5."""
    from pounding_cli.bench.run import PERTURBATION, SETTINGS

    linear = next(p for p in scene_files() if p.stem == "linear")
    default = next(s for s in SETTINGS if s.default)
    (report,) = bench([linear], (default,), repeats=1, reference_divisor=1, duration=6.0)
    assert report.sensitivity is not None and report.sensitivity.impact_count == 0
    assert report.sensitivity.peak_deflection == pytest.approx(PERTURBATION, rel=1e-6)
    assert report.floor == max(report.convergence.peak_deflection, report.sensitivity.peak_deflection)
    assert "Scaling the record by 1 + 0.0001 changes peak deflections by 1.0e-04" in markdown([report])
    (row,) = table_rows([report])
    assert row["input_sensitivity"] == report.sensitivity.peak_deflection and row["error_floor"] == report.floor


def test_front_counts_one_run_once():
    """on_front: a setting beaten on time and error is off the front; two settings that take
    the same steps and give the same errors (the contact step scaled in a scene without
    contact) are one run, whose timings differ by noise alone: neither pushes the other off."""
    import dataclasses

    from pounding_cli.bench.metrics import Errors
    from pounding_cli.bench.run import Row, SceneReport, Setting, on_front

    def row(name, steps, wall, error, integrator="hybrid"):
        return Row("s", Setting(name, integrator), steps, 0, wall, Errors(error, error, 0.0, 0, 0.0))

    rows = [row("default", 100, 0.0205, 1.3e-5), row("twin", 100, 0.0203, 1.3e-5),
            row("faster, worse", 60, 0.0127, 1.4e-5), row("slower, worse", 300, 0.05, 2e-5),
            row("beaten", 120, 0.03, 1.3e-5)]  # fmt: skip
    report = SceneReport("s", Setting("ref", "cdm"), 1000, Errors(0.0, 0.0, 0.0, 0, 0.0), rows)
    assert on_front(report) == {"default", "twin", "faster, worse"}
    rows[1] = row("twin", 100, 0.0203, 1.2e-5)  # a different run: it beats the default
    assert on_front(dataclasses.replace(report, rows=rows)) == {"twin", "faster, worse"}


def test_a_scene_the_hybrid_takes_exactly_has_a_reference_fine_enough_to_judge_it():
    """Without contact or yielding members the hybrid's only error is its peaks' interpolation
    (~1e-9 here), and the CDM at a quarter of the structure's automatic step is itself ~1e-5
    off, which hid it (every hybrid row of the linear scene read the reference's 1.3e-5). Its
    reference takes 1/8 of that step again: it moves by less than 1e-6 when halved (CDM error
    second order: 1/64 of 1.0e-5), and the default's error against it is below 1e-6 too
    (over the first 6 s: measured 7.3e-8 and 9.7e-8, the reference's own error). Scenes with
    contact keep a quarter of their (contact-limited) step."""
    from pounding_cli.api import prepare
    from pounding_cli.bench.run import EXACT_REFERENCE_FACTOR, SETTINGS, reference_scale

    paths = {p.stem: p for p in scene_files()}
    assert reference_scale(prepare(paths["paper_pounding"]), 4) == 0.25
    assert reference_scale(prepare(paths["linear"]), 4) == 1 / (4 * EXACT_REFERENCE_FACTOR)
    default = next(s for s in SETTINGS if s.default)
    (report,) = bench([paths["linear"]], (default,), repeats=1, reference_divisor=4, duration=6.0)
    assert report.reference.dt_scale == 1 / 32 and report.reference.name == "cdm, Δt auto / 32 (reference)"
    assert report.convergence.peak_deflection < 1e-6
    (row,) = report.rows
    print(f"reference halving {report.convergence.peak_deflection:.2e}, default {row.errors.peak_deflection:.2e}")
    assert row.errors.peak_deflection < 1e-6
