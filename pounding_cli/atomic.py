"""Writing a file so that its final name never holds an incomplete file: pound's one writer.

    with atomic_path("out.h5") as tmp:      # tmp = ".out.h5.<pid>.tmp", beside out.h5
        write_everything_to(tmp)
    # out.h5 is now complete; had the block raised, neither out.h5 nor tmp would exist

The block writes the temporary file beside the final name (same folder, so the same file
system and an atomic rename); on success the file's data is flushed to the disk (fsync) and
:func:`os.replace` gives it the final name in one step, replacing an older file only then;
on any exception, Ctrl-C and SIGTERM included, the temporary file is removed and the final
name is left as it was. A process killed outright (SIGKILL, a power cut) can leave only a
temporary file, never a half-written final one; :func:`stale_temporaries` finds those of
processes that no longer run.

An OSError while writing (disk full, no permission, a folder that vanished) becomes an
:class:`~pounding_cli.errors.InputError` naming the final path and the operating system's
reason, so the command line reports it in one line and exits 2.
"""

from __future__ import annotations

import os
import re
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from .errors import InputError

TEMPORARY = re.compile(r"^\.(?P<name>.+)\.(?P<pid>[0-9]+)\.tmp$")
"""The name of a temporary file: ``.<final name>.<pid of the writing process>.tmp``."""


def temporary_name(path: Path) -> Path:
    """Where the file for `path` is written before it is renamed (same folder)."""
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside `path` to write to; rename it to `path` when the block
    ends normally, remove it when the block raises (module docstring)."""
    path = Path(path)
    tmp = temporary_name(path)
    try:
        yield tmp
        _fsync(tmp)
        os.replace(tmp, path)
        _fsync(path.parent)
    except OSError as exc:
        raise InputError(f"cannot write the file ({reason(exc)})", file=path) from None
    finally:
        _remove(tmp)


def write_text(path: str | Path, text: str) -> Path:
    """Write `text` (UTF-8) to `path` atomically; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def reason(exc: OSError) -> str:
    """The operating system's reason for an OSError, e.g. "No space left on device" (h5py's
    errors hold a long text naming the temporary file, with the reason inside it)."""
    if exc.errno:
        return os.strerror(exc.errno)
    found = re.search(r"error message = '([^']+)'", str(exc))
    return found[1] if found else str(exc) or type(exc).__name__


def _remove(tmp: Path) -> None:
    """Remove a temporary file if it is there (it is not once renamed, or never created)."""
    try:
        tmp.unlink()
    except OSError:
        pass


def _fsync(path: Path) -> None:
    """Flush a file's (or a folder's: the rename) data to the disk, where the system allows."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        if path.is_dir():
            return  # a folder that cannot be opened for reading: nothing to flush
        raise
    try:
        os.fsync(fd)
    except OSError:
        if not path.is_dir():  # some file systems cannot fsync a folder
            raise
    finally:
        os.close(fd)


def stale_temporaries(folder: Path) -> list[Path]:
    """Temporary files in `folder` whose writing process no longer runs on this machine (a
    process killed while writing)."""
    out = []
    for path in folder.glob(".*.tmp"):
        match = TEMPORARY.match(path.name)
        if match and not alive(int(match["pid"])):
            out.append(path)
    return out


def alive(pid: int) -> bool:
    """Whether a process of this id runs on this machine."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
