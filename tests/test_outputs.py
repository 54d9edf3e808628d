"""Outputs: nothing a user owns is ever destroyed (pounding_cli/outputs.py, sweep/store.py).

- an output that is one of the run's inputs (the model, its record definition, its record
  files; reached by the same path, a symbolic link or a hard link) is refused, --force or not;
- `-o DIR/` (and `-o` naming an existing folder) writes DIR/<model>.h5 and says so;
- the output name is claimed at the start: a second run writing it meanwhile is refused
  naming the first; a claim dies with its process (kill -9 included);
- a sweep writes only into a new, empty or sweep-made folder (.pound-sweep), else needs
  --force, which it reports; a file it writes is never one of its inputs;
- `pound report --html`/`--animate` and `pound record --plot` never write over what they read.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.outputs import claim, claim_file

from conftest import INPUTS

runner = CliRunner()
ENV = {"COLUMNS": "200"}


def short_model(folder: Path, name: str = "m.json", duration: float = 0.3, **analysis) -> Path:
    """The wide-gap example, 0.3 s long, in `folder` beside a link to the shipped records."""
    from pounding_cli.model import read_document

    doc = read_document(INPUTS / "paper_wide_gap.toml")
    doc["analysis"].update(duration=duration, **analysis)
    path = folder / name
    path.write_text(json.dumps(doc))
    if not (folder / "records").exists():
        (folder / "records").symlink_to(INPUTS / "records")
    return path


def pound(*args: str) -> object:
    return runner.invoke(app, [str(a) for a in args], env=ENV)


@pytest.mark.parametrize("how", ["same path", "symlink", "hard link", "record file", "record definition"])
def test_the_output_is_never_an_input(tmp_path: Path, how: str) -> None:
    model = short_model(tmp_path)
    record = tmp_path / "quake.mseed"
    shutil.copy(INPUTS / "records" / "ridgecrest2019_ccc.mseed", record)
    doc = json.loads(model.read_text())
    for c in ("L", "T"):
        doc["excitation"]["record"][c]["file"] = "quake.mseed"
    if how == "record definition":
        (tmp_path / "q.record.json").write_text(json.dumps(doc["excitation"]["record"]))
        doc["excitation"]["record"] = "q.record.json"
    model.write_text(json.dumps(doc))
    target = {"same path": model, "record file": record, "record definition": tmp_path / "q.record.json",
              "symlink": tmp_path / "link.h5", "hard link": tmp_path / "hard.h5"}[how]  # fmt: skip
    if how == "symlink":
        target.symlink_to(model.name)
    elif how == "hard link":
        os.link(record, target)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    result = pound("run", model, "-o", target, "--force", "--no-progress")
    assert result.exit_code == 2, result.stderr
    assert f"{target}: is the " in result.stderr and "writing there would destroy it" in result.stderr, result.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()} == before
    assert not any(p.name.endswith((".tmp", ".claim")) for p in tmp_path.iterdir())


@pytest.mark.parametrize("given", ["new/", "existing", "existing/"])
def test_an_output_naming_a_folder_is_written_into(tmp_path: Path, given: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """pathlib drops a trailing slash: `-o new/` used to write a file named `new`."""
    model = short_model(tmp_path)
    (tmp_path / "existing").mkdir()
    monkeypatch.chdir(tmp_path)
    result = pound("run", model.name, "-o", given, "--no-progress")
    assert result.exit_code == 0, result.stderr
    folder = tmp_path / given.rstrip("/")
    assert folder.is_dir() and h5py.is_hdf5(folder / "m.h5")
    assert f"{given} names a folder: the results are in {Path(given) / 'm.h5'}" in result.stderr


def test_a_claimed_output_is_refused_naming_the_holder(tmp_path: Path) -> None:
    model = short_model(tmp_path)
    out = tmp_path / "out.h5"
    with claim(out, "pound run"):
        assert claim_file(out).exists()
        result = pound("run", model, "-o", out, "--no-progress", "--force")
        assert result.exit_code == 2
        assert result.stderr.startswith(f"{out}: is being written by another pound run (pid {os.getpid()} on "), result.stderr
        assert "wait for it to finish or choose another output name" in result.stderr
    assert not claim_file(out).exists() and not out.exists()
    assert pound("run", model, "-o", out, "--no-progress").exit_code == 0


def test_a_claim_dies_with_its_process(tmp_path: Path) -> None:
    """kill -9 leaves the claim file, but not the claim: the next run takes it."""
    out = tmp_path / "out.h5"
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom pathlib import Path\n"
                               "from pounding_cli.outputs import claim\nwith claim(Path(sys.argv[1])):\n"
                               "    print('held', flush=True)\n    time.sleep(60)\n", str(out)],
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(Exception, match="is being written by another pound run"):
            with claim(out):
                pass
    finally:
        holder.kill()
        holder.wait()
    assert claim_file(out).exists()
    with claim(out):
        pass
    assert not claim_file(out).exists()


@pytest.mark.slow
def test_two_runs_started_a_second_apart(tmp_path: Path) -> None:
    """The issue's case: both used to exit 0, the second replacing the first's file. The
    first holds the output while it writes (POUND_TEST_PAUSE_WRITING keeps it there)."""
    model = short_model(tmp_path, duration=2.0)
    out = tmp_path / "out.h5"
    env = {**os.environ, "POUND_TEST_PAUSE_WRITING": f"{tmp_path / 'writing'}:5"}
    first = subprocess.Popen([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(out), "--no-progress"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, text=True)  # fmt: skip
    deadline = time.time() + 120
    while not (tmp_path / "writing").exists() and first.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    second = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(out), "--no-progress",
                             "--force"], capture_output=True, text=True, timeout=120)  # fmt: skip
    assert second.returncode == 2, second.stderr
    assert f"is being written by another pound run (pid {first.pid} " in second.stderr
    assert first.wait(timeout=120) == 0, first.stderr.read()
    with h5py.File(out) as f:
        assert f.attrs["status"] == "complete"


# --- sweeps ----------------------------------------------------------------------------------


def sweep_file(folder: Path) -> Path:
    short_model(folder, "base.json", duration=0.2)
    path = folder / "s.sweep.toml"
    path.write_text('base = "base.json"\nparameters = { "excitation.angle" = [0.0, 90.0] }\n')
    return path


def test_a_sweep_refuses_a_folder_of_the_users_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The issue's case: DIR held the user's own summary.csv and sweep.json, which a sweep
    replaced, exit 0."""
    from test_fuzz import InProcess

    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    sweep = sweep_file(tmp_path)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "summary.csv").write_text("my own table\n")
    (mine / "sweep.json").write_text('{"my": "notes"}\n')
    result = pound("sweep", sweep, "-o", mine)
    assert result.exit_code == 2
    assert result.stderr.startswith(f"{mine}: holds files that no pound sweep wrote (summary.csv, sweep.json); ")
    assert "or pass --force to write into this one" in result.stderr
    assert sorted(p.name for p in mine.iterdir()) == ["summary.csv", "sweep.json"]
    assert (mine / "summary.csv").read_text() == "my own table\n"
    result = pound("sweep", sweep, "-o", mine, "--force")
    assert result.exit_code == 0, result.stderr
    assert (f"{mine}: writing into a folder that no pound sweep made (--force); of what it holds, sweep.json, "
            "summary.csv will be replaced") in result.stderr  # fmt: skip
    assert (mine / ".pound-sweep").is_file()
    assert pound("sweep", sweep, "-o", mine).exit_code == 0  # now a sweep's folder: resumed without --force


def test_a_sweep_writes_into_new_empty_and_earlier_sweep_folders(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from test_fuzz import InProcess

    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    sweep = sweep_file(tmp_path)
    (tmp_path / "empty").mkdir()
    for name in ("new", "empty"):
        result = pound("sweep", sweep, "-o", tmp_path / name)
        assert result.exit_code == 0, result.stderr
        assert (tmp_path / name / ".pound-sweep").is_file()
    earlier = tmp_path / "earlier"
    shutil.copytree(tmp_path / "new", earlier)
    (earlier / ".pound-sweep").unlink()  # a folder of a release before the marker
    result = pound("sweep", sweep, "-o", earlier)
    assert result.exit_code == 0, result.stderr
    assert "2 cases: 2 complete (2 already were)" in result.stderr


def test_a_sweep_never_writes_over_its_inputs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """--force lets a sweep write into the folder of its own files, but not over them: a
    record file named summary.csv would have been replaced."""
    from test_fuzz import InProcess

    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    sweep = sweep_file(tmp_path)
    (tmp_path / "summary.csv").symlink_to(sweep.name)  # an input under a name the sweep writes
    before = sweep.read_text()
    result = pound("sweep", sweep, "-o", tmp_path, "--force")
    assert result.exit_code == 2, result.stderr
    assert f"{tmp_path / 'summary.csv'}: is the file of this sweep" in result.stderr
    assert sweep.read_text() == before and not (tmp_path / "cases").exists()


def test_report_and_record_plot_never_write_over_what_they_read(tmp_path: Path) -> None:
    model = short_model(tmp_path)
    out = tmp_path / "out.h5"
    assert pound("run", model, "-o", out, "--no-progress").exit_code == 0
    data = out.read_bytes()
    for option in ("--html", "--animate"):
        result = pound("report", out, option, out)
        assert result.exit_code == 2 and "is a result file being reported" in result.stderr, result.stderr
    assert out.read_bytes() == data
    at2 = tmp_path / "quake.AT2"
    shutil.copy(Path(__file__).parent / "records" / "data" / "synthetic.AT2", at2)
    text = at2.read_text()
    result = pound("record", at2, "--plot", at2)
    assert result.exit_code == 2 and "is the record being described" in result.stderr, result.stderr
    assert at2.read_text() == text
