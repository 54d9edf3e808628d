"""What a worker process does for one case: check it, or run it and write its file.

These functions run in the sweep's worker processes (local or on Dask workers) and take
and return plain picklable values. They import pound's numeric modules only when called,
so that a worker's thread settings take effect before numpy and numba load.
"""

from __future__ import annotations

import json
import os
import socket
from pathlib import Path
from typing import Any


def check_case(document: dict[str, Any], source: str, columns: dict[str, list[str]]) -> dict[str, Any]:
    """Validate and prepare a case as `pound run` would (assembly, record, time grid),
    without integrating. Returns {"input_sha256": str} or {"problem": message}, and
    {"columns_problem": message} if the summary names a building or column it lacks; "warnings":
    its plausibility warnings, one `file: field: message` line each."""
    from ..api import input_sha256, prepare
    from ..errors import InputError
    from ..model import validate_model

    try:
        scene = prepare(validate_model(document, source))
    except InputError as exc:
        return {"problem": str(exc)}
    out: dict[str, Any] = {"input_sha256": input_sha256(scene.loaded, scene.ground),
                           "warnings": [str(n) for n in scene.notices]}  # fmt: skip
    lines = {b.name: [c.name for c in b.column_lines] for b in scene.system.buildings}
    for building, names in columns.items():
        if building not in lines:
            out["columns_problem"] = f"the model has no building {building!r}; buildings: {', '.join(lines)}"
        elif missing := [n for n in names if n not in lines[building]]:
            out["columns_problem"] = (f"building {building!r} has no column line {missing[0]!r}; its columns: "
                                      f"{', '.join(lines[building])}")  # fmt: skip
    return out


def run_case(document: dict[str, Any], source: str, expected_sha256: str, output: str, failure: str) -> dict[str, Any]:
    """Run one case and write its HDF5 file at `output` (atomically, as `pound run` does).

    A run that fails (diverges) writes its partial results, marked by their status. A case
    that cannot run at all leaves a failure note at `failure` (JSON: status, input_sha256,
    host) instead; a successful rerun removes the note. Returns {"status": …}, and
    {"write_error": message} when the file could not be written (a full disk): the sweep
    then stops with that message, exit 2."""
    import time

    from ..errors import WriteError

    t0 = time.perf_counter()
    try:
        status = _run(document, source, expected_sha256, Path(output))
    except WriteError as exc:  # the disk is full (no note could be written either): the sweep stops
        return {"status": f"failed: {exc}", "write_error": str(exc), "elapsed_s": time.perf_counter() - t0}
    except Exception as exc:  # noqa: BLE001 - one case's failure must not stop the sweep
        status = f"failed: {_message(exc)}"
        write_failure(Path(failure), expected_sha256, status)
    else:
        Path(failure).unlink(missing_ok=True)
    return {"status": status, "elapsed_s": time.perf_counter() - t0}


def _run(document: dict[str, Any], source: str, expected_sha256: str, output: Path) -> str:
    from ..api import execute, input_sha256, prepare
    from ..errors import InputError
    from ..model import validate_model
    from ..results import write_hdf5

    scene = prepare(validate_model(document, source))
    if input_sha256(scene.loaded, scene.ground) != expected_sha256:
        raise InputError(
            "the case's inputs changed after the sweep was checked (was the base model or a record "
            "file edited meanwhile?); run the sweep again",
            file=source,
        )
    result = execute(scene)
    write_hdf5(result, output)
    return result.status


def _message(exc: BaseException) -> str:
    from ..errors import PoundError

    return str(exc) if isinstance(exc, PoundError) else f"{type(exc).__name__}: {exc}"


def write_failure(path: Path, input_sha256: str, status: str) -> None:
    """Write a failure note atomically: {"status", "input_sha256", "host", "pid"}."""
    from ..atomic import write_text

    note = {"status": status, "input_sha256": input_sha256, "host": socket.gethostname(), "pid": os.getpid()}
    write_text(path, json.dumps(note, indent=1) + "\n")
