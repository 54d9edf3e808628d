"""Reading result files for a report: a run's results, its resolved model, and a label.

Every problem (no such file, not HDF5, not written by pound) becomes an
:class:`~pounding_cli.errors.InputError` naming the file, so the CLI exits 2 without a
traceback.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..results import RunResult


@dataclass
class Run:
    """One run to report on: its results as read, the resolved model and a label for legends."""

    path: Path
    result: RunResult
    model: dict[str, Any]  # the resolved model (the file's root attribute `model`, parsed)
    label: str  # the file's stem unless given

    @property
    def title(self) -> str:
        """The model's title, or the file name."""
        return self.model.get("title") or self.path.name


def open_run(path: str | Path, label: str | None = None) -> Run:
    """Read a pound result file; InputError naming the file if it is not one."""
    from ..results import read_hdf5

    path = Path(path)
    if not path.exists():
        raise InputError("no such file", file=path)
    if path.is_dir():
        raise InputError("is a folder; give a result file (.h5) written by `pound run`", file=path)
    try:
        result = read_hdf5(path)
    except OSError as exc:
        raise InputError(f"cannot read it as HDF5 ({exc}); give a result file written by `pound run`", file=path) from None
    except KeyError as exc:
        raise InputError(
            f"not a pound result file: {exc.args[0] if exc.args else exc} is missing "
            "(see the HDF5 layout in docs/user-guide.md)", file=path,
        ) from None  # fmt: skip
    try:
        model = json.loads(result.model_json)
    except json.JSONDecodeError:
        raise InputError("its root attribute `model` is not JSON; was it written by `pound run`?", file=path) from None
    return Run(path=path, result=result, model=model, label=label or path.stem)


def open_runs(paths: list[str | Path]) -> list[Run]:
    """Several runs, labelled by file stem (by the parent folder too when stems repeat)."""
    runs = [open_run(p) for p in paths]
    stems = [r.label for r in runs]
    if len(set(stems)) < len(stems):
        for r in runs:
            r.label = f"{r.path.parent.name}/{r.path.stem}"
    return runs
