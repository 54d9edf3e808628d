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
    assert names == ["corner", "linear", "paper_pounding", "row_of_5", "stiff_contact"]
    for path in scene_files():
        load_model(path)
