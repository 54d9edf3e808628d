"""Fuzzing record files: mutate valid record inputs and run what the CLI runs on them.

Seeds (all shippable: the synthetic files of tests/records/data/ and plain text made here):
a PEER .AT2 file, CSMIP/COSMOS V1 and V2 text, one- and two-column plain text, and a
``*.record.toml`` record definition naming them. Mutations: truncation, binary garbage,
wrong encodings (UTF-16, Latin-1, BOM, line endings), NaN/inf/huge values in the data,
header lines deleted/duplicated/retyped, point counts and time steps changed (NPTS/DT
mismatches), empty files, enormous lines; record definitions also get their keys deleted,
retyped and renamed. Each case runs one of

- ``pound record FILE`` (a record file as read),
- ``pound record DEF.record.toml`` (a definition: read, processed, scaled),
- ``pound validate MODEL`` (a one-storey model whose excitation names the definition),

through typer's CliRunner with ``POUND_DEBUG=1``, so a bug surfaces as its exception rather
than as the "internal error" paragraph. Required: no uncaught exception; every rejection is
exit 2 with a message naming the file (and the field or line); every acceptance gives
finite accelerations (checked through the API the command calls) and valid JSON.

POUND_FUZZ_EXAMPLES sets the number of cases (default 1000, fixed seed). A failing case is
kept as a folder under tests/fuzz_regressions/records/ (its files and case.json) and
replayed by test_record_fuzz_regressions.
"""

from __future__ import annotations

import copy
import json
import math
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from pounding_cli.api import prepare
from pounding_cli.cli import app
from pounding_cli.records.inspect import open_record

from conftest import model_doc, square_building
from test_fuzz import CASE_SECONDS, deadline, oddity

EXAMPLES = int(os.environ.get("POUND_FUZZ_EXAMPLES", "1000"))
DATA = Path(__file__).parent / "records" / "data"
REGRESSIONS = Path(__file__).parent / "fuzz_regressions" / "records"
runner = CliRunner()


def _plain(columns: int) -> bytes:
    t = np.arange(40) * 0.01
    a = 0.3 * np.sin(2 * np.pi * 2.0 * t) * np.exp(-t)
    if columns == 1:
        return ("# one value per line, m/s2\n" + "".join(f"{v:.6f}\n" for v in a)).encode()
    return ("time, acc\n" + "".join(f"{ti:.2f}, {v:.6f}\n" for ti, v in zip(t, a))).encode()


# name -> (bytes, what `pound record` needs for it, what a definition's component says)
SEEDS: dict[str, tuple[bytes, list[str], dict[str, Any]]] = {
    "synthetic.AT2": ((DATA / "synthetic.AT2").read_bytes(), [], {"units": "g"}),
    "synthetic_2ch.V1": ((DATA / "synthetic_2ch.V1").read_bytes(), [], {"units": "g", "trace": 0}),
    "synthetic_2ch.V2": ((DATA / "synthetic_2ch.V2").read_bytes(), [], {"units": "cm/s2", "trace": 0}),
    "one_column.txt": (_plain(1), ["--units", "m/s2", "--dt", "0.01"], {"units": "m/s2", "dt": 0.01}),
    "two_columns.csv": (_plain(2), ["--units", "m/s2"], {"units": "m/s2"}),
}

ODD_NUMBERS = [
    "nan", "NaN", "inf", "-inf", "Infinity", "1e308", "-1.7e308", "1e309", "-1e400", "1e-320", "0", "-0",
    "5e-324", "2.2250738585072014e-308", "1.7976931348623157e308", "1D308", "1.5D-03", "-.25d+01", "²", "٣",
    "-1", "1", "2", "3", "10", "999999999999", "9" * 5000, "1.2.3", "1,5", "0x10", "", "--1", ".", "1e",
    "1d3", "  ", "é", "1.#INF", "-.0200", "00000000000000000000000000000000000.02",
]  # fmt: skip
ODD_LINES = [
    "", "NPTS=     23, DT=   .0100 SEC,", "NPTS= 0, DT= 0 SEC", "NPTS=999999999999, DT=1e-320 SEC",
    "ACCELERATION TIME SERIES IN UNITS OF FURLONGS", "ACCELERATION TIME SERIES IN UNITS OF CM/S2",
    "Corrected accelerogram", "Uncorrected Accelerogram Data", "/&",
    "    21 Accelerogram points at 0 pts/sec in units of g.       Format: (8f9.6)",
    "    21 Accelerogram points at 99999999999999999999999999999999 pts/sec in units of g. Format: (8f9.6)",
    "   20 points of accel data equally spaced at .0000 sec, in cm/sec2. (8f10.6)",
    "   20 points of accel data equally spaced at  .005 sec, in furlongs. (0f0.0)",
    "99999999999 points of accel data equally spaced at  .005 sec, in cm/sec2. (8f10.6)",
    "time, acc", "0.0, nan", "1e308 1e308", "1 2 3", "\x00\x01\x02", "\t,;", "# comment", "%",
    "nan nan nan nan nan", "  .1E+00  .2E+00  inf  .3E+00  .4E+00",
]  # fmt: skip
ODD_VALUES = [
    None, True, 0, -1, 1e300, math.nan, math.inf, -math.inf, "", "g", "m/s2", "furlongs", "auto", "text",
    "AT2", "COSMOS", "MSEED", "PICKLE", "HNE", "0", "7", "../nowhere.AT2", "/", ".", "synthetic.AT2", [], {},
    {"freqmin": 0.1}, {"freqmin": 1e9}, {"start": 0.05, "end": 0.1}, {"start": 100.0}, 1e-300, 10**30,
    "é\u0000", 0.5, 2.0, 0.001,
]  # fmt: skip
GARBAGE = [b"\x00", b"\xff\xfe", b"\xef\xbb\xbf", bytes(range(256)), b"\x1a\x1b\x7f", b"\xc3\x28", b"obspy.core.stream"]


# --- mutating a file's bytes ----------------------------------------------------------------------


def _lines(data: bytes) -> list[bytes]:
    return data.splitlines(keepends=True) or [b""]


def _number_spans(data: bytes, header_only: bool) -> list[tuple[int, int]]:
    """Byte spans of the numbers in the file (in its first 30 lines when header_only)."""
    import re

    text = data
    if header_only:
        text = b"".join(_lines(data)[:30])
    return [m.span() for m in re.finditer(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?", text)]


def mutate_bytes(data: bytes, kind: str, pick: int, payload: int) -> bytes:
    """One mutation of a record file's bytes; `pick` chooses where, `payload` what."""
    lines = _lines(data)
    line = pick % len(lines)
    if kind == "truncate":
        return data[: pick % (len(data) + 1)]
    if kind == "garbage":
        at = pick % (len(data) + 1)
        return data[:at] + GARBAGE[payload % len(GARBAGE)] + data[at:]
    if kind == "binary":
        return bytes((i * 37 + payload) % 256 for i in range(512 + pick % 4096))
    if kind == "empty":
        return b"" if payload % 2 else b"\n\n  \n"
    if kind == "utf16":
        text = data.decode("utf-8", errors="replace")
        return text.encode(("utf-16", "utf-16-le", "utf-16-be", "utf-32")[payload % 4])
    if kind == "latin1":
        text = data.decode("utf-8", errors="replace").splitlines(keepends=True) or [""]
        text[line] = "é°µ " + text[line]
        return "".join(text).encode("latin-1", errors="replace")
    if kind == "bom":
        return b"\xef\xbb\xbf" + data
    if kind == "line_endings":
        ending = (b"\r\n", b"\r", b"\n")[payload % 3]
        return ending.join(data.splitlines()) + ending
    if kind == "delete_line":
        return b"".join(lines[:line] + lines[line + 1 :])
    if kind == "duplicate_line":
        return b"".join(lines[: line + 1] + lines[line:])
    if kind == "swap_lines" and len(lines) > 1:
        other = (line + 1 + payload) % len(lines)
        lines[line], lines[other] = lines[other], lines[line]
        return b"".join(lines)
    if kind == "retype_line":
        new = ODD_LINES[payload % len(ODD_LINES)].encode("utf-8")
        return b"".join(lines[:line] + [new + b"\n"] + lines[line + 1 :])
    if kind in ("value", "header_number"):
        spans = _number_spans(data, header_only=kind == "header_number")
        if not spans:
            return data
        start, end = spans[pick % len(spans)]
        return data[:start] + ODD_NUMBERS[payload % len(ODD_NUMBERS)].encode() + data[end:]
    if kind == "enormous_line":
        big = (b"1.0 " * 300_000, b"x" * 1_200_000, b"9" * 1_200_000, b"\t" * 1_200_000, b"-" * 1_200_000)
        return b"".join(lines[:line] + [big[payload % len(big)] + b"\n"] + lines[line:])
    return data


BYTE_MUTATIONS = [
    "truncate", "garbage", "binary", "empty", "utf16", "latin1", "bom", "line_endings", "delete_line",
    "duplicate_line", "swap_lines", "retype_line", "value", "value", "header_number", "header_number",
    "enormous_line",
]  # fmt: skip
byte_mutation = st.tuples(
    st.sampled_from(BYTE_MUTATIONS), st.integers(0, 100_000), st.integers(0, 1000)
)


# --- mutating a record definition -----------------------------------------------------------------


def definition(seed_l: str, seed_t: str) -> dict[str, Any]:
    """A record definition naming two (fuzzed) record files."""
    return {
        "name": "fuzzed record",
        "event": "synthetic",
        "L": {"file": "L_" + seed_l, **SEEDS[seed_l][2]},
        "T": {"file": "T_" + seed_t, **SEEDS[seed_t][2]},
        "processing": {"demean": True},
    }


def definition_toml(doc: dict[str, Any]) -> bytes:
    """The definition as TOML (its values are strings, numbers and booleans)."""
    out = [f"{k} = {json.dumps(v)}" for k, v in doc.items() if not isinstance(v, dict)]
    for key, table in doc.items():
        if isinstance(table, dict):
            out.append(f"\n[{key}]")
            out += [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    return ("\n".join(out) + "\n").encode()


def _paths(node: Any, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))


def mutate_document(doc: dict, kind: str, pick: int, payload: int) -> dict:
    """One mutation of the definition's keys (as tests/test_fuzz.py does to models)."""
    value = copy.deepcopy(ODD_VALUES[payload % len(ODD_VALUES)])
    paths = [p for p in _paths(doc) if p]
    path = paths[pick % len(paths)]
    parent = doc
    for p in path[:-1]:
        parent = parent[p]
    key = path[-1]
    if kind == "delete":
        del parent[key]
    elif kind == "set":
        parent[key] = value
    elif kind == "rename":
        parent[("nam", "Fiel", "unit", "L ", "t", "trace_id", "proccessing")[payload % 7]] = parent.pop(key)
    return doc


doc_mutation = st.tuples(st.sampled_from(["delete", "set", "rename"]), st.integers(0, 1000), st.integers(0, 1000))


# --- one case: write the files, run the command, check the outcome -------------------------------


ODDITIES = [None] * 24 + ["fifo", "devzero", "loop", "folder"]
"""The fuzzed record file is not a regular file (issue 27: a FIFO blocked, /dev/zero was read
without end): exit 2 naming it, within the case's deadline."""


def plan_case(folder: Path, case: dict[str, Any]) -> tuple[list[str], Path, Path]:
    """The command's arguments, the file given on the command line and the fuzzed record file."""
    seed = case["seed"]
    if case["driver"] == "file":
        target = folder / seed
        return ["record", str(target), *SEEDS[seed][1]], target, target
    fuzzed = folder / ("L_" + seed)
    record = folder / ("fuzz.record.json" if case["doc_as_json"] else "fuzz.record.toml")
    if case["driver"] == "definition":
        return ["record", str(record)], record, fuzzed
    model = folder / "fuzz_model.json"
    return ["validate", str(model)], model, fuzzed


def write_case(folder: Path, case: dict[str, Any]) -> None:
    """Write the case's files into `folder` (where plan_case says)."""
    args, given_file, fuzzed = plan_case(folder, case)
    data = SEEDS[case["seed"]][0]
    for kind, pick, payload in case["mutations"]:
        data = mutate_bytes(data, kind, pick, payload)
    if case.get("oddity"):
        oddity(fuzzed, case["oddity"])
    else:
        fuzzed.write_bytes(data)
    if case["driver"] == "file":
        return
    (folder / ("T_" + case["other"])).write_bytes(SEEDS[case["other"]][0])
    doc = definition(case["seed"], case["other"])
    for kind, pick, payload in case["doc_mutations"]:
        doc = mutate_document(doc, kind, pick, payload)
    record = folder / ("fuzz.record.json" if case["doc_as_json"] else "fuzz.record.toml")
    if case["doc_as_json"]:
        record.write_text(json.dumps(doc))
    else:
        text = definition_toml(doc) if all(isinstance(v, (str, int, float, bool, dict)) for v in doc.values()) else b""
        for kind, pick, payload in case["toml_mutations"]:
            text = mutate_bytes(text, kind, pick, payload)
        record.write_bytes(text)
    if case["driver"] == "model":
        model = model_doc(square_building(size=6.0), duration=0.5)
        model["excitation"]["record"] = record.name
        given_file.write_text(json.dumps(model))


def _strict_json(text: str) -> Any:
    def refuse(constant: str) -> Any:
        raise AssertionError(f"--json printed {constant}, which is not JSON")

    return json.loads(text, parse_constant=refuse)


def check_case(folder: Path, case: dict[str, Any]) -> str:
    """Run the case as the CLI would; assert the contract; return "accepted" or "rejected"."""
    args, given_file, fuzzed = plan_case(folder, case)
    if case["json"]:
        args.append("--json")
    with deadline(CASE_SECONDS):
        result = runner.invoke(app, args, env={"POUND_DEBUG": "1", "COLUMNS": "200"})
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code in (0, 2), (result.exit_code, result.stderr)
    if case.get("oddity") and not (case["doc_mutations"] or case["toml_mutations"]):
        # (a mutated definition may be refused first, or no longer name the file)
        assert result.exit_code == 2, f"read a path that is no file: {result.stderr}"
        assert str(fuzzed) in result.stderr, f"does not name the path that is no file: {result.stderr}"
    elif not (case["mutations"] or case["doc_mutations"] or case["toml_mutations"]):
        assert result.exit_code == 0, f"an unchanged seed is refused: {result.stderr}"
    if result.exit_code == 2:
        message = result.stderr
        assert str(given_file) in message, f"the message does not name {given_file}: {message}"
        if case["driver"] == "definition" and not case["doc_mutations"] and not case["toml_mutations"]:
            # only the record file was fuzzed: the message names it and the component field
            assert str(fuzzed) in message, f"the message does not name {fuzzed}: {message}"
            assert ": L." in message, f"the message does not name the field L.<...>: {message}"
        return "rejected"
    if case["json"]:
        _strict_json(result.stdout)
    if case["driver"] == "model":
        scene_acc = prepare(given_file).ground.acceleration
        assert np.isfinite(scene_acc).all(), "accepted a model whose ground acceleration is not finite"
    else:
        extra = SEEDS[case["seed"]][1] if case["driver"] == "file" else []
        options = dict(zip([a.lstrip("-") for a in extra[::2]], extra[1::2]))
        if "dt" in options:
            options["dt"] = float(options["dt"])
        for component in open_record(given_file, **options).components:
            assert component.acceleration.size >= 2
            assert np.isfinite(component.acceleration).all(), f"accepted non-finite samples in {component.name}"
            assert math.isfinite(component.dt) and component.dt > 0
    return "accepted"


cases = st.fixed_dictionaries(
    {
        "seed": st.sampled_from(sorted(SEEDS)),
        "other": st.sampled_from(sorted(SEEDS)),
        "mutations": st.lists(byte_mutation, min_size=0, max_size=3),
        "driver": st.sampled_from(["file"] * 5 + ["definition"] * 4 + ["model"]),
        "doc_mutations": st.lists(doc_mutation, max_size=2),
        "doc_as_json": st.booleans(),
        "toml_mutations": st.lists(byte_mutation, max_size=1),
        "json": st.booleans(),
        "oddity": st.sampled_from(ODDITIES),
    }
)


def keep(folder: Path, case: dict[str, Any]) -> Path:
    """Save a failing case (its files as written, and the case) as a regression folder."""
    REGRESSIONS.mkdir(parents=True, exist_ok=True)
    n = len([p for p in REGRESSIONS.iterdir() if p.name.startswith("case_")])
    target = REGRESSIONS / f"case_{n:03d}"
    def oddities(directory: str, names: list[str]) -> list[str]:  # remade from the case on replay
        return [n for n in names if (Path(directory) / n).is_symlink() or not (Path(directory) / n).is_file()]

    shutil.copytree(folder, target, ignore=oddities)
    for f in target.iterdir():
        if f.stat().st_size > 100_000:  # keep regressions small: an enormous line is remade
            f.unlink()
    (target / "case.json").write_text(json.dumps(case, indent=1) + "\n")
    return target


@pytest.mark.slow
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])  # fmt: skip
@given(case=cases)
def test_fuzzed_record_files(tmp_path_factory, case):
    folder = tmp_path_factory.mktemp("recfuzz")
    write_case(folder, case)
    try:
        check_case(folder, case)
    except Exception:
        if os.environ.get("POUND_FUZZ_KEEP"):
            keep(folder, case)
        raise


@pytest.mark.parametrize("case", sorted(REGRESSIONS.glob("case_*/case.json")) if REGRESSIONS.exists() else [],
                         ids=lambda p: p.parent.name)  # fmt: skip
def test_record_fuzz_regressions(case, tmp_path):
    """Every failing case the fuzzer found, replayed from the files it wrote (files too large
    to keep are remade from the case's description)."""
    saved = json.loads(case.read_text())
    write_case(tmp_path, saved)
    for f in case.parent.iterdir():
        if f.name != "case.json":
            shutil.copy(f, tmp_path / f.name)
    outcome = check_case(tmp_path, saved)
    if "expect" in saved:  # an example of issue 27: its exact outcome
        assert outcome == saved["expect"], (outcome, saved["found"])
