"""Fuzzing model files: mutate the shipped example and run what `pound validate` and `pound
run` run. Every rejection must be an InputError (exit 2) naming the file; every acceptance
must describe and then run to "complete" or to "failed: <reason>" — never an uncaught
exception. POUND_FUZZ_EXAMPLES sets the number of cases (default 1000, fixed seed).

A failing example found here is kept as a regression file in tests/fuzz_regressions/.
"""

from __future__ import annotations

import copy
import json
import math
import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pounding_cli as pound
from pounding_cli.errors import InputError
from pounding_cli.model import read_document

from conftest import INPUTS

EXAMPLES = int(os.environ.get("POUND_FUZZ_EXAMPLES", "1000"))
BASE = read_document(INPUTS / "paper_pounding.toml")
BASE["analysis"]["duration"] = 1.0  # keep accepted runs short
REGRESSIONS = Path(__file__).parent / "fuzz_regressions"

ODD_VALUES = [
    None, True, False, 0, -1, 1e300, -1e300, math.nan, math.inf, -math.inf, "", "3 m", "auto", [],
    [1, 2], [[0, 0]], {}, {"a": 1}, "é\u0000", 10**30, 1e-300, [[0, 0], [1, 1], [2, 2]],
    [[0, 0], [8, 8], [8, 0], [0, 8]], [[0, 0], [0, 8], [8, 8], [8, 0]], [[0, 0], [0, 0], [8, 0], [8, 8]],
    [[0.0, 0.0]] * 5000,
]  # fmt: skip


def _paths(node: Any, prefix=()):
    """Every path into the document (dict keys and list indices)."""
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


def _get(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def _mutate(doc: dict, kind: str, pick: int, value: Any, name: str) -> dict:
    value = copy.deepcopy(value)  # never share (or grow) the pool's objects
    paths = [p for p in _paths(doc) if p]
    path = paths[pick % len(paths)]
    parent = _get(doc, path[:-1])
    key = path[-1]
    if kind == "delete":
        del parent[key]
    elif kind == "set":
        parent[key] = value
    elif kind == "rename" and isinstance(parent, dict):
        parent[name] = parent.pop(key)
    elif kind == "duplicate" and isinstance(parent, list):
        parent.append(copy.deepcopy(parent[key]))
    elif kind == "scale" and isinstance(parent[key], (int, float)) and not isinstance(parent[key], bool):
        parent[key] = parent[key] * value if isinstance(value, (int, float)) and not isinstance(value, bool) else -parent[key]
    elif kind == "nest":
        parent[key] = [[[[[[value]]]]]]
    return doc


mutation = st.tuples(
    st.sampled_from(["delete", "set", "rename", "duplicate", "scale", "nest"]),
    st.integers(min_value=0, max_value=10_000),
    st.sampled_from(ODD_VALUES),
    st.sampled_from(["nam", "heigth", "slabs", "columns", "dt ", "L", "units", "x"]),
)


def _write(doc: dict, tmp: Path, fmt: str, garble: str | None) -> Path:
    if fmt == "json":
        text = json.dumps(doc)
    else:
        import tomli_w  # noqa: F401  (only if installed)

        text = tomli_w.dumps(doc)
    data = text.encode()
    if garble == "truncate":
        data = data[: len(data) // 2]
    elif garble == "binary":
        data = bytes(range(256)) * 4
    elif garble == "latin1":
        data = text.replace('"', '"é', 1).encode("latin-1", errors="replace")
    path = tmp / f"fuzz.{fmt}"
    path.write_bytes(data)
    (tmp / "records").mkdir(exist_ok=True)
    for f in (INPUTS / "records").glob("*"):
        target = tmp / "records" / f.name
        if not target.exists():
            target.symlink_to(f)
    return path


def _check(path: Path) -> str:
    """What the CLI would do: validate, describe, run. Returns the outcome."""
    try:
        loaded = pound.load_model(path)
        pound.describe(loaded)
    except InputError as exc:
        text = str(exc)
        assert str(path) in text, f"the message does not name the file: {text}"
        return "rejected"
    result = pound.run_model(loaded)
    assert result.status == "complete" or result.status.startswith("failed: "), result.status
    return result.status.split(":")[0]


def _keep(doc: dict, garble: str | None) -> None:
    REGRESSIONS.mkdir(exist_ok=True)
    n = len(list(REGRESSIONS.glob("case_*.json")))
    (REGRESSIONS / f"case_{n:03d}.json").write_text(json.dumps({"model": doc, "garble": garble}, default=str))


@pytest.mark.slow
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])  # fmt: skip
@given(mutations=st.lists(mutation, min_size=1, max_size=3),
       garble=st.sampled_from([None] * 12 + ["truncate", "binary", "latin1"]))  # fmt: skip
def test_fuzzed_model_files(tmp_path_factory, mutations, garble):
    doc = copy.deepcopy(BASE)
    for kind, pick, value, name in mutations:
        doc = _mutate(doc, kind, pick, value, name)
    tmp = tmp_path_factory.mktemp("fuzz")
    path = _write(doc, tmp, "json", garble)
    try:
        _check(path)
    except Exception:
        _keep(doc, garble)
        raise


@pytest.mark.parametrize("case", sorted(REGRESSIONS.glob("case_*.json")) if REGRESSIONS.exists() else [],
                         ids=lambda p: p.name)  # fmt: skip
def test_fuzz_regressions(case, tmp_path):
    saved = json.loads(case.read_text())
    _check(_write(saved["model"], tmp_path, "json", saved["garble"]))
