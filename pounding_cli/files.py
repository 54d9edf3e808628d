"""Reading an input file without trusting what its path names: pound's one reader of bytes.

    raw = read_regular(path, limit=50_000_000)   # bytes, or FileRefused saying why not

A path may name something that is not a file at all: a FIFO (reading blocks until someone
writes), a device (/dev/zero never ends), a socket, a folder, a symbolic link to any of them
or to itself. So the path is opened without blocking (O_NONBLOCK: a FIFO opens at once, with
no writer), the opened object is asked what it is (fstat, which follows the links the open
followed, so a link cannot change its target between the check and the read), anything but a
regular file is refused, and at most `limit` + 1 bytes are read, so that a file that grows
while it is read (or a size the file system does not report) is refused too.

:class:`FileRefused` carries the reason in words ("is a FIFO (named pipe), not a regular
file"); the callers turn it into their own error, naming the file and the field.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path


MAX_RECORD_BYTES = 2**30
"""Largest record file pound reads, bytes (1 GiB: a day of three 200 Hz channels as text is
about 0.5 GB; a strong-motion record is a few MB)."""


class FileRefused(Exception):
    """An input path that pound does not read; `reason` says why, in words."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(reason)


KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def kind_of(mode: int) -> str:
    """What a file of this st_mode is, in words (for anything but a regular file)."""
    return next((name for test, name in KINDS if test(mode)), "not a regular file")


def read_regular(path: str | Path, limit: int) -> bytes:
    """The bytes of the regular file at `path`, at most `limit` of them; FileRefused when it
    is missing, is not a regular file, cannot be read or holds more than `limit` bytes."""
    fd = _open(Path(path))
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise FileRefused(f"is {kind_of(info.st_mode)}, not a regular file; pound reads its inputs from regular files only")
        if info.st_size > limit:
            raise FileRefused(f"file is {info.st_size} bytes; an input file of this kind is limited to {limit}")
        os.set_blocking(fd, True)
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(limit + 1 - size, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise FileRefused(f"cannot read the file ({exc.strerror or exc})") from None
    finally:
        os.close(fd)
    if size > limit:
        raise FileRefused(f"file holds more than {limit} bytes (it grew while it was read); an input file of this "
                          "kind is limited to that")  # fmt: skip
    return b"".join(chunks)


def read_start(path: str | Path, size: int) -> bytes:
    """The first `size` bytes of the regular file at `path` (format detection); FileRefused
    as read_regular."""
    fd = _open(Path(path))
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise FileRefused(f"is {kind_of(info.st_mode)}, not a regular file; pound reads its inputs from regular files only")
        os.set_blocking(fd, True)
        return os.read(fd, size)
    except OSError as exc:
        raise FileRefused(f"cannot read the file ({exc.strerror or exc})") from None
    finally:
        os.close(fd)


def check_regular(path: str | Path, limit: int) -> int:
    """The size of the regular file at `path` (for readers that open it themselves, such as
    obspy's); FileRefused as read_regular, without reading it."""
    fd = _open(Path(path))
    try:
        info = os.fstat(fd)
    finally:
        os.close(fd)
    if not stat.S_ISREG(info.st_mode):
        raise FileRefused(f"is {kind_of(info.st_mode)}, not a regular file; pound reads its inputs from regular files only")
    if info.st_size > limit:
        raise FileRefused(f"file is {info.st_size} bytes; an input file of this kind is limited to {limit}")
    return info.st_size


def _open(path: Path) -> int:
    """A read-only descriptor of `path` that never blocks on opening (a FIFO without writer)."""
    if "\x00" in str(path):
        raise FileRefused("no such file: the name holds a NUL character, which no file name can")
    try:
        return os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        if path.is_symlink():
            raise FileRefused(f"no such file: the symbolic link points to {os.readlink(path)!r}, which does not exist") from None
        raise FileRefused("no such file") from None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise FileRefused("cannot read the file: its symbolic links form a loop") from None
        try:  # a socket cannot be opened (ENXIO); say what it is
            mode = os.stat(path).st_mode
        except OSError:
            mode = stat.S_IFREG
        if not stat.S_ISREG(mode):
            raise FileRefused(f"is {kind_of(mode)}, not a regular file; pound reads its inputs from regular files only") from None
        raise FileRefused(f"cannot read the file ({exc.strerror or exc})") from None


def resolve_in(folder: Path, relative: str | Path) -> Path:
    """The path `relative` names from `folder`, resolved (links followed: a record
    definition's own paths are relative to the file a link points to); a loop of links is
    left unresolved for the reader to report, rather than raised here (RuntimeError)."""
    path = Path(folder) / relative
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of links; a NUL in the name (the reader refuses it)
        return path
