"""`pound report --animate`: the plan-view animation has the stated number of frames, is short
and small by default, and refuses what it cannot write."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli.cli import app
from pounding_cli.errors import InputError
from pounding_cli.report import open_run
from pounding_cli.report.animate import DEFAULT_MAX_FRAMES, DEFAULT_WINDOW_S, PlanMovie, animate_plan, frame_indices

from conftest import INPUTS

runner = CliRunner()


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    path = tmp_path_factory.mktemp("animation") / "pounding.h5"
    assert pound.run_model(INPUTS / "paper_pounding.toml", output=path).complete
    return open_run(path)


def test_frames_follow_start_end_and_stride(run):
    frames = frame_indices(run, start=14.0, end=16.0, stride=10)
    np.testing.assert_array_equal(frames, np.arange(1400, 1601, 10))  # 0.01 s samples: 21 frames
    assert frame_indices(run, start=14.0, end=16.0, stride=1, max_frames=50).size == 50  # capped
    assert frame_indices(run, start=14.0, end=16.0, max_frames=50).size == 41  # the stride grows to fit: 5


def test_default_is_short(run):
    frames = frame_indices(run)
    t = run.result.time[frames]
    assert frames.size == DEFAULT_MAX_FRAMES
    assert t[-1] - t[0] <= DEFAULT_WINDOW_S
    assert t[0] < run.result.contact.events["t_peak"][0] < t[-1]  # centred on the impact


def test_gif_has_the_stated_frames(run, tmp_path):
    path = tmp_path / "level3.gif"
    n = animate_plan(run, path, level=3, start=14.0, end=16.0, stride=10, fps=10)
    assert n == 21
    with Image.open(path) as gif:
        assert gif.n_frames == 21
        assert gif.size == (512, gif.size[1]) and gif.info["duration"] == 100
    assert path.stat().st_size < 500_000


def test_contacts_are_highlighted(run):
    frames = frame_indices(run, start=14.55, end=14.62, stride=1)
    movie = PlanMovie(run, 3, None, frames)
    images = movie.render()
    red = [int((np.abs(img.astype(int) - [214, 39, 40]).sum(axis=2) < 30).sum()) for img in images]
    hit = int(np.argmax(red))
    assert movie.run.result.time[frames[hit]] == pytest.approx(14.58, abs=0.006)  # the impact at 14.583 s
    assert red[0] == 0 < red[hit]


def test_cli_animates_all_levels(run, tmp_path):
    path = tmp_path / "all.gif"
    r = runner.invoke(app, ["report", str(run.path), "--animate", str(path), "--max-frames", "12"])
    assert r.exit_code == 0, r.output
    assert f"{path}: 12 frames" in r.stderr
    with Image.open(path) as gif:
        assert gif.n_frames == 12


def test_mp4_needs_ffmpeg(run, tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))  # no ffmpeg anywhere
    r = runner.invoke(app, ["report", str(run.path), "--animate", str(tmp_path / "a.mp4")])
    assert r.exit_code == 2 and "needs ffmpeg" in r.stderr


def test_mp4_pipes_every_frame_to_ffmpeg(run, tmp_path, monkeypatch):
    """A stand-in ffmpeg that stores what it is given: frames × width × height × 3 bytes."""
    fake = tmp_path / "ffmpeg"
    fake.write_text('#!/bin/sh\nfor last; do :; done\ncat > "$last"\n')
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    out = tmp_path / "a.mp4"
    n = animate_plan(run, out, level=1, start=10.0, end=10.5, stride=5)
    movie = PlanMovie(run, 1, None, frame_indices(run, 10.0, 10.5, 5))
    w, h = movie.size
    assert n == 11 and out.stat().st_size == n * w * h * 3


@pytest.mark.parametrize("name, words", [("a.avi", "name a .gif or .mp4 file"), ("no/a.gif", "does not exist")])
def test_bad_targets(run, tmp_path, name, words):
    with pytest.raises(InputError, match=words):
        animate_plan(run, tmp_path / name)


def test_bad_window_and_level(run, tmp_path):
    with pytest.raises(InputError, match="no stored sample between"):
        frame_indices(run, start=50.0, end=60.0)
    r = runner.invoke(app, ["report", str(run.path), "--animate", str(tmp_path / "a.gif"), "--level", "7"])
    assert r.exit_code == 2 and "level 7 does not exist: the run has levels 1 to 4" in r.stderr
