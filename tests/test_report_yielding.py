"""`pound report` of yielding members: the member table and its --json numbers (equal to the
HDF5 datasets of /buildings/<b>/yielding), --column narrowing the members, the hysteretic
energy in the energy table and plot, and the hysteresis-loop figure (axes, labels, series).

Two shortened runs (16 s of the record, the strong part): the base-isolated building of
inputs/isolated_moat.toml beside its neighbour, and inputs/paper_inelastic.toml (every column
yields)."""

from __future__ import annotations

import json

import h5py
import jsonschema
import numpy as np
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.model import read_document
from pounding_cli.report import open_run, summary
from pounding_cli.report.energy import energy_figure
from pounding_cli.report.html import report_html
from pounding_cli.report.loops import MAX_COLUMNS, loop_figure, loop_members
from pounding_cli.report.plots import all_figures
from pounding_cli.report.tables import WORST, energy_table, yielding_tables

from conftest import INPUTS, ROOT, load_doc

runner = CliRunner()
WIDE = {"COLUMNS": "200"}
DURATION = 16.0


def _shortened(model: str, folder, duration: float = DURATION):
    doc = read_document(INPUTS / model)
    doc["analysis"]["duration"] = duration
    path = folder / model.replace(".toml", ".h5")
    assert pound.run_model(load_doc(doc), output=path).complete
    return path


@pytest.fixture(scope="module")
def isolated_h5(tmp_path_factory):
    return _shortened("isolated_moat.toml", tmp_path_factory.mktemp("isolated"))


@pytest.fixture(scope="module")
def inelastic_h5(tmp_path_factory):
    return _shortened("paper_inelastic.toml", tmp_path_factory.mktemp("inelastic"))


def _json(*args):
    r = runner.invoke(app, ["report", *map(str, args), "--json"])
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def _members(g):
    raw = g["yielding/members"][()]
    return [(n.decode(), k.decode(), int(s)) for n, k, s in zip(raw["name"], raw["kind"], raw["storey"])]


def test_json_of_yielding_members_equals_the_hdf5(isolated_h5, inelastic_h5):
    schema = json.loads((ROOT / "schemas" / "report.schema.json").read_text(encoding="utf-8"))
    for path in (isolated_h5, inelastic_h5):
        doc = _json(path)
        jsonschema.validate(doc, schema, cls=jsonschema.Draft202012Validator)
        with h5py.File(path) as f:
            for b in doc["buildings"]:
                g = f[f"buildings/{b['name']}"]
                assert b["isolated"] == bool(g.attrs["isolated"])
                if "yielding" not in g:
                    assert b["yielding"] is None
                    continue
                y = b["yielding"]
                members = _members(g)
                assert [(m["name"], m["kind"], m["storey"]) for m in y["members"]] == members
                peak, mu = g["yielding/peak"][()], g["yielding/ductility"][()]
                residual = g["yielding/residual_deflection"][()]
                raw = g["yielding/members"][()]
                for i, m in enumerate(y["members"]):
                    assert m["peak_deflection_m"] == peak[i, :3].tolist()
                    assert m["peak_force_N"] == peak[i, 3:].tolist()
                    assert m["ductility"] == mu[i].tolist()
                    assert m["residual_deflection_m"] == residual[i].tolist()
                    assert m["residual_m"] == np.hypot(*residual[i])
                    assert m["yield_force_N"] == raw["yield_force"][i].tolist()
                    assert [m["X_m"], m["Y_m"]] == [raw["X"][i], raw["Y"][i]]
                kinds = np.array([k for _, k, _ in members])
                columns, isolators = kinds == "column", kinds == "isolator"
                assert y["columns"] == columns.sum() and y["isolators"] == isolators.sum()
                if columns.any():
                    assert y["max_ductility"] == mu[columns].max()
                    assert max(y["max_ductility_member"]["ductility"]) == y["max_ductility"]
                    storeys = raw["storey"]
                    for s in y["storey_ductility"]:
                        here = columns & (storeys == s["storey"])
                        assert s["columns"] == here.sum()
                        assert s["ductility_x"] == mu[here, 0].max() and s["ductility_y"] == mu[here, 1].max()
                        assert s["yielded"] == (mu[here].max(axis=1) > 1).sum()
                        assert s["residual_m"] == np.hypot(residual[here, 0], residual[here, 1]).max()
                else:
                    assert y["max_ductility"] is None and y["storey_ductility"] == []
                if isolators.any():
                    assert y["peak_isolator_displacement_m"] == peak[isolators, 2].max()
                    assert y["peak_isolator_force_N"] == peak[isolators, 5].max()
                else:
                    assert y["peak_isolator_displacement_m"] is None


def test_the_examples_yield(isolated_h5, inelastic_h5):
    iso = {b["name"]: b for b in summary(isolated_h5)["buildings"]}
    assert iso["isolated"]["isolated"] and iso["isolated"]["yielding"]["isolators"] == 9
    assert iso["isolated"]["yielding"]["columns"] == 0 and iso["neighbour"]["yielding"] is None
    assert iso["isolated"]["yielding"]["peak_isolator_displacement_m"] > 0.0087  # past the yield displacement
    inel = {b["name"]: b for b in summary(inelastic_h5)["buildings"]}
    assert inel["left"]["yielding"]["columns"] == 36 and inel["right"]["yielding"]["columns"] == 45
    assert inel["left"]["yielding"]["max_ductility"] > 1
    assert [s["storey"] for s in inel["left"]["yielding"]["storey_ductility"]] == [1, 2, 3, 4]


def test_column_narrows_the_members(isolated_h5, inelastic_h5):
    doc = _json(inelastic_h5, "--column", "left:C9")
    left, right = doc["buildings"]
    assert [(m["name"], m["storey"]) for m in left["yielding"]["members"]] == [("C9", s) for s in (1, 2, 3, 4)]
    assert right["yielding"]["members"] == [] and right["yielding"]["columns"] == 45  # the totals stay
    assert len(left["yielding"]["storey_ductility"]) == 4
    doc = _json(isolated_h5, "--column", "C5")  # isolators are not column lines: they all stay
    assert [m["name"] for m in doc["buildings"][0]["yielding"]["members"]] == [f"I{i}" for i in range(1, 10)]


def test_member_tables(isolated_h5, inelastic_h5):
    r = runner.invoke(app, ["report", str(inelastic_h5)], env=WIDE)
    assert r.exit_code == 0, r.output
    doc = summary(inelastic_h5)
    left = doc["buildings"][0]["yielding"]
    assert f"Inelastic columns: left, the {WORST} most ductile of 36" in r.stdout
    assert "Inelastic columns: left, largest peak ductility per storey (member local axes)" in r.stdout
    s1 = left["storey_ductility"][0]
    cells = [[c.strip() for c in line.split("│")[1:-1]] for line in r.stdout.splitlines() if line.startswith("│")]
    assert ["1", f"{s1['yielded']} of 9", f"{s1['ductility_x']:.3g}", s1["x_column"]] in [c[:4] for c in cells]
    tables = {t.title: t for t in yielding_tables(doc)}
    per_storey = tables["Inelastic columns: left, largest peak ductility per storey (member local axes)"]
    assert [row[0] for row in per_storey.rows] == ["1", "2", "3", "4"]
    assert per_storey.rows[0][1] == f"{s1['yielded']} of 9"
    worst = tables[f"Inelastic columns: left, the {WORST} most ductile of 36"]
    assert len(worst.rows) == WORST
    top = max(left["members"], key=lambda m: max(m["ductility"]))
    assert worst.rows[0][2:4] == [f"{top['ductility'][0]:.3g}", f"{top['ductility'][1]:.3g}"]
    # --column: that column line's members, storey by storey
    doc = summary(inelastic_h5, column="left:C9")
    (c9,) = yielding_tables(doc)
    assert c9.title == "Inelastic columns: left, column left:C9 (member local axes)"
    members = doc["buildings"][0]["yielding"]["members"]
    assert [row[:4] for row in c9.rows] == [[m["name"], str(m["storey"]), f"{m['ductility'][0]:.3g}",
                                             f"{m['ductility'][1]:.3g}"] for m in members]  # fmt: skip
    # isolators: peak resultant displacement and force, residual displacement
    r = runner.invoke(app, ["report", str(isolated_h5)], env=WIDE)
    assert r.exit_code == 0, r.output
    assert "Isolators: isolated (storey 1, the isolation storey)" in r.stdout
    doc = summary(isolated_h5)
    (iso,) = yielding_tables(doc)
    for row, m in zip(iso.rows, doc["buildings"][0]["yielding"]["members"]):
        assert row[:3] == [m["name"], f"{1e3 * m['peak_deflection_m'][2]:.4g}", f"{m['peak_force_N'][2] / 1e3:.4g}"]
        assert row[-1] == f"{1e3 * m['residual_m']:.3g}"
    assert f"{1e3 * doc['buildings'][0]['yielding']['members'][0]['peak_deflection_m'][2]:.4g}" in r.stdout


def test_energy_includes_the_hysteretic_energy(isolated_h5):
    run = open_run(isolated_h5)
    doc = summary(run)
    table = energy_table(doc)
    k = table.headers.index("hysteretic")
    dissipated = run.result.energy_column("hysteretic")[-1]
    assert dissipated > 0 and table.rows[0][k] == f"{dissipated / 1e3:.4g}"
    fig = energy_figure(run)
    top = fig.axes[0]
    stacked = [c.get_label() for c in top.collections]
    assert "hysteretic" in stacked
    poly = top.collections[stacked.index("hysteretic")]
    below = sum(run.result.energy_column(n) for n in stacked[: stacked.index("hysteretic")]) / 1e3
    top_edge = poly.get_paths()[0].vertices[:, 1].max()
    np.testing.assert_allclose(top_edge, (below + run.result.energy_column("hysteretic") / 1e3).max())


def _series(ax):
    return {ln.get_label(): ln for ln in ax.get_lines() if not ln.get_label().startswith("_")}


def test_loop_figure_of_the_isolators(isolated_h5):
    run = open_run(isolated_h5)
    b = run.result.buildings["isolated"]
    y = b.yielding
    fig = loop_figure(run, "isolated")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == 9
    for i, ax in enumerate(panels):
        assert ax.get_xlabel() == "deflection δ (mm)" and ax.get_ylabel() == "force f (kN)"
        assert ax.get_title().startswith(f"I{i + 1}, isolator: μ ")
        lines = _series(ax)
        assert list(lines) == ["local x", "local y", "±F_y local x", "±F_y local y"]
        for k, axis in enumerate(("local x", "local y")):
            np.testing.assert_array_equal(lines[axis].get_xdata(), 1e3 * y.deflection[:, i, k])
            np.testing.assert_array_equal(lines[axis].get_ydata(), y.force[:, i, k] / 1e3)
        fy = y.members["yield_force"][i] / 1e3
        levels = sorted({round(float(ln.get_ydata()[0]), 9) for ln in ax.get_lines() if ln.get_linestyle() != "-"})
        np.testing.assert_allclose(levels, [-fy[0], fy[0]])  # both axes' lines: F_y equal for a round bearing
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == ["local x", "local y", "±F_y local x", "±F_y local y"]
    assert "Hysteresis loops: isolated, isolators" in fig.get_suptitle()
    empty = loop_figure(run, "neighbour")  # no yielding members (the plots leave it out)
    assert [t.get_text() for ax in empty.axes for t in ax.texts] == ["no yielding members"]


def test_loop_figure_of_columns(inelastic_h5):
    run = open_run(inelastic_h5)
    b = run.result.buildings["left"]
    y = b.yielding
    chosen = loop_members(b)
    assert [int(y.members["storey"][i]) for i in chosen] == [1, 2, 3, 4]  # the most ductile of each storey
    for i in chosen:
        here = y.members["storey"] == y.members["storey"][i]
        assert y.ductility[i].max() == y.ductility[here].max()
    fig = loop_figure(run, "left")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == 4 <= MAX_COLUMNS
    assert [ax.get_title().split(":")[0] for ax in panels] == [
        f"{y.members['name'][i]}, storey {y.members['storey'][i]}" for i in chosen]  # fmt: skip
    fig = loop_figure(run, "left", column="C9")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title().split(":")[0] for ax in panels] == [f"C9, storey {s}" for s in (1, 2, 3, 4)]
    c9_4 = [i for i, m in enumerate(y.members) if m["name"] == "C9" and m["storey"] == 4][0]
    np.testing.assert_array_equal(_series(panels[3])["local y"].get_ydata(), y.force[:, c9_4, 1] / 1e3)
    assert "column C9" in fig.get_suptitle()


def test_plots_and_html_have_the_loops(isolated_h5, inelastic_h5, tmp_path):
    runs = [open_run(isolated_h5)]
    assert [s for s in all_figures(runs) if s.endswith("loops")] == ["isolated-loops"]
    both = [open_run(isolated_h5), open_run(inelastic_h5)]
    assert [s for s in all_figures(both) if s.endswith("loops")] == [
        "isolated_moat-isolated-loops", "paper_inelastic-left-loops", "paper_inelastic-right-loops"]  # fmt: skip
    out = tmp_path / "plots"
    r = runner.invoke(app, ["report", str(isolated_h5), "--plots", str(out), "--html", str(tmp_path / "r.html")])
    assert r.exit_code == 0, r.output
    assert (out / "isolated-loops.png").stat().st_size > 10_000
    text = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "isolated: Hysteresis loops of the yielding members" in text and "Isolators: isolated" in text
    assert text.count("<img") == len(all_figures(runs))
    assert not [s for s in all_figures(runs, column="neighbour:C1") if s.endswith("loops")]
    assert "Hysteresis loops" not in report_html(runs, column="neighbour:C1", fmt="svg")
