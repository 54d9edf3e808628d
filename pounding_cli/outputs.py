"""Where a command writes, decided so that nothing a user owns is destroyed.

- :func:`output_file` — the file an `-o` names: a name ending in "/" (or an existing folder)
  is a folder, written into with the default name, and said so.
- :func:`refuse_inputs` — an output that is one of the run's inputs (the model, its record
  definition, its record files; the same file however reached: links, hard links) is
  refused, whatever --force says.
- :func:`claim` — the output name is claimed for the whole run: a second `pound run` (or a
  sweep) writing the same name while the first runs is refused at its start, naming the
  first, instead of both writing it and the later one silently replacing the earlier's.

A claim is an exclusive lock (flock) on a small file beside the output,
``.<name>.claim``, holding who claimed it. The lock goes with its process however that ends
(kill -9 included), so a claim is never stale; the file is removed when the claim ends, or
when the process ends by a signal after its results were written (interrupts.die_by); only
kill -9 leaves it, and the next claimant takes it over.
"""

from __future__ import annotations

import os
import socket
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from .errors import InputError
from .interrupts import at_death, forget_at_death


def output_file(output: str | Path, default_name: str) -> tuple[Path, str | None]:
    """(the file to write, a note for the user or None). `output` ending in a path separator,
    or naming an existing folder, names a folder: the file is `default_name` inside it
    (`pathlib` would drop the trailing "/" and write a file named like the folder)."""
    text = os.fspath(output)
    seps = (os.sep, os.altsep) if os.altsep else (os.sep,)
    if text.endswith(seps) or Path(text).is_dir():
        path = Path(text) / default_name
        return path, f"{text} names a folder: the results are in {path}"
    return Path(text), None


def same_file(a: Path, b: Path) -> bool:
    """Whether two paths are one file (links followed; hard links are one file too)."""
    try:
        sa, sb = os.stat(a), os.stat(b)
    except OSError:
        return False
    return (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino)


def refuse_inputs(output: Path, inputs: list[tuple[Path, str]], instead: str = "another output file (-o)") -> None:
    """InputError if `output` is one of `inputs` ((path, what it is)): writing the results
    would replace it (--force or not)."""
    for path, what in inputs:
        if same_file(output, path):
            raise InputError(
                f"is {what} ({path}); writing there would destroy it: give {instead}",
                file=output,
            )


def claim_file(path: Path) -> Path:
    """The file whose lock claims `path`: ``.<name>.claim`` beside it."""
    return path.with_name(f".{path.name}.claim")


@contextmanager
def claim(path: Path, what: str = "pound run") -> Iterator[None]:
    """Hold the claim on the output `path` for the block; InputError naming the holder if
    another process holds it. The claim file is removed when the block ends."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no claims
        yield
        return
    lock = claim_file(path)
    for _ in range(100):  # retried only while another claim is being released under us
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        except OSError as exc:
            raise InputError(f"cannot claim the output name: cannot create {lock.name} ({exc.strerror})", file=path) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = _holder(fd)
            os.close(fd)
            raise InputError(
                f"is being written by another {holder}; wait for it to finish or choose another output name",
                file=path,
            ) from None
        if _still_there(fd, lock):
            break
        os.close(fd)  # the holder removed the file as we opened it: claim the new one
    else:  # pragma: no cover - a hundred races in a row
        raise InputError("cannot claim the output name: its claim file keeps changing", file=path)
    def release() -> None:
        if _still_there(fd, lock):
            lock.unlink()

    at_death(release)  # a death by the signal after the rename (interrupts.die_by) removes it too
    try:
        command = " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]) if sys.argv else "python"
        try:  # who holds it, for the message of the next claimant (a full disk may refuse it)
            os.ftruncate(fd, 0)
            os.write(fd, f"{what} (pid {os.getpid()} on {socket.gethostname()}, started "
                         f"{time.strftime('%Y-%m-%d %H:%M:%S')}: {command})".encode())  # fmt: skip
        except OSError:
            pass
        yield
    finally:
        forget_at_death(release)
        try:
            release()
        except OSError:
            pass
        os.close(fd)


def _still_there(fd: int, lock: Path) -> bool:
    """Whether the locked descriptor is still the file at `lock` (not one removed meanwhile)."""
    try:
        here, held = os.stat(lock), os.fstat(fd)
    except OSError:
        return False
    return (here.st_dev, here.st_ino) == (held.st_dev, held.st_ino)


def _holder(fd: int) -> str:
    """Who holds a claim, as its file says (a moment after it was taken, it may say nothing)."""
    for _ in range(20):
        try:
            text = os.pread(fd, 4096, 0).decode("utf-8", errors="replace").strip()
        except OSError:
            text = ""
        if text:
            return text
        time.sleep(0.01)
    return "pound process (it has not said which yet)"
