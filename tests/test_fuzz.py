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

import copy
import json
import math
import os
import re
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


mutation = st.tuples(
    st.sampled_from(["delete", "set", "rename", "duplicate", "scale", "nest", "unit", "unit"]),
    st.integers(min_value=0, max_value=10_000),
    st.sampled_from(ODD_VALUES),
    st.sampled_from(["nam", "heigth", "slabs", "columns", "dt ", "L", "units", "x", "Duration", "base"]),
)
GARBLES = [None] * 14 + ["truncate", "binary", "latin1", "utf16", "bom"]


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
    """Write the case's file into `folder`, beside links to what the seeds name; its path."""
    text, fmt = _text(case["document"], case["format"])
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
    path.write_bytes(data)
    for name in SHARED_FILES:
        link = folder / name
        if not link.exists():
            link.symlink_to(INPUTS / name)
    return path


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


def check_case(folder: Path, case: dict[str, Any]) -> str:
    """Run the case as the command line does; assert the contract; return the outcome."""
    path = write_case(folder, case)
    out = folder / ("swept" if case["kind"] == "sweep" else "out.h5")
    args = (["sweep", str(path), "-o", str(out), "--dry-run", "--json"] if case["kind"] == "sweep"
            else ["run", str(path), "-o", str(out), "--json", "--no-progress"])  # fmt: skip
    result = runner.invoke(app, args, env={"POUND_DEBUG": "1", "COLUMNS": "200", **LIMITS})
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.stderr)
    if not (case["mutations"] or case["garble"]):
        assert result.exit_code == 0, f"an unchanged seed is refused: {result.stderr}"
    if result.exit_code == 2:
        lines = [line for line in result.stderr.splitlines() if not line.startswith("checking the cases of ")]
        first = lines[0] if lines else ""
        assert first.startswith(f"{path}: "), f"the message does not start with the file: {result.stderr}"
        assert all(line.startswith(f"{path}: ") for line in lines), f"a line of stderr is not a problem: {lines}"
        assert NAMES_A_FIELD_OR_LINE.search(first[len(str(path)) :]), f"names no field or line: {first}"
        assert not out.exists(), "a refused case wrote its output"
        return "rejected"
    if case["kind"] == "sweep":
        assert result.exit_code == 0 and not out.exists(), "a dry run writes nothing"
        for line in result.stdout.splitlines():
            json.loads(line)
        return "accepted"
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
    }
)


def _case(drawn: dict[str, Any]) -> dict[str, Any]:
    kind, seed = SEEDS[drawn["seed"]]
    doc = copy.deepcopy(seed)
    for kind_, pick, value, name in drawn["mutations"]:
        doc = _mutate(doc, kind_, pick, value, name)
    return {**drawn, "kind": kind, "document": doc}


def keep(case: dict[str, Any], error: BaseException) -> Path:
    """Save a failing case as tests/fuzz_regressions/case_NNN.json."""
    REGRESSIONS.mkdir(exist_ok=True)
    n = len(list(REGRESSIONS.glob("case_*.json")))
    path = REGRESSIONS / f"case_{n:03d}.json"
    saved = {k: case[k] for k in ("seed", "kind", "format", "garble", "document")}
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
