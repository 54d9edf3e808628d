"""Fuzzing model and sweep files through the command line.

Seeds: every model file shipped in inputs/ (the paper's buildings with and without pounding,
with inelastic columns, under Kobe; the isolated building with its moat wall), one with a
fixed obstacle (a wall beside the wide-gap example, as no shipped model has one), and the
shipped sweep files. Each case mutates a seed's document — keys deleted, duplicated, renamed,
retyped (NaN, ±inf, huge, negative, zero, empty, degenerate, self-intersecting and clockwise
polygons, repeated vertices, enormous arrays), values scaled, nested deeply, and units swapped
(mm for m, kN for N, t for kg, percent for ratios, radians for degrees and back, ms for s,
g for m/s²) — writes it as JSON or TOML (tomli_w), sometimes garbled (truncated, binary,
Latin-1, UTF-16, a BOM), and runs the entry point in-process (typer's CliRunner) with
POUND_DEBUG=1, so that a bug surfaces as its exception, not as the "internal error" paragraph:

- a model: ``pound run FILE -o out.h5 --json``; a sweep: ``pound sweep FILE --dry-run --json``
  (every case checked as a run checks it; the sweep's workers are this process).

Issue 27 added generators for the classes a hostile tester found beyond these:

- extreme magnitudes in every numeric field (``extreme``: subnormals, 1e±308, integers of
  19, 309, 401 and 5,000 digits — the last written into the text as digits);
- lax-type substitutions in every scalar field (``lax``: "no", 0, 1.0 for a boolean; "3",
  true for a number; true for a string); a model whose only mutation makes a boolean not a
  boolean, a number a string or a boolean, or a string a boolean must be refused naming that
  field (the oracle: before, `enabled = "no"` ran with pounding off, exit 0);
- file-system oddities (garbles ``fifo``, ``devzero``, ``loop``, ``folder`` for the file on the
  command line; ``record_fifo``, ``record_devzero`` for the record file the model names): exit 2
  naming the file (and the record's field), never a hang — each case runs under a deadline;
- output paths (``output``, runs only): the model itself, a link to it, a link to its record
  file (all with --force: refused, the file untouched), a folder given with a trailing slash or
  existing (written into), and a name another writer holds (claimed in this process: refused
  naming it).

Required: no uncaught exception; exit 0 with a complete file, exit 1 with a partial file whose
status says ``failed: <reason>`` (stderr says it too), or exit 2 with a message naming the file
and a field (``path.to.field: …``) or a line (``line N``). The resource limits are lowered
(POUND_MAX_STEPS etc. below) so that accepted runs stay short: a run beyond them is refused,
which fuzzes those messages too.

POUND_FUZZ_EXAMPLES sets the number of cases (default 1000, a fixed seed: hypothesis is pinned
in the test extras). POUND_FUZZ_KEEP=1 keeps each failing case (the document, its format and
garbling) as tests/fuzz_regressions/case_NNN.json, replayed by test_fuzz_regressions.
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import re
import shutil
from pathlib import Path
from typing import Any

import h5py
import pytest
import tomli_w
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from pounding_cli.cli import app
from pounding_cli.model import read_document
from pounding_cli.model.load import format_loc
from pounding_cli.outputs import claim

from conftest import INPUTS

EXAMPLES = int(os.environ.get("POUND_FUZZ_EXAMPLES", "1000"))
REGRESSIONS = Path(__file__).parent / "fuzz_regressions"
DURATION = 0.3  # s: accepted runs stay short
LIMITS = {"POUND_MAX_STEPS": "3e5", "POUND_MAX_OUTPUT_GB": "0.05", "POUND_MAX_MEMORY_GB": "0.1",
          "POUND_MAX_STOREYS": "40"}  # fmt: skip
"""Resource limits while fuzzing: a mutated model runs in well under a second, or is refused."""
runner = CliRunner()


def _model_seed(name: str) -> dict[str, Any]:
    doc = read_document(INPUTS / f"{name}.toml")
    doc.setdefault("analysis", {})["duration"] = DURATION
    return doc


def _obstacle_seed() -> dict[str, Any]:
    """The wide-gap example with a wall 2 mm beside the right building, over all its floors."""
    doc = _model_seed("paper_wide_gap")
    doc["obstacles"] = [{"name": "wall", "polygon": [[8.5, -1.0], [24.5, -1.0], [24.5, -0.002], [8.5, -0.002]],
                         "elevation": [0.0, 10.0], "material": "concrete"}]  # fmt: skip
    return doc


def _sweep_seed(name: str) -> dict[str, Any]:
    doc = read_document(INPUTS / f"{name}.sweep.toml")
    doc.setdefault("set", {})["analysis.duration"] = DURATION
    if name == "paper_studies":  # 73 angles of Kobe would make one case take seconds: 4 of them
        doc["studies"]["6.3"]["parameters"]["excitation.angle"]["step"] = 120
    return doc


SEEDS: dict[str, tuple[str, dict[str, Any]]] = {
    **{name: ("model", _model_seed(name)) for name in
       ("paper_pounding", "paper_wide_gap", "paper_inelastic", "paper_kobe", "isolated_moat")},
    "obstacle_wall": ("model", _obstacle_seed()),
    **{f"{name}.sweep": ("sweep", _sweep_seed(name)) for name in ("pounding_angle_gap", "isolated_moat", "paper_studies")},
}  # fmt: skip
SHARED_FILES = ["records", "kobe_jma.record.toml", "paper_pounding.toml", "paper_kobe.toml", "isolated_moat.toml"]
"""What the seeds name, linked into each case's folder: the records and the sweeps' base models."""

ODD_VALUES = [
    None, True, False, 0, -1, 1e300, -1e300, math.nan, math.inf, -math.inf, "", "3 m", "auto", [],
    [1, 2], [[0, 0]], {}, {"a": 1}, "é\u0000", 10**30, 1e-300, [[0, 0], [1, 1], [2, 2]],
    [[0, 0], [8, 8], [8, 0], [0, 8]], [[0, 0], [0, 8], [8, 8], [8, 0]], [[0, 0], [0, 0], [8, 0], [8, 8]],
    [[0.0, 0.0] for _ in range(5000)], 10**6, 0.5, "../nowhere.toml", "left",
]  # fmt: skip
"""Values a mutation sets. No list holds one object twice: a later mutation of one element
would change them all (deepcopy keeps the sharing), growing a document without bound."""

LENGTH, FORCE, MASS, RATIO, ANGLE, TIME = (
    [("mm for m", 1e3)],
    [("kN for N", 1e-3), ("MN for N", 1e-6), ("N for kN", 1e3)],
    [("t for kg", 1e-3)],
    [("percent for a ratio", 100.0)],
    [("radians for degrees", math.pi / 180), ("degrees for radians", 180 / math.pi)],
    [("ms for s", 1e3), ("s for ms", 1e-3)],
)  # fmt: skip
UNITS: dict[str, list[tuple[str, float]]] = {
    **dict.fromkeys(["height", "slab", "section", "sections", "origin", "x", "y", "eccentricity", "gap", "thickness",
                     "yield_deflection", "yield_displacement", "polygon", "elevation"], LENGTH),
    **dict.fromkeys(["elastic_modulus", "k_normal", "k_tangential", "initial_stiffness", "post_yield_stiffness",
                     "characteristic_strength", "yield_force", "damping_normal", "damping_tangential"], FORCE),
    **dict.fromkeys(["mass", "mass_per_area", "rotational_inertia"], MASS),
    **dict.fromkeys(["ratios", "poisson_ratio", "post_yield_ratio", "friction_static", "friction_kinetic",
                     "restitution"], RATIO),
    **dict.fromkeys(["angle", "rotation"], ANGLE),
    **dict.fromkeys(["duration", "dt", "output_interval"], TIME),
    "scale": [("g for m/s²", 9.80665)],
}  # fmt: skip
"""Unit swaps by key (a sweep's parameter path by its last name): what a slip of units does."""


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


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def pick_leaf(doc: dict, kind: str, pick: int) -> tuple[tuple, Any, Any] | None:
    """(path, old value, new value) of an "extreme" or "lax" mutation: a number (extreme), or
    a boolean, number or string (lax), and what replaces it; None if the document has none."""
    leaves = [p for p in _paths(doc) if p and _scalar(_get(doc, p), numbers_only=kind == "extreme")]
    if not leaves:
        return None
    path = leaves[pick % len(leaves)]
    old = _get(doc, path)
    pool = EXTREMES if kind == "extreme" else LAX[bool if isinstance(old, bool) else str if isinstance(old, str) else float]
    return path, old, pool[(pick // len(leaves)) % len(pool)]


def _scalar(v: Any, numbers_only: bool) -> bool:
    """A number (not a boolean), or, unless numbers_only, a boolean or a string."""
    return _is_number(v) or (not numbers_only and isinstance(v, (bool, str)))


def _numeric(v: Any) -> bool:
    """A number, or a (nested) non-empty list of numbers, or a sweep's {start, stop, step} range."""
    if isinstance(v, list):
        return bool(v) and all(_numeric(x) for x in v)
    if isinstance(v, dict):
        return bool(v) and all(_numeric(x) for x in v.values())
    return _is_number(v)


def _scaled(v: Any, factor: float) -> Any:
    if isinstance(v, list):
        return [_scaled(x, factor) for x in v]
    if isinstance(v, dict):
        return {k: _scaled(x, factor) for k, x in v.items()}
    return v * factor


def unit_key(key: Any) -> str | None:
    """The name a unit swap looks up: a key, or the last name of a sweep's parameter path."""
    if not isinstance(key, str):
        return None
    return re.sub(r"\[.*?\]", "", key).rsplit(".", 1)[-1]


def _mutate(doc: dict, kind: str, pick: int, value: Any, name: str) -> dict:
    value = copy.deepcopy(value)  # never share (or grow) the pool's objects
    paths = [p for p in _paths(doc) if p]
    if not paths:
        return doc
    if kind == "unit":
        swappable = [p for p in paths if unit_key(p[-1]) in UNITS and _numeric(_get(doc, p))]
        if swappable:
            path = swappable[pick % len(swappable)]
            swaps = UNITS[unit_key(path[-1])]
            _get(doc, path[:-1])[path[-1]] = _scaled(_get(doc, path), swaps[(pick // len(swappable)) % len(swaps)][1])
        return doc
    if kind in ("extreme", "lax"):
        target = pick_leaf(doc, kind, pick)
        if target is not None:
            path, _, new = target
            _get(doc, path[:-1])[path[-1]] = copy.deepcopy(new)
        return doc
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
    elif kind == "scale" and _is_number(parent[key]):
        parent[key] = parent[key] * value if _is_number(value) else -parent[key]
    elif kind == "nest":
        parent[key] = [[[[[[value]]]]]]
    return doc


HUGE_INT = "__pound_fuzz_5000_digits__"
"""A value written into the text as a whole number of 5,000 digits (json and tomli_w cannot
write one: Python refuses to convert more than 4,300 digits to text)."""

EXTREMES = [
    5e-324, -5e-324, 2.2250738585072014e-308, 1e-308, 1e-300, -0.0, 1e306, 1e308, 1.7976931348623157e308,
    -1.7976931348623157e308, 2**63, -(2**63), 10**18, 10**308, 10**400, HUGE_INT,
]  # fmt: skip
"""Magnitudes at the ends of what floats and integers hold (issue 27: 1e308 durations, 5e-324
steps and 1e18 inertias hung or overflowed)."""

LAX = {
    bool: ["no", "yes", "true", "false", "off", "0", "1", 0, 1, 0.0, 1.0],
    float: ["3", "1e3", "inf", "0.5 m", True, False],
    str: [True, False, 3, 2.5],
}
"""What pydantic's lax mode would coerce, by the type of the value it replaces."""


def must_refuse(old: Any, new: Any) -> bool:
    """Whether a strict model must refuse `new` where `old` was: a boolean that is not one, a
    number given as text or a boolean, a string given as a boolean."""
    if isinstance(old, bool):
        return not isinstance(new, bool)
    if isinstance(old, (int, float)):
        return isinstance(new, (str, bool))
    if isinstance(old, str):
        return isinstance(new, bool)
    return False


mutation = st.tuples(
    st.sampled_from(["delete", "set", "rename", "duplicate", "scale", "nest", "unit", "unit", "extreme", "extreme",
                     "lax", "lax"]),
    st.integers(min_value=0, max_value=10_000),
    st.sampled_from(ODD_VALUES),
    st.sampled_from(["nam", "heigth", "slabs", "columns", "dt ", "L", "units", "x", "Duration", "base"]),
)  # fmt: skip
FS_GARBLES = ["fifo", "devzero", "loop", "folder"]
"""The file on the command line is not a regular file."""
RECORD_GARBLES = ["record_fifo", "record_devzero"]
"""The record file the model names is not a regular file."""
GARBLES = [None] * 22 + ["truncate", "binary", "latin1", "utf16", "bom"] + FS_GARBLES + RECORD_GARBLES
OUTPUTS = ["out.h5"] * 12 + ["model", "model_link", "record_link", "folder/", "existing_folder", "claimed"]
"""Where a run writes (check_case): its own file, or a collision with an input or a writer."""


def _text(doc: dict, fmt: str) -> tuple[str, str]:
    """The document as JSON or TOML text, and the format used: TOML has no null, so a
    document holding one is written as JSON."""
    if fmt == "toml":
        try:
            return tomli_w.dumps(doc), "toml"
        except (TypeError, ValueError):
            pass
    return json.dumps(doc), "json"


def write_case(folder: Path, case: dict[str, Any]) -> Path:
    """Write the case's file into `folder`, beside links to what the seeds name; its path.
    A saved regression may hold the file's `text` itself (a JSON object with a key twice)."""
    if "text" in case:
        text, fmt = case["text"], case["format"]
    else:
        text, fmt = _text(case["document"], case["format"])
    text = text.replace(json.dumps(HUGE_INT), "7" * 5000)  # the same in JSON and TOML: "..."
    data = text.encode()
    garble = case["garble"]
    if garble == "truncate":
        data = data[: len(data) // 2]
    elif garble == "binary":
        data = bytes(range(256)) * 4
    elif garble == "latin1":
        data = text.replace('"', '"é', 1).encode("latin-1", errors="replace")
    elif garble == "utf16":
        data = text.encode("utf-16")
    elif garble == "bom":
        data = b"\xef\xbb\xbf" + data
    path = folder / (f"fuzz.sweep.{fmt}" if case["kind"] == "sweep" else f"fuzz.{fmt}")
    if garble in FS_GARBLES:
        oddity(path, garble)
    else:
        path.write_bytes(data)
    if garble in RECORD_GARBLES or case.get("output") == "record_link":
        (folder / "records").mkdir()  # the records the seeds name: a copy, or an oddity
        for name in ("ridgecrest2019_ccc.mseed", "README.md"):
            target = folder / "records" / name
            if garble in RECORD_GARBLES and name.endswith(".mseed"):
                oddity(target, garble.removeprefix("record_"))
            else:
                shutil.copy(INPUTS / "records" / name, target)
    for name in SHARED_FILES:
        link = folder / name
        if not link.exists():
            link.symlink_to(INPUTS / name)
    return path


def oddity(path: Path, kind: str) -> None:
    """Make `path` something that is not a regular file."""
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "devzero":
        path.symlink_to("/dev/zero")
    elif kind == "loop":
        path.symlink_to(path.name)
    elif kind == "folder":
        path.mkdir()
    else:
        raise AssertionError(kind)


FS_MESSAGES = ("not a regular file", "symbolic links form a loop", "is a directory")
"""What a message about a path that is no regular file says."""


class InProcess:
    """The sweep's executor, in this process: the checks run here, as fast as they can."""

    description = "this process (fuzzing)"

    def __init__(self, jobs: int) -> None:
        pass

    def run(self, tasks):
        for key, function, args in tasks:
            yield key, True, function(*args)

    def close(self) -> None:
        pass


NAMES_A_FIELD_OR_LINE = re.compile(
    r"\bline \d+|: (\(top level\)|\"[^\"]*\"|[A-Za-z_][\w+-]*)(\.[\w.+-]+|\[\"[^\"]*\"\]|\[[^\]]+\])*: "
)
"""In a message after its file name: a line, or a field path (`buildings[0].floors[1].slab`,
`materials["C30/37"]`, `"dt "`) followed by ": "."""


CASE_SECONDS = 120
"""A case that takes longer (a read that blocks, a loop that never ends) fails the fuzzer."""


@contextlib.contextmanager
def deadline(seconds: float):
    """Raise TimeoutError in this (the main) thread if the block runs longer than `seconds`."""
    import signal

    def expired(signum, frame):
        raise TimeoutError(f"the case ran for more than {seconds:g} s (a hang)")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def output_of(folder: Path, path: Path, case: dict[str, Any]) -> tuple[str, Path, bool]:
    """(what -o says, the file the results must be in, whether the run must be refused for
    its output) for a run case's `output`."""
    kind = case.get("output", "out.h5")
    out = folder / "out.h5"
    if kind == "model":
        return str(path), path, True
    if kind in ("model_link", "record_link"):
        out.symlink_to(path.name if kind == "model_link" else "records/ridgecrest2019_ccc.mseed")
        return str(out), out, True
    if kind in ("folder/", "existing_folder"):
        (folder / "results").mkdir(exist_ok=kind == "existing_folder")
        return str(folder / "results") + ("/" if kind == "folder/" else ""), folder / "results" / f"{path.stem}.h5", False
    return str(out), out, False


def check_case(folder: Path, case: dict[str, Any]) -> str:
    """Run the case as the command line does; assert the contract; return the outcome."""
    path = write_case(folder, case)
    kind = case.get("output", "out.h5")
    if case["kind"] == "sweep":
        out, given, collides = folder / "swept", str(folder / "swept"), False
        args = ["sweep", str(path), "-o", given, "--dry-run", "--json"]
    else:
        given, out, collides = output_of(folder, path, case)
        args = ["run", str(path), "-o", given, "--json", "--no-progress"] + (["--force"] if collides else [])
    inputs = {p: p.read_bytes() for p in (path, folder / "records" / "ridgecrest2019_ccc.mseed")
              if p.is_file() and not p.is_symlink() or p == path and p.is_file()}  # fmt: skip
    with claim(out) if kind == "claimed" else contextlib.nullcontext(), deadline(CASE_SECONDS):
        result = runner.invoke(app, args, env={"POUND_DEBUG": "1", "COLUMNS": "200", **LIMITS})
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.stderr)
    expect = case.get("expect")  # a saved example of the issue: its exact outcome
    if expect is not None:
        assert result.exit_code == expect["exit"], (expect, result.exit_code, result.stderr)
        for text in expect.get("stderr", []):
            assert text in result.stderr, (text, result.stderr)
    assert all(p.read_bytes() == data for p, data in inputs.items()), "an input was written over"
    refused_by = None
    if collides or kind == "claimed":
        refused_by = "writing there would destroy it" if collides else "is being written by another pound run"
    plain = not (case["mutations"] or case["garble"])
    if plain and refused_by is None:
        assert result.exit_code == 0, f"an unchanged seed is refused: {result.stderr}"
    if plain and refused_by is not None:
        assert result.exit_code == 2 and refused_by in result.stderr, result.stderr
    for where in case.get("must_refuse", []):  # a lax type in a field of an otherwise valid model
        assert result.exit_code == 2 and f": {where}: " in result.stderr, (
            f"{where}: a value of the wrong type was not refused naming the field (exit {result.exit_code}): "
            f"{result.stderr}")  # fmt: skip
    if result.exit_code == 2:
        lines = [line for line in result.stderr.splitlines() if not line.startswith("checking the cases of ")]
        first = lines[0] if lines else ""
        named = (str(path), str(out), given.rstrip("/"))
        assert first.startswith(tuple(f"{p}: " for p in named)), f"the message does not start with the file: {result.stderr}"
        assert all(line.startswith(tuple(f"{p}: " for p in named)) for line in lines), f"a line of stderr is not a problem: {lines}"
        if case["garble"] in FS_GARBLES:
            assert any(text in first for text in FS_MESSAGES), f"does not say what the path is: {first}"
        elif refused_by is None or not plain:
            rest = first.split(": ", 1)[1] if ": " in first else ""
            assert NAMES_A_FIELD_OR_LINE.search(": " + rest) or refused_by and refused_by in first, (
                f"names no field or line: {first}")  # fmt: skip
        if case["garble"] in RECORD_GARBLES and not case["mutations"]:
            assert "excitation.record" in first and any(text in first for text in FS_MESSAGES), first
        assert not out.exists() or collides or kind == "claimed", "a refused case wrote its output"
        return "rejected"
    assert case["garble"] not in FS_GARBLES, f"a path that is no regular file was read: {result.stderr}"
    if case["kind"] == "sweep":
        assert result.exit_code == 0 and not out.exists(), "a dry run writes nothing"
        for line in result.stdout.splitlines():
            json.loads(line)
        return "accepted"
    if kind in ("folder/",):
        assert f"names a folder: the results are in {out}" in result.stderr, result.stderr
    summary = json.loads(result.stdout)
    with h5py.File(out, "r") as f:
        status = str(f.attrs["status"])
    assert status == summary["status"]
    if result.exit_code == 0:
        assert status == "complete"
        return "complete"
    assert status.startswith("failed: ") and len(status) > len("failed: ") + 10, status
    assert f"{status}; partial results in {out}" in result.stderr
    return "failed"


cases = st.fixed_dictionaries(
    {
        "seed": st.sampled_from(sorted(SEEDS)),
        "mutations": st.lists(mutation, min_size=1, max_size=3),
        "format": st.sampled_from(["json", "toml"]),
        "garble": st.sampled_from(GARBLES),
        "output": st.sampled_from(OUTPUTS),
    }
)


def _case(drawn: dict[str, Any]) -> dict[str, Any]:
    kind, seed = SEEDS[drawn["seed"]]
    doc = copy.deepcopy(seed)
    for kind_, pick, value, name in drawn["mutations"]:
        doc = _mutate(doc, kind_, pick, value, name)
    must = []
    (first, pick, _, _), *others = drawn["mutations"]
    if kind == "model" and first == "lax" and not others and drawn["garble"] in (None, "bom"):
        path, old, new = pick_leaf(seed, "lax", pick)
        if must_refuse(old, new):  # the seed is valid: this field alone is wrong
            must.append(format_loc(path))
    return {**drawn, "kind": kind, "document": doc, "must_refuse": must}


def keep(case: dict[str, Any], error: BaseException) -> Path:
    """Save a failing case as tests/fuzz_regressions/case_NNN.json."""
    REGRESSIONS.mkdir(exist_ok=True)
    n = len(list(REGRESSIONS.glob("case_*.json")))
    path = REGRESSIONS / f"case_{n:03d}.json"
    saved = {k: case[k] for k in ("seed", "kind", "format", "garble", "document", "output", "must_refuse") if k in case}
    path.write_text(json.dumps({**saved, "found": f"{type(error).__name__}: {error}"[:300]}, default=str) + "\n")
    return path


@pytest.mark.slow
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])  # fmt: skip
@given(drawn=cases)
def test_fuzzed_model_and_sweep_files(tmp_path_factory, monkeypatch, drawn):
    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    case = _case(drawn)
    try:
        event(f"{case['kind']} {case['format']}: {check_case(tmp_path_factory.mktemp('fuzz'), case)}")
    except Exception as exc:
        if os.environ.get("POUND_FUZZ_KEEP"):
            keep(case, exc)
        raise


def _saved(path: Path) -> dict[str, Any]:
    saved = json.loads(path.read_text())
    if "model" in saved:  # the first regressions: paper_pounding.toml's document, as JSON
        return {"seed": "paper_pounding", "kind": "model", "format": "json", "garble": saved["garble"],
                "document": saved["model"], "mutations": ["saved"]}  # fmt: skip
    return {**saved, "mutations": ["saved"]}


@pytest.mark.parametrize("case", sorted(REGRESSIONS.glob("case_*.json")) if REGRESSIONS.exists() else [],
                         ids=lambda p: p.name)  # fmt: skip
def test_fuzz_regressions(case, tmp_path, monkeypatch):
    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    check_case(tmp_path, _saved(case))


@pytest.mark.parametrize("seed", sorted(SEEDS))
def test_every_seed_is_accepted_as_written(seed, tmp_path, monkeypatch):
    """The unchanged seeds pass, in both formats (so a rejection is the mutation's doing)."""
    monkeypatch.setattr("pounding_cli.sweep.run.LocalPool", InProcess)
    kind, doc = SEEDS[seed]
    for fmt in ("json", "toml"):
        folder = tmp_path / fmt
        folder.mkdir()
        outcome = check_case(folder, {"seed": seed, "kind": kind, "document": doc, "format": fmt, "garble": None,
                                      "mutations": []})  # fmt: skip
        assert outcome in ("complete", "accepted"), (seed, fmt, outcome)


def test_unit_swaps_reach_every_kind_of_field():
    """Each unit swap has fields to act on among the seeds (else it would fuzz nothing)."""
    found = {unit_key(p[-1]) for _, doc in SEEDS.values() for p in _paths(doc) if p and _numeric(_get(doc, p))}
    for units in (LENGTH, FORCE, MASS, RATIO, ANGLE, TIME):
        assert any(key in found for key, swaps in UNITS.items() if swaps is units), units
