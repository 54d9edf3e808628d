"""The sweep's output folder: where each case's file goes, what state a case is in, and the
lock that keeps two sweeps from writing into one folder.

    DIR/sweep.json               the expanded sweep: every case, its hash and values (manifest)
    DIR/summary.h5, summary.csv  one row per case, rebuilt from the case files
    DIR/cases/<hash>.h5          one case's results, exactly as `pound run` writes them
    DIR/cases/<hash>.failed.json a case that could not run: its message (no .h5 then)
    DIR/.lock                    held while a sweep writes here
    DIR/.pound-sweep             the marker: this folder is a sweep's (JSON: who made it, when)

A sweep writes only into a folder that is new, empty, or marked as a sweep's (check_owner):
anything else may hold the user's own files of those names, and needs --force, which the
sweep reports. A folder of an earlier release's sweep (no marker, but a sweep.json that is a
pound manifest) is taken as a sweep's, and marked.

A case file is written under a temporary name and renamed when complete, so a file named
``<hash>.h5`` is never half-written; its ``input_sha256`` attribute must equal the case's
for it to count, and its ``status`` says whether it ran to the end.
"""

from __future__ import annotations

import json
import os
import socket
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

from ..atomic import stale_temporaries, write_text
from ..errors import InputError

CASES = "cases"
MANIFEST = "sweep.json"
LOCK = ".lock"
MARKER = ".pound-sweep"
WRITES = (MANIFEST, "summary.h5", "summary.csv", CASES, LOCK, MARKER)
"""What a sweep writes at the top of its folder."""

COMPLETE, PENDING = "complete", "pending"


@dataclass(frozen=True)
class CaseState:
    """What the folder holds for one case: "complete", "failed: …" (with or without partial
    results in the case file) or "pending" (nothing yet, or a file of other inputs)."""

    status: str
    has_results: bool  # the case file holds (possibly partial) results

    @property
    def complete(self) -> bool:
        return self.status == COMPLETE


class OutputFolder:
    """Paths and states inside a sweep's output folder."""

    def __init__(self, root: str | Path):
        self.root = Path(root)

    @property
    def cases(self) -> Path:
        return self.root / CASES

    @property
    def manifest(self) -> Path:
        return self.root / MANIFEST

    def case_file(self, short_hash: str) -> Path:
        return self.cases / f"{short_hash}.h5"

    def failure_file(self, short_hash: str) -> Path:
        return self.cases / f"{short_hash}.failed.json"

    def state(self, short_hash: str, input_sha256: str) -> CaseState:
        """The case's state, from its file (or failure note), checked against its full hash."""
        import h5py

        path = self.case_file(short_hash)
        if path.exists():
            try:
                with h5py.File(path, "r") as f:
                    if str(f.attrs["input_sha256"]) == input_sha256:
                        return CaseState(str(f.attrs["status"]), True)
            except (OSError, KeyError):
                pass  # unreadable: run it again
        note = self.failure_file(short_hash)
        if note.exists():
            try:
                data = json.loads(note.read_text(encoding="utf-8"))
                if data.get("input_sha256") == input_sha256:
                    return CaseState(str(data["status"]), False)
            except (OSError, ValueError, KeyError):
                pass
        return CaseState(PENDING, False)

    def check_owner(self, force: bool = False) -> str | None:
        """Refuse a folder that holds files a sweep did not write, unless `force` (then a note
        for the user is returned); None for a new or empty folder or a sweep's."""
        if not self.root.exists():
            return None
        if not self.root.is_dir():
            raise InputError("is a file; give a folder for the sweep's results", file=self.root)
        if (self.root / MARKER).is_file() or self._earlier_sweep():
            return None
        try:
            held = sorted(p.name for p in self.root.iterdir())
        except OSError as exc:
            raise InputError(f"cannot read the output folder ({exc.strerror})", file=self.root) from None
        if not held:
            return None
        shown = ", ".join(held[:5]) + (f" and {len(held) - 5} more" if len(held) > 5 else "")
        replaced = ", ".join(n for n in WRITES if n in held) or "none of them"
        if not force:
            raise InputError(
                f"holds files that no pound sweep wrote ({shown}); a sweep writes {MANIFEST}, summary.csv, "
                f"summary.h5 and {CASES}/ into its folder, replacing files of those names: give a new or empty "
                "folder, or pass --force to write into this one",
                file=self.root,
            )
        return (f"{self.root}: writing into a folder that no pound sweep made (--force); of what it holds, "
                f"{replaced} will be replaced")  # fmt: skip

    def _earlier_sweep(self) -> bool:
        """A folder an earlier release's sweep wrote: its sweep.json is a pound manifest."""
        try:
            data = json.loads(self.manifest.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return False
        return (isinstance(data, dict) and "pound_version" in data and isinstance(data.get("cases"), list)
                and all(isinstance(c, dict) and "hash" in c and "input_sha256" in c for c in data["cases"]))  # fmt: skip

    def prepare(self) -> None:
        """Create the folder and its cases/ folder (an error naming the folder if it can't be),
        and mark it as a sweep's."""
        try:
            self.cases.mkdir(parents=True, exist_ok=True)
        except FileExistsError:
            raise InputError("is a file; give a folder for the sweep's results", file=self.root) from None
        except OSError as exc:
            raise InputError(f"cannot create the output folder ({exc.strerror})", file=self.root) from None
        marker = self.root / MARKER
        if not marker.is_file():
            from .. import __version__

            write_text(marker, json.dumps({"pound_version": __version__, "host": socket.gethostname(),
                                           "pid": os.getpid()}) + "\n")  # fmt: skip

    @contextmanager
    def locked(self) -> Iterator[None]:
        """Hold the folder's lock; InputError if another sweep holds it. The lock goes with
        the process, however it ends (kill -9 included)."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no lock
            yield
            return
        path = self.root / LOCK
        handle = open(path, "a+", encoding="utf-8")
        try:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                handle.seek(0)
                holder = handle.read().strip() or "another process"
                raise InputError(f"another pound sweep is writing into this folder ({holder}); wait for it "
                                 "to finish or give another folder", file=self.root) from None  # fmt: skip
            handle.seek(0)
            handle.truncate()
            handle.write(f"pid {os.getpid()} on {socket.gethostname()}\n")
            handle.flush()
            yield
        finally:
            handle.close()

    def remove_stale_temporaries(self) -> list[Path]:
        """Delete temporary files (``.<hash>.h5.<pid>.tmp``) whose writing process no longer
        runs on this machine (a killed sweep); returns them."""
        removed = stale_temporaries(self.cases)
        for path in removed:
            path.unlink(missing_ok=True)
        return removed

    def write_manifest(self, document: dict[str, Any]) -> None:
        """Write sweep.json atomically."""
        write_text(self.manifest, json.dumps(document, indent=1, ensure_ascii=False) + "\n")

    def read_manifest(self) -> dict[str, Any]:
        """The manifest of the sweep last run into this folder."""
        try:
            return json.loads(self.manifest.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise InputError(f"no {MANIFEST}: not the output folder of a pound sweep", file=self.root) from None
        except ValueError as exc:
            raise InputError(f"{MANIFEST} is not valid JSON ({exc})", file=self.root) from None
