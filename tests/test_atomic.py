"""One atomic writer for every file pound writes (pounding_cli/atomic.py): a writer that fails
midway, however, leaves neither the final name nor its temporary file, and an older file of
that name untouched; an OSError while writing is an InputError naming the final path."""

from __future__ import annotations

import errno
import json
import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli.atomic import atomic_path, stale_temporaries, temporary_name, write_text
from pounding_cli.errors import InputError

from conftest import ROOT, example_doc, load_doc


class Midway(Exception):
    """Raised by a writer after it has written part of its file."""


def _folder_listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.mark.parametrize("failure", [Midway, KeyboardInterrupt])
def test_a_writer_that_raises_midway_leaves_neither_file(tmp_path, failure):
    target = tmp_path / "out.txt"
    with pytest.raises(failure):
        with atomic_path(target) as tmp:
            assert tmp.parent == tmp_path and tmp.name == f".out.txt.{os.getpid()}.tmp"
            tmp.write_text("half of it")
            raise failure()
    assert _folder_listing(tmp_path) == []


def test_an_older_file_survives_a_failed_write_and_is_replaced_by_a_good_one(tmp_path):
    target = write_text(tmp_path / "summary.csv", "old\n")
    with pytest.raises(Midway):
        with atomic_path(target) as tmp:
            tmp.write_text("new, but only half")
            raise Midway
    assert target.read_text() == "old\n" and _folder_listing(tmp_path) == ["summary.csv"]
    write_text(target, "new\n")
    assert target.read_text() == "new\n" and _folder_listing(tmp_path) == ["summary.csv"]


def test_an_os_error_names_the_final_path_and_the_reason(tmp_path):
    (tmp_path / "plain").write_text("a regular file, not a folder")
    target = tmp_path / "plain" / "out.h5"
    with pytest.raises(InputError) as caught:
        with atomic_path(target) as tmp:
            h5py.File(tmp, "w").close()
    assert str(caught.value) == f"{target}: cannot write the file (Not a directory)"
    with pytest.raises(InputError, match=re.escape(f"{tmp_path / 'x.csv'}: cannot write the file (No space left on device)")):
        with atomic_path(tmp_path / "x.csv") as tmp:
            tmp.write_text("partial")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert _folder_listing(tmp_path) == ["plain"]


def test_stale_temporaries_are_those_of_dead_processes(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = tmp_path / f".abc.h5.{int(dead.stdout)}.tmp"
    mine = temporary_name(tmp_path / "def.h5")
    for path in (stale, mine, tmp_path / "abc.h5", tmp_path / ".hidden"):
        path.write_text("x")
    assert stale_temporaries(tmp_path) == [stale]


# --- the writers themselves, made to fail midway ---------------------------------------------------


@pytest.fixture(scope="module")
def short_result():
    doc = example_doc()
    doc["analysis"]["duration"] = 0.5
    return pound.run_model(load_doc(doc))


def test_hdf5_writer_failing_midway(tmp_path, monkeypatch, short_result):
    from pounding_cli.results import hdf5

    def half_written(group, contact, *scales):
        group.create_dataset("events", data=np.zeros(3))  # something is in the file already
        raise Midway

    monkeypatch.setattr(hdf5, "_write_contact", half_written)
    with pytest.raises(Midway):
        hdf5.write_hdf5(short_result, tmp_path / "out.h5")
    assert _folder_listing(tmp_path) == []


def test_figure_writer_failing_midway(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    from pounding_cli.records.plot import save_figure

    def half_saved(self, fname, **kwargs):
        Path(fname).write_bytes(b"\x89PNG half")
        raise Midway

    monkeypatch.setattr(Figure, "savefig", half_saved)
    with pytest.raises(Midway):
        save_figure(Figure(), tmp_path / "record.png")
    assert _folder_listing(tmp_path) == []


def test_gif_writer_failing_midway(tmp_path, monkeypatch):
    from PIL import Image

    from pounding_cli.report import animate

    def half_saved(self, fp, *args, **kwargs):
        Path(fp).write_bytes(b"GIF89a half")
        raise Midway

    monkeypatch.setattr(Image.Image, "save", half_saved)
    with pytest.raises(Midway):
        animate._write_gif([np.zeros((8, 8, 3), dtype=np.uint8)] * 2, tmp_path / "plan.gif", 12)
    assert _folder_listing(tmp_path) == []


def test_mp4_is_written_by_ffmpeg_under_the_temporary_name(tmp_path, monkeypatch):
    """ffmpeg gets the temporary name (and -f mp4, as that name has no suffix); when it fails
    midway, nothing is left."""
    from pounding_cli.report import animate

    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    log = tmp_path / "argv.txt"
    fake = bin_dir / "ffmpeg"
    fake.write_text(f'#!/bin/sh\necho "$@" > {log}\nfor last; do :; done\nhead -c 10 > "$last"\nexit $FAKE_EXIT\n')
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.environ['PATH']}")
    out = tmp_path / "movie" / "plan.mp4"
    out.parent.mkdir()
    frames = [np.zeros((8, 8, 3), dtype=np.uint8)] * 3
    monkeypatch.setenv("FAKE_EXIT", "1")
    with pytest.raises(InputError, match="ffmpeg failed"):
        animate._write_mp4(frames, out, 12, (8, 8))
    assert _folder_listing(out.parent) == []
    assert log.read_text().split()[-3:] == ["-f", "mp4", str(temporary_name(out))]
    monkeypatch.setenv("FAKE_EXIT", "0")
    animate._write_mp4(frames, out, 12, (8, 8))
    assert _folder_listing(out.parent) == ["plan.mp4"] and out.read_bytes() == bytes(10)


def test_sweep_summary_failing_midway(tmp_path, monkeypatch):
    from pounding_cli.sweep import summary
    from pounding_cli.sweep.store import OutputFolder

    def half_written(path, manifest, rows):
        Path(path).write_bytes(b"\x89HDF half")
        raise Midway

    monkeypatch.setattr(summary, "_write_h5", half_written)
    with pytest.raises(Midway):
        summary.write_summary(OutputFolder(tmp_path), {"columns": []}, [])
    assert _folder_listing(tmp_path) == []


# --- no other writer -------------------------------------------------------------------------------

WRITING = re.compile(
    r"os\.replace\(|\.rename\(|\.write_text\(|\.write_bytes\(|open\([^)]*[\"'][wax]|savefig\(|"
    r"h5py\.File\([^)]*[\"'][wax]|\.save\("
)
NOT_OUTPUTS = {
    ("sweep/store.py", 'open(path, "a+"'): "the sweep folder's lock file: it holds no results",
    ("solver/kernel_cache.py", "stamp.write_text("): "numba's cache stamp: a partial stamp only recompiles",
    ("report/html.py", "savefig(buffer"): "an image embedded in the HTML, drawn in memory",
    ("sweep/summary.py", 'h5py.File(path, "w"'): "_write_h5, called by write_summary with atomic_path's name",
}


def test_every_file_pound_writes_goes_through_the_atomic_writer():
    """Every call that writes a file either writes the name atomic_path yields (`tmp`) or is
    one of the few listed here, with the reason it need not be atomic."""
    found = []
    for path in sorted((ROOT / "pounding_cli").rglob("*.py")):
        name = path.relative_to(ROOT / "pounding_cli").as_posix()
        if name == "atomic.py":
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            if not WRITING.search(line) or "(tmp" in line:
                continue
            if not any(name == where and text in line for where, text in NOT_OUTPUTS):
                found.append(f"{name}:{number}: {line.strip()}")
    assert found == [], "writes a file in place, not through pounding_cli.atomic:\n" + "\n".join(found)


# --- late write failures: the run completed, its file cannot be written ----------------------------


def test_a_folder_that_vanishes_during_the_run_is_exit_2_naming_the_path(tmp_path):
    """A real late failure: the output folder is replaced by a regular file while the time loop
    runs (after the up-front checks passed), so the HDF5 file cannot be created."""
    import shutil

    folder = tmp_path / "results"
    output = folder / "out.h5"
    doc = example_doc()
    doc["analysis"]["duration"] = 0.5

    def replace_the_folder(done, total):
        if folder.is_dir():
            shutil.rmtree(folder)
            folder.write_text("now a regular file")

    with pytest.raises(InputError) as caught:
        pound.run_model(load_doc(doc), output=output, progress=replace_the_folder)
    assert caught.value.exit_code == 2
    assert str(caught.value) == (
        f"{output}: cannot write the file (Not a directory); the analysis ran (complete) but its results were not "
        "written: make room or give another output file, and run again"
    )
    assert _folder_listing(tmp_path) == ["results"] and folder.read_text() == "now a regular file"


def test_disk_full_while_writing_is_exit_2_with_the_path_and_nothing_written(tmp_path, monkeypatch):
    """`pound run` whose HDF5 writing fails midway as h5py reports a full disk (an OSError
    whose text carries errno 28): exit 2, one line naming the output, no traceback, no file."""
    from typer.testing import CliRunner

    from pounding_cli.cli import app

    doc = example_doc()
    doc["analysis"]["duration"] = 0.5
    model = tmp_path / "model.json"
    model.write_text(json.dumps(doc))
    (tmp_path / "records").symlink_to(ROOT / "inputs" / "records")
    written = []
    create = h5py.Group.create_dataset

    def filling_up(self, name, *args, **kwargs):
        if len(written) == 5:
            raise OSError(f"Can't write data (file write failed: time = Mon Jan  1 00:00:00 2024, filename = "
                          f"'{self.file.filename}', file descriptor = 5, errno = 28, error message = 'No space left "
                          "on device', buf = 0x1, total write size = 8, bytes this sub-write = 8, bytes actually "
                          "written = 18446744073709551615, offset = 0)")  # fmt: skip
        written.append(name)
        return create(self, name, *args, **kwargs)

    monkeypatch.setattr(h5py.Group, "create_dataset", filling_up)
    out = tmp_path / "results" / "out.h5"
    result = CliRunner().invoke(app, ["run", str(model), "-o", str(out), "--no-progress"])
    assert result.exit_code == 2, result.output
    assert result.stderr == (f"{out}: cannot write the file (No space left on device); the analysis ran (complete) "
                             "but its results were not written: make room or give another output file, and run "
                             "again\n")  # fmt: skip
    assert _folder_listing(out.parent) == []
