"""`pound report SWEEP_DIR/`: the summary table, its JSON document and schema, plots of summary
columns against a swept parameter (also polar), grouped bars of named cases, failed cases,
folders of killed sweeps, table-valued parameters."""

from __future__ import annotations

import csv
import json

import h5py
import jsonschema
import numpy as np
import pytest
from referencing import Registry, Resource
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.report.sweep_bars import cases_figure
from pounding_cli.report.sweep_data import match_cases, open_sweep
from pounding_cli.report.sweep_document import sweep_summary
from pounding_cli.report.sweep_lines import parameter_figure
from pounding_cli.sweep import read_summary, run_sweep

from conftest import INPUTS, ROOT, sweep_then_kill

runner = CliRunner()
WIDE = {"COLUMNS": "250"}
SWEEP = """
title = "Report test: angle × gap, and three named cases"
set = { "analysis.duration" = 16.0 }

[summary]
columns = { left = ["C9"] }

[studies.angle]
description = "angle of incidence × gap"
parameters = { "excitation.angle" = [0, 45, 90, 135], "buildings.right.origin[0]" = [8.02, 8.05] }

[studies.cases]
description = "named cases"
cases."pounding" = {}
cases."no pounding" = { "contact.enabled" = false }
cases."e_y = 0.4 m" = { "buildings.left.floors[*].eccentricity" = [0.0, 0.4] }
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("sweep")
    path = tmp / "report.sweep.toml"
    path.write_text(f'base = "{(INPUTS / "paper_pounding.toml").as_posix()}"\n' + SWEEP, encoding="utf-8")
    outcome = run_sweep(path, tmp / "out", jobs=2)
    assert outcome.ok
    return tmp / "out"


def _json(*args):
    r = runner.invoke(app, ["report", *map(str, args), "--json"])
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def test_json_validates_and_is_the_summary(folder):
    doc = _json(folder)
    schemas = {name: json.loads((ROOT / "schemas" / name).read_text(encoding="utf-8"))
               for name in ("report-sweep.schema.json", "sweep-summary.schema.json")}  # fmt: skip
    registry = Registry().with_resources((s["$id"], Resource.from_contents(s)) for s in schemas.values())
    jsonschema.Draft202012Validator(schemas["report-sweep.schema.json"], registry=registry).validate(doc)
    assert doc["rows"] == read_summary(folder)  # the rows of `pound sweep --json`
    assert doc["counts"] == {"cases": 11, "complete": 11, "failed": 0, "pending": 0} and doc["complete"]
    with h5py.File(folder / "summary.h5") as f:
        table = f["cases"][()]
        assert [c["name"] for c in doc["columns"]] == list(table.dtype.names)
        for row, record in zip(doc["rows"], table):
            assert row["peak_isd_x_m[left/C9/4]"] == record["peak_isd_x_m[left/C9/4]"]
            assert row["impacts"] == record["impacts"] and row["case"] == record["case"].decode()
        assert doc["title"] == f.attrs["title"]


def test_study_selects_rows(folder):
    doc = _json(folder, "--study", "cases")
    assert [r["case"] for r in doc["rows"]] == ["pounding", "no pounding", "e_y = 0.4 m"]
    assert doc["selected_studies"] == ["cases"] and doc["counts"]["cases"] == 3
    r = runner.invoke(app, ["report", str(folder), "--study", "nope"])
    assert r.exit_code == 2 and "no study 'nope'; studies: 'angle', 'cases'" in r.stderr


def test_tables(folder):
    r = runner.invoke(app, ["report", str(folder), "--column", "left:C9"], env=WIDE)
    assert r.exit_code == 0, r.output
    text = r.stdout
    assert text.lstrip().startswith("Sweep")
    for words in ("11: 11 complete, 0 failed, 0 pending", "study 'angle'", "excitation.angle",
                  "left C9 Δx (mm)", "no pounding", "e_y = 0.4 m"):  # fmt: skip
        assert words in text, words
    row = read_summary(folder)[0]
    c9 = max(row[f"peak_isd_x_m[left/C9/{s}]"] for s in range(1, 5))
    assert f"{1e3 * c9:.4g}" in text


def test_parameter_figure_is_figure_8(folder):
    sweep = open_sweep(folder)
    fig = parameter_figure(sweep, "excitation.angle", column="left:C9")
    axes = fig.axes
    assert [ax.get_ylabel() for ax in axes] == ["peak Δx (mm)", "peak Δy (mm)", "peak Δθ (mrad)"]
    assert axes[-1].get_xlabel() == "excitation.angle (°)"
    lines = axes[0].get_lines()
    assert len(lines) == 4 * 2  # a line per storey and per gap
    rows = [r for r in sweep.rows if r["study"] == "angle" and r["buildings.right.origin[0]"] == 8.02]
    first = lines[0]
    np.testing.assert_array_equal(first.get_xdata(), [0, 45, 90, 135])
    np.testing.assert_allclose(first.get_ydata(), [1e3 * r["peak_isd_x_m[left/C9/1]"] for r in rows])
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend[:4] == ["storey 1", "storey 2", "storey 3", "storey 4"]
    assert "angle: buildings.right.origin[0]=8.05" in legend


def test_polar_figure(folder):
    fig = parameter_figure(open_sweep(folder), "excitation.angle", column="left:C9", polar=True)
    assert [ax.name for ax in fig.axes] == ["polar"] * 3
    np.testing.assert_allclose(fig.axes[0].get_lines()[0].get_xdata(), np.radians([0, 45, 90, 135]))


def _overlaps(fig):
    """Pairs of texts of a drawn polar figure that overlap: per panel its title, angle labels
    and radial labels, and the figure's title."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    renderer = fig.canvas.get_renderer()

    def boxes(texts):
        return [(t.get_text(), t.get_window_extent(renderer)) for t in texts if t.get_visible() and t.get_text()]

    found = []
    suptitle = boxes([fig._suptitle])
    for ax in fig.axes:
        title, angles, radii = boxes([ax.title]), boxes(ax.get_xticklabels()), boxes(ax.get_yticklabels())
        assert title and len(angles) == 8 and len(radii) >= 2
        for group, other in ((title, angles + radii + suptitle), (radii, angles)):
            found += [(a, b) for a, box in group for b, box2 in other if box.overlaps(box2)]
        found += [(a, b) for i, (a, box) in enumerate(radii) for b, box2 in radii[i + 1:] if box.overlaps(box2)]
    return found


@pytest.mark.parametrize("scale", [1.0, 1e-4], ids=["mm", "long radial labels"])
def test_polar_labels_do_not_overlap(folder, scale):
    """No panel title, angle label, radial label or figure title runs into another, with the
    sweep's values and with them scaled to give long radial labels (0.0012 mm)."""
    from pounding_cli.report.sweep_data import Sweep

    sweep = open_sweep(folder)
    results = set(sweep.names("result"))
    rows = [{k: v * scale if k in results and isinstance(v, float) else v for k, v in r.items()} for r in sweep.rows]
    scaled = Sweep(sweep.folder, sweep.attrs, sweep.columns, rows)
    for fig in (parameter_figure(scaled, "excitation.angle", column="left:C9", polar=True),
                parameter_figure(scaled, "excitation.angle", polar=True)):  # fmt: skip
        assert _overlaps(fig) == []


def test_bars_of_named_cases(folder):
    sweep = open_sweep(folder)
    rows = match_cases(sweep, ["cases/*"])
    fig = cases_figure(sweep, rows, column="left:C9")
    axes = fig.axes
    assert [ax.get_ylabel() for ax in axes] == ["peak Δx (mm)", "peak Δy (mm)", "peak Δθ (mrad)"]
    assert [t.get_text() for t in axes[-1].get_xticklabels()] == [f"storey {s}" for s in range(1, 5)]
    bars = axes[0].containers
    assert [b.get_label() for b in bars] == ["cases/pounding", "cases/no pounding", "cases/e_y = 0.4 m"]
    heights = [p.get_height() for p in bars[1].patches]
    np.testing.assert_allclose(heights, [1e3 * rows[1][f"peak_isd_x_m[left/C9/{s}]"] for s in range(1, 5)])


def test_cli_plots(folder, tmp_path):
    out = tmp_path / "plots"
    r = runner.invoke(app, ["report", str(folder), "--plots", str(out), "--column", "left:C9",
                            "--y", "peak_isd_theta_rad[left/C9/*]", "--html", str(tmp_path / "s.html")])  # fmt: skip
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(["sweep-excitation.angle.png", "sweep-excitation.angle-polar.png",
                            "sweep-excitation.angle-impacts.png", "sweep-excitation.angle-columns.png",
                            "sweep-cases-angle.png", "sweep-cases-cases.png"])  # fmt: skip
    text = (tmp_path / "s.html").read_text(encoding="utf-8")
    assert text.count("data:image/png;base64,") == 6 and "<caption>Sweep</caption>" in text
    r = runner.invoke(app, ["report", str(folder), "--plots", str(tmp_path / "p2"), "--case", "*pounding",
                            "--x", "buildings.right.origin[0]"])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in (tmp_path / "p2").iterdir()) == [
        "sweep-buildings.right.origin_0-impacts.png", "sweep-buildings.right.origin_0.png", "sweep-cases.png"]


@pytest.mark.parametrize("args, words", [
    (["--x", "contact.enabled"], "'contact.enabled' is not a numeric swept parameter"),
    (["--column", "right:C1"], "no per-storey columns of 'right:C1'; it has left:C9"),
    (["--case", "nothing*"], "no case matches 'nothing*'"),
    (["--y", "peak_*[nowhere]"], "no summary column matches"),
    (["--animate", "a.gif"], "--animate: applies to result files, not to a sweep folder"),
])  # fmt: skip
def test_cli_errors(folder, tmp_path, args, words):
    r = runner.invoke(app, ["report", str(folder), "--plots", str(tmp_path / "p"), *args])
    assert r.exit_code == 2, r.output
    assert words in r.stderr


def test_failed_cases_are_said_first(folder, tmp_path):
    """A case whose file says it failed (the summary.h5 of the folder still says complete:
    the report reads the case files, as read_summary does)."""
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    row = read_summary(copy)[2]
    with h5py.File(copy / row["file"], "r+") as f:
        f.attrs["status"] = "failed: unstable at t = 3.2 s"
    r = runner.invoke(app, ["report", str(copy)], env=WIDE)
    assert r.exit_code == 0
    first = r.stdout.strip().splitlines()[0]
    assert first.startswith("INCOMPLETE SWEEP: 11 cases: 10 complete, 1 failed, 0 pending (not run yet). FAILED: "
                            f"angle/{row['case']}: unstable at t = 3.2 s")  # fmt: skip
    assert "INCOMPLETE SWEEP" in r.stderr
    doc = sweep_summary(copy)
    assert doc["complete"] is False and doc["counts"]["failed"] == 1 and doc["source"] == "case files"
    assert doc["rows"][2]["status"] == "failed: unstable at t = 3.2 s"
    with h5py.File(copy / "summary.h5") as f:
        assert f.attrs["failed"] == 0, "the report wrote nothing"


def test_a_folder_that_is_not_a_sweep(tmp_path):
    r = runner.invoke(app, ["report", str(tmp_path)])
    assert r.exit_code == 2 and "not a sweep output folder (no sweep.json)" in r.stderr
    (tmp_path / "sweep.json").write_text("{}")
    r = runner.invoke(app, ["report", str(tmp_path)])
    assert r.exit_code == 2 and "no cases/ folder and no summary.h5: no case has run" in r.stderr
    (tmp_path / "cases").mkdir()
    r = runner.invoke(app, ["report", str(tmp_path)])
    assert r.exit_code == 2 and "sweep.json is not the manifest of a pound sweep (no 'columns')" in r.stderr
    assert "Traceback" not in r.output


def test_a_summary_copied_alone_is_read_and_said_so(folder, tmp_path):
    """summary.h5 without sweep.json and cases/ (sent to a colleague): its rows, with a note."""
    (tmp_path / "summary.h5").write_bytes((folder / "summary.h5").read_bytes())
    doc = sweep_summary(tmp_path)
    assert doc["source"] == "summary.h5" and doc["rows"] == read_summary(folder)
    r = runner.invoke(app, ["report", str(tmp_path)], env=WIDE)
    assert r.exit_code == 0 and r.stdout.startswith("Rows read from summary.h5 as the sweep last wrote it")


# --- a killed sweep -----------------------------------------------------------------------------

KILLED = """
set = { "analysis.integrator" = "cdm", "analysis.duration" = 12.0 }
parameters = { "excitation.angle" = ANGLES }
"""


def _report_of_killed(out, sweep):
    """The report's document and its first line, checked against what the folder holds: the
    statuses `pound sweep --dry-run` gives, and the rows of read_summary; nothing written."""
    files = {p: p.stat().st_mtime_ns for p in out.rglob("*")}
    doc = _json(out)
    listed = run_sweep(sweep, out, jobs=1, dry_run=True)
    assert [r["status"] for r in doc["rows"]] == [r["status"] for r in listed.rows]
    assert doc["rows"] == read_summary(out) and doc["source"] == "case files"
    complete = sum(r["status"] == "complete" for r in listed.rows)
    assert complete == len(list((out / "cases").glob("*.h5")))
    n = doc["counts"]
    assert n == {"cases": len(listed.rows), "complete": complete, "failed": 0, "pending": len(listed.rows) - complete}
    r = runner.invoke(app, ["report", str(out)], env=WIDE)
    assert r.exit_code == 0, r.output
    first = r.stdout.strip().splitlines()[0]
    assert first.startswith(f"INCOMPLETE SWEEP: {n['cases']} cases: {complete} complete, 0 failed, "
                            f"{n['pending']} pending (not run yet)")  # fmt: skip
    assert f"{n['cases']}: {complete} complete, 0 failed, {n['pending']} pending" in r.stdout
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*")} == files, "the report wrote nothing"
    return doc


def test_report_of_a_killed_sweep_reads_the_case_files(tmp_path):
    """kill -9 of a real sweep into a fresh folder (no summary.h5 yet), then of the same sweep
    grown from 4 to 8 angles (summary.h5 of the 4): the report lists every case of sweep.json,
    each complete or pending as `--dry-run` sees it, and says so at the top."""
    sweep = tmp_path / "killed.sweep.toml"
    out = tmp_path / "out"

    def write(angles):
        sweep.write_text(f'base = "{(INPUTS / "paper_pounding.toml").as_posix()}"\n'
                         + KILLED.replace("ANGLES", json.dumps(angles)), encoding="utf-8")  # fmt: skip

    write([0, 30, 60, 90])
    sweep_then_kill(sweep, out, 1)
    assert not (out / "summary.h5").exists()
    doc = _report_of_killed(out, sweep)
    assert doc["counts"]["cases"] == 4 and doc["counts"]["pending"] >= 1

    assert run_sweep(sweep, out, jobs=2).ok  # completes the 4 and writes their summary
    write([0, 30, 60, 90, 15, 45, 75, 105])
    sweep_then_kill(sweep, out, 1)
    with h5py.File(out / "summary.h5") as f:
        assert f["cases"].shape == (4,) and f.attrs["complete"] == 4, "the killed sweep left the old summary"
    doc = _report_of_killed(out, sweep)
    assert doc["counts"]["cases"] == 8 and 5 <= doc["counts"]["complete"] < 8
    assert [r["excitation.angle"] for r in doc["rows"]] == [0, 30, 60, 90, 15, 45, 75, 105]


# --- table-valued parameters -------------------------------------------------------------------

RECORDS = """
set = { "analysis.duration" = 1.0 }

[[parameters."excitation.record"]]
name = "Ridgecrest as shipped"
L = { file = "records/ridgecrest2019_ccc.mseed", trace = "HNE", units = "m/s2" }
T = { file = "records/ridgecrest2019_ccc.mseed", trace = "HNN", units = "m/s2" }

[[parameters."excitation.record"]]
L = { file = "records/ridgecrest2019_ccc.mseed", trace = "HNN", units = "m/s2" }
T = { file = "records/ridgecrest2019_ccc.mseed", trace = "HNE", units = "m/s2" }
"""


def test_inline_records_are_short_in_tables_and_whole_in_csv_and_json(tmp_path):
    """A swept inline record: its name (or ~40 characters of its JSON) in the rich table and
    the HTML report; the whole table in summary.csv and --json."""
    from pounding_cli.report.sweep_data import SHORT

    sweep = tmp_path / "records.sweep.toml"
    sweep.write_text(f'base = "{(INPUTS / "paper_pounding.toml").as_posix()}"\n' + RECORDS, encoding="utf-8")
    out = tmp_path / "out"
    assert run_sweep(sweep, out, jobs=2).ok
    rows = _json(out)["rows"]
    records = [r["excitation.record"] for r in rows]
    assert records[0]["name"] == "Ridgecrest as shipped" and records[1]["L"]["trace"] == "HNN"
    whole = [json.dumps(v, ensure_ascii=False) for v in records]
    assert all(len(w) > 3 * SHORT for w in whole)
    with open(out / "summary.csv", encoding="utf-8", newline="") as f:
        table = list(csv.DictReader(f))
    assert [json.loads(line["excitation.record"]) for line in table] == records
    r = runner.invoke(app, ["report", str(out), "--html", str(tmp_path / "r.html")], env={"COLUMNS": "400"})
    assert r.exit_code == 0, r.output
    html_text = (tmp_path / "r.html").read_text(encoding="utf-8")
    unnamed = '{"L": {"file": "records/ridgecrest2019_…'  # the JSON without the unset fields, cut
    assert len(unnamed) == SHORT
    for text in (r.stdout, html_text.replace("&quot;", '"')):
        assert "Ridgecrest as shipped" in text and unnamed in text
        assert not any(w in text for w in whole) and '"trace": "HNE"' not in text
