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

Signals are deferred while the block runs (interrupts.deferred): SIGTERM or Ctrl-C is acted
on at the writer's checkpoints and once more just before the rename (the write is abandoned,
nothing written), or, arriving after that, once the file has its final name.

An error while writing — an OSError (disk full, no permission, a folder that vanished), or
any error of the library writing the file, which may wrap ENOSPC in its own exception or
fail on the next call after a failed write — becomes an
:class:`~pounding_cli.errors.InputError` naming the final path and the operating system's
reason, so the command line reports it in one line and exits 2; the temporary file is
removed either way.
"""

from __future__ import annotations

import io
import os
import re
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Iterator

from .errors import InputError, WriteError
from .interrupts import checkpoint, deferred

TEMPORARY = re.compile(r"^\.(?P<name>.+)\.(?P<pid>[0-9]+)\.tmp$")
"""The name of a temporary file: ``.<final name>.<pid of the writing process>.tmp``."""


class Abandon(Exception):
    """Raised in the block of atomic_path or atomic_stream to drop what it wrote: the temporary
    file is removed, the final name left as it was, and the exception passes on unchanged
    (never taken for a failure to write)."""


def temporary_name(path: Path) -> Path:
    """Where the file for `path` is written before it is renamed (same folder)."""
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


@contextmanager
def atomic_path(path: str | Path, committed: Callable[[], None] | None = None) -> Iterator[Path]:
    """Yield a temporary path beside `path` to write to; rename it to `path` when the block
    ends normally, remove it when the block raises (module docstring). `committed` is
    called right after the rename (a run marks its results written)."""
    path = Path(path)
    tmp = temporary_name(path)
    with deferred(), _written_or_removed(tmp, path):
        yield tmp
        _rename(tmp, path, committed)


@contextmanager
def atomic_stream(path: str | Path, committed: Callable[[], None] | None = None) -> Iterator[Path]:
    """atomic_path for a file written in parts over a long time (a run in independent groups
    writes each group's buildings as the group ends, city/grouped.py): signals are deferred
    only where the writer defers them (interrupts.deferred around each part) and at the
    rename, so that Ctrl-C or SIGTERM stops the run at once between the parts."""
    path = Path(path)
    tmp = temporary_name(path)
    with _written_or_removed(tmp, path):
        yield tmp
        with deferred():
            _rename(tmp, path, committed)


def _rename(tmp: Path, path: Path, committed: Callable[[], None] | None) -> None:
    """Flush the complete temporary file and give it its final name (then `committed()`)."""
    _fsync(tmp)
    checkpoint()  # the last moment a signal abandons the write
    os.replace(tmp, path)
    if committed is not None:
        committed()
    _fsync(path.parent)


@contextmanager
def _written_or_removed(tmp: Path, path: Path) -> Iterator[None]:
    """Within the block `tmp` is written for `path`: a failure to write is a WriteError naming
    `path`, and `tmp` is removed at the end unless it was renamed."""
    try:
        yield
    except OSError as exc:
        raise WriteError(f"cannot write the file ({reason(exc)})", file=path) from None
    except (InputError, KeyboardInterrupt, Abandon):
        raise
    except Exception as exc:  # the writing library's own error (wrapping ENOSPC in its own)
        if not _failed_writing(exc, tmp):
            raise
        raise WriteError(f"cannot write the file ({reason(exc)})", file=path) from None
    finally:
        _remove(tmp)


def _failed_writing(exc: Exception, tmp: Path) -> bool:
    """Whether an exception raised while writing `tmp` is the file system's doing: the disk
    full (or short) now, whatever the library made of it."""
    if isinstance(exc.__cause__ or exc.__context__, OSError):
        return True
    try:
        usage = os.statvfs(tmp.parent)
    except OSError:
        return False
    return usage.f_bavail * usage.f_frsize < 1 << 20 or "errno = 28" in str(exc) or "No space" in str(exc)


@contextmanager
def hdf5_writer(tmp: Path, **options: Any) -> Iterator[Any]:
    """An h5py.File, mode "w", writing `tmp` through a DiskSink: HDF5 never meets a failed
    write (after one, as when the disk fills up, the C library segfaults on closing the file
    and prints a traceback per object it frees), and the OSError the sink met is raised once
    the file is closed, for atomic_path to report and clean up."""
    import h5py

    fd = os.open(tmp, os.O_RDWR | os.O_CREAT | os.O_TRUNC | getattr(os, "O_CLOEXEC", 0), 0o644)
    sink = DiskSink(fd)
    try:
        with deferred():  # HDF5 writes through the sink's Python code as it opens and closes the file
            f = h5py.File(sink, "w", **options)
        try:
            yield f
        finally:
            with deferred():
                f.close()
    finally:
        os.close(fd)
    sink.check()


_SLOW_WRITES = float(os.environ.get("POUND_TEST_SLOW_WRITES", "0") or 0)
"""For tests/test_write_faults.py only: seconds each write waits, so that the writing of a
result file spans long enough to be signalled throughout. Unset: 0."""


class DiskSink(io.RawIOBase):
    """A file object over a descriptor that never fails a write: the first OSError (ENOSPC,
    EDQUOT, EIO) is kept, and what could not be written is held in memory so that reads stay
    consistent, until :meth:`check` raises the error (module docstring of hdf5_writer)."""

    def __init__(self, fd: int):
        super().__init__()
        self.fd, self.pos, self.end = fd, 0, 0
        self.error: OSError | None = None
        self.held: dict[int, bytes] = {}  # offset -> bytes not written (after self.error)

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self.pos

    def seek(self, offset: int, whence: int = 0) -> int:
        base = {0: 0, 1: self.pos, 2: self.end}[whence]
        self.pos = base + offset
        return self.pos

    def write(self, data: Any) -> int:
        if _SLOW_WRITES:
            time.sleep(_SLOW_WRITES)
        data = bytes(data)
        if self.error is None:
            try:
                written = 0
                while written < len(data):
                    written += os.pwrite(self.fd, data[written:], self.pos + written)
            except OSError as exc:
                self.error = exc
                self.held[self.pos + written] = data[written:]
        else:
            self.held[self.pos] = data
        self.pos += len(data)
        self.end = max(self.end, self.pos)
        return len(data)

    def readinto(self, buffer: Any) -> int:
        view = memoryview(buffer).cast("B")
        n = min(len(view), max(0, self.end - self.pos))
        got = os.preadv(self.fd, [view[:n]], self.pos) if n else 0
        view[got:n] = bytes(n - got)
        for offset, data in self.held.items():  # what the disk did not take
            lo, hi = max(offset, self.pos), min(offset + len(data), self.pos + n)
            if lo < hi:
                view[lo - self.pos : hi - self.pos] = data[lo - offset : hi - offset]
        self.pos += n
        return n

    def truncate(self, size: int | None = None) -> int:
        size = self.pos if size is None else size
        if self.error is None:
            try:
                os.ftruncate(self.fd, size)
            except OSError as exc:
                self.error = exc
        self.end = size
        return size

    def flush(self) -> None:
        pass

    def check(self) -> None:
        """Raise the OSError a write met, if any."""
        if self.error is not None:
            raise self.error


def write_text(path: str | Path, text: str) -> Path:
    """Write `text` (UTF-8) to `path` atomically; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def reason(exc: BaseException) -> str:
    """The operating system's reason for an error while writing, e.g. "No space left on
    device" (h5py's errors hold a long text naming the temporary file, with the reason inside
    it, or none: then the errno of the OSError behind it)."""
    if isinstance(exc, OSError) and exc.errno:
        return os.strerror(exc.errno)
    if "errno = 28" in str(exc) or "No space left" in str(exc):
        return os.strerror(28)
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
