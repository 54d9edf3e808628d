"""`pound report --html`: one self-contained file with the tables and every plot embedded."""

from __future__ import annotations

import re

import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.report import open_run
from pounding_cli.report.html import report_html

from conftest import EXAMPLE, INPUTS

runner = CliRunner()


@pytest.fixture(scope="module")
def pounding(tmp_path_factory):
    path = tmp_path_factory.mktemp("html") / "pounding.h5"
    assert pound.run_model(INPUTS / "paper_pounding.toml", output=path).complete
    return path


def _self_contained(text: str) -> None:
    assert not re.search(r"""(src|href)=["'](?!data:)""", text), "an external reference"
    assert "<script" not in text


def test_html_embeds_tables_and_plots(pounding, tmp_path):
    out = tmp_path / "report.html"
    r = runner.invoke(app, ["report", str(pounding), "--html", str(out), "--column", "left:C9"])
    assert r.exit_code == 0, r.output
    text = out.read_text(encoding="utf-8")
    _self_contained(text)
    assert text.count('src="data:image/png;base64,') == 7
    for words in ("<caption>Run</caption>", "<caption>Buildings</caption>", "left, column C9",
                  "Impacts per contact pair", "Plan view of every level", "Peak storey shears: left",
                  "Peak column forces: left, column C9", "Peak storey shear and torque per storey"):  # fmt: skip
        assert words in text, words
    assert 'class="failed"' not in text


def test_html_reuses_the_written_plots_and_the_animation(pounding, tmp_path):
    out = tmp_path / "r.html"
    r = runner.invoke(app, ["report", str(pounding), "--plots", str(tmp_path / "p"), "--animate",
                            str(tmp_path / "a.gif"), "--max-frames", "5", "--html", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    text = out.read_text(encoding="utf-8")
    assert text.count("data:image/png;base64,") == 7 and text.count("data:image/gif;base64,") == 1
    import base64

    plan = base64.b64encode((tmp_path / "p" / "plan.png").read_bytes()).decode()
    assert plan in text  # the very file --plots wrote


def test_html_svg(pounding):
    text = report_html([open_run(pounding)], fmt="svg")
    assert text.count("data:image/svg+xml;base64,") == 7


def test_failed_run_is_flagged_first(pounding, tmp_path, monkeypatch):
    from pounding_cli import api
    from pounding_cli.assembly import TimeGrid

    def unstable(analysis, omega_max, duration, *args, **kwargs):
        limit = 2 / omega_max
        return TimeGrid(dt=1.05 * limit, stride=1, n_steps=int(duration / limit), stability_limit=limit)

    monkeypatch.setattr(api, "time_grid", unstable)
    failed = tmp_path / "failed.h5"
    assert not pound.run_model(EXAMPLE, output=failed).complete
    text = report_html([open_run(failed), open_run(pounding)])
    body = text[text.index("<body>"):]
    assert body.index('class="failed"') < body.index("<table")
    assert "FAILED RUN" in body and str(failed) in body
