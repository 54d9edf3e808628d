"""What a worker does for one case of `pound gap --suite`: run `pound gap` on the case's
model and write its file, or read the file a previous run left.

A case file is exactly the file `pound gap -o` writes for the case's model (gap/hdf5.py),
plus the root attribute ``case_sha256``: the input_sha256 of the case's model as given (its
resolved model, record file bytes and pound's version). A file whose ``case_sha256`` and
status match is complete and is read instead of run again (resuming). Runs in the sweep's
worker processes: plain picklable arguments and results, imports inside.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any


def gap_case(document: dict[str, Any], source: str, output: str, failure: str) -> dict[str, Any]:
    """{"status", "pairs" (rows of /gap/pairs), "reused", "elapsed_s"} of one case."""
    from ..sweep.tasks import _message, write_failure

    t0 = time.perf_counter()
    sha = ""
    try:
        pairs, reused, sha = _gap(document, source, Path(output))
    except Exception as exc:  # noqa: BLE001 - one case's failure must not stop the suite
        status = f"failed: {_message(exc)}"
        write_failure(Path(failure), sha, status)
        return {"status": status, "pairs": [], "reused": False, "elapsed_s": time.perf_counter() - t0}
    Path(failure).unlink(missing_ok=True)
    return {"status": "complete", "pairs": pairs, "reused": reused, "elapsed_s": time.perf_counter() - t0}


def _gap(document: dict[str, Any], source: str, output: Path) -> tuple[list[dict[str, Any]], bool, str]:
    from ..api import input_sha256, prepare
    from ..gap.hdf5 import write_gap
    from ..gap.required import required_gaps
    from ..model import validate_model

    scene = prepare(validate_model(document, source))
    sha = input_sha256(scene.loaded, scene.ground)
    found = read_case(output, sha)
    if found is not None:
        return found, True, sha
    write_gap(required_gaps(scene), output, {"case_sha256": sha})
    found = read_case(output, sha)
    assert found is not None
    return found, False, sha


def warm_up() -> None:
    """Import pound's analysis and gap modules and the solver's compiled kernels."""
    from ..api import execute  # noqa: F401
    from ..gap.required import required_gaps  # noqa: F401
    from ..solver import integrate  # noqa: F401


def read_case(path: Path, sha: str) -> list[dict[str, Any]] | None:
    """The pairs of a complete case file of inputs `sha`, None if there is none."""
    import h5py

    from ..gap.hdf5 import read_pairs

    if not path.is_file():
        return None
    try:
        with h5py.File(path, "r") as f:
            if str(f.attrs.get("case_sha256", "")) != sha or str(f.attrs.get("status", "")) != "complete":
                return None
            return read_pairs(f)
    except (OSError, KeyError):
        return None
