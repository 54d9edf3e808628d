"""Input files: what a path may name, and what pound reads from it.

Every input (a model, a sweep file, a record definition, a record file) is read only when it
is a regular file, and at most its size limit plus one byte of it (pounding_cli/files.py): a
FIFO, a device, a socket, a folder or a symbolic-link loop is refused at once, exit 2, naming
the file (and, for a record file, the field that names it). Each case runs in a subprocess
with a timeout, so that a reader that blocks (a FIFO) or never ends (/dev/zero) fails the test
instead of hanging it.

Also here: what is accepted that was refused (a UTF-8 BOM in TOML, Fortran D exponents in AT2
data, epoch times in a two-column record).
"""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding_cli.files import FileRefused, read_regular
from pounding_cli.model import read_document
from pounding_cli.records.read import read_accelerogram

from conftest import INPUTS

DATA = Path(__file__).parent / "records" / "data"
MODEL = (Path(__file__).parent / "invalid" / "invalid_integer_5000_digits.toml").read_text().replace("1" * 5000, "1000.0")
"""A valid one-building model (tests/invalid's control model) whose record is the shipped one."""


def pound(args: list[str], cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pounding_cli", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout)  # fmt: skip


def oddity(folder: Path, kind: str, name: str) -> Path:
    """A path `name` in `folder` that is not a regular file, of the given kind."""
    path = folder / name
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "zero":
        path.symlink_to("/dev/zero")
    elif kind == "urandom":
        path.symlink_to("/dev/urandom")
    elif kind == "loop":
        path.symlink_to(path.name)
    elif kind == "dangling":
        path.symlink_to("nowhere")
    elif kind == "folder":
        path.mkdir()
    elif kind == "socket":
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(path))
        server.close()
    else:
        raise AssertionError(kind)
    return path


KINDS = {
    "fifo": "is a FIFO (named pipe), not a regular file",
    "zero": "is a character device, not a regular file",
    "urandom": "is a character device, not a regular file",
    "loop": "cannot read the file: its symbolic links form a loop",
    "dangling": "no such file: the symbolic link points to 'nowhere'",
    "socket": "is a socket, not a regular file",
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_model_path_that_is_not_a_regular_file(kind: str, tmp_path: Path) -> None:
    path = oddity(tmp_path, kind, "model.toml")
    proc = pound(["validate", path.name], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith(f"model.toml: {KINDS[kind]}"), proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("kind", ["fifo", "zero", "loop", "folder"])
def test_sweep_and_record_definition_paths_that_are_not_regular_files(kind: str, tmp_path: Path) -> None:
    oddity(tmp_path, kind, "quake.record.toml")
    (tmp_path / "model.toml").write_text(MODEL.split("[excitation.record]")[0].replace(
        "[excitation]", '[excitation]\nrecord = "quake.record.toml"'), encoding="utf-8")  # fmt: skip
    proc = pound(["validate", "model.toml"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "excitation.record: " in proc.stderr, proc.stderr  # names the file, or the device it links to

    oddity(tmp_path, kind, "s.sweep.toml")
    proc = pound(["sweep", "s.sweep.toml", "-o", "out"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("s.sweep.toml: "), proc.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kind", ["fifo", "zero", "urandom", "loop", "socket"])
def test_record_file_that_is_not_a_regular_file(kind: str, tmp_path: Path) -> None:
    """The component file of a record: refused before obspy or the text reader opens it."""
    oddity(tmp_path, kind, "quake.txt")
    record = "[excitation.record]\nL = { file = \"quake.txt\", units = \"g\", dt = 0.01 }\n"
    model = MODEL.split("[excitation.record]")[0].replace('components = ["L", "T"]', 'components = ["L"]')
    (tmp_path / "model.toml").write_text(model + record + "[analysis]\nduration = 1.0\n", encoding="utf-8")
    proc = pound(["validate", "model.toml"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "excitation.record.L.file: " in proc.stderr, proc.stderr  # names the file, or the device it links to
    proc = pound(["record", "quake.txt", "--units", "g", "--dt", "0.01"], tmp_path)
    assert proc.returncode == 2 and "quake.txt: " in proc.stderr, proc.stderr


def test_unreadable_model(tmp_path: Path) -> None:
    if os.geteuid() == 0:
        pytest.skip("root reads any file: permissions cannot make one unreadable")
    path = tmp_path / "model.toml"
    path.write_text(MODEL, encoding="utf-8")
    path.chmod(0)
    proc = pound(["validate", "model.toml"], tmp_path)
    assert proc.returncode == 2 and "model.toml: cannot read the file (Permission denied)" in proc.stderr


def test_at_most_limit_plus_one_byte_is_read(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A file that reports a small size but holds more (one that grows while read, or a
    /proc file) is refused after limit + 1 bytes, not read to its end."""
    path = tmp_path / "a.toml"
    path.write_bytes(b"x" * 100)
    assert read_regular(path, 100) == b"x" * 100
    with pytest.raises(FileRefused, match="100 bytes|more than 99"):
        read_regular(path, 99)
    reads = []
    real = os.read

    def counted(fd: int, n: int) -> bytes:
        reads.append(n)
        return real(fd, n)

    monkeypatch.setattr(os, "fstat", lambda fd: os.stat_result((0o100644, 0, 0, 1, 0, 0, 0, 0, 0, 0)))
    monkeypatch.setattr(os, "read", counted)
    with pytest.raises(FileRefused, match="grew while it was read"):
        read_regular(path, 10)
    assert sum(reads) <= 11 + 1, reads


def test_utf8_bom_in_toml_is_dropped(tmp_path: Path) -> None:
    path = tmp_path / "model.toml"
    path.write_bytes(b"\xef\xbb\xbf" + MODEL.encode())
    assert read_document(path)["title"] == "One small building, one mistake"
    json_path = tmp_path / "model.json"
    json_path.write_bytes(b"\xef\xbb\xbf" + b'{"title": "t"}')
    assert read_document(json_path) == {"title": "t"}


def test_huge_integer_names_its_field_in_toml_and_json(tmp_path: Path) -> None:
    from pounding_cli.errors import InputError

    for name, text in (("a.toml", "[analysis]\nduration = -" + "7" * 4301 + "\n"),
                       ("a.json", '{"analysis": {"duration": [' + "7" * 4301 + "]}}")):  # fmt: skip
        path = tmp_path / name
        path.write_text(text)
        with pytest.raises(InputError, match=r"analysis\.duration(\[0\])?: a whole number of 4301 digits"):
            read_document(path)


def test_at2_fortran_d_exponents(tmp_path: Path) -> None:
    """Values written 0.306D+00 (Fortran's double-precision exponent) read as 0.306E+00."""
    text = (DATA / "synthetic.AT2").read_text()
    head, body = text.split("\n", 4)[:4], text.split("\n", 4)[4]
    fortran = tmp_path / "fortran.AT2"
    fortran.write_text("\n".join(head) + "\n" + body.replace("E+", "D+").replace("E-", "d-"))
    assert "D+" in fortran.read_text() and "d-" in fortran.read_text()
    a, b = read_accelerogram(DATA / "synthetic.AT2", units="g"), read_accelerogram(fortran, units="g")
    np.testing.assert_array_equal(a.acceleration, b.acceleration)


@pytest.mark.parametrize("start", [0.0, 1.7e9, 1e11])
def test_two_column_epoch_times(start: float, tmp_path: Path) -> None:
    """Times of a large value (Unix epoch seconds) are uniform to their own rounding: a record
    at 0.01 s starting at 1.7e9 s is accepted, with Δt = 0.01 s to 1e-8."""
    path = tmp_path / "epoch.txt"
    k = np.arange(3000)
    path.write_text("".join(f"{start + i * 0.01:.2f} {0.1 * np.sin(i / 7):.6f}\n" for i in k))
    record = read_accelerogram(path, units="m/s2")
    assert abs(record.dt - 0.01) < 1e-8 * 0.01 * max(1.0, start / 1e9) * 100, record.dt
    assert record.acceleration.size == k.size


def test_epoch_times_still_refuse_a_missing_sample(tmp_path: Path) -> None:
    path = tmp_path / "gap.txt"
    times = [1.7e9 + i * 0.01 for i in range(100) if i != 50]
    path.write_text("".join(f"{t:.2f} 0.1\n" for t in times))
    with pytest.raises(Exception, match="line 51: time step 0.0199"):
        read_accelerogram(path, units="m/s2")


def test_trace_named_by_a_non_ascii_digit() -> None:
    from pounding_cli.errors import RecordReadError

    with pytest.raises(RecordReadError, match="no trace matches '²'"):
        read_accelerogram(INPUTS / "records" / "ridgecrest2019_ccc.mseed", trace="²")
