"""Sweep files (``*.sweep.toml`` or ``.json``): a base model and the settings that vary.

A sweep file names a base model file and, for one study or for several (``[studies.NAME]``),
the values to give to fields of the model, addressed by dotted paths into the model
document (docs/sweep.md, "Paths"). Each study's runs are its named ``cases`` (override
tables) × the combinations of its ``parameters`` (a full product in ``mode = "grid"``, item
by item in ``mode = "zip"``); either alone is a study too. Like model files, sweep files are
strict: unknown keys, malformed paths and empty value lists are errors naming the field.

What a path points at, and whether a value suits the model, is checked when the sweep is
expanded against the base model (:mod:`pounding_cli.sweep.expand`), before anything runs.
"""

from __future__ import annotations

import datetime
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Strict as StrictType
from pydantic import (
    BaseModel, BeforeValidator, Discriminator, Field, JsonValue, PlainValidator, Tag, WithJsonSchema, model_validator,
)  # fmt: skip

from .base import Count, Name, Real, Strict
from .load import FRIENDLIER, PLAIN_KEY, describe_error, read_document, validated

MAX_CASES = 100_000
"""Most cases one sweep may expand to (and most values one parameter may take)."""

ROUND_DIGITS = 12
"""Range and linspace values are rounded to this many significant digits, so that steps of
0.1 give 0.1, 0.2, 0.3 as written rather than 0.30000000000000004."""


# --- paths -------------------------------------------------------------------------------

Key = str
"""A table key, or the name of an item of a list of named tables (buildings, obstacles)."""


@dataclass(frozen=True)
class Index:
    """A list selector: ``[i]`` (0-based, negative from the end) or ``[*]`` (``i is None``)."""

    i: int | None

    def __str__(self) -> str:
        return "[*]" if self.i is None else f"[{self.i}]"


Step = Key | Index

_BARE = re.compile(r"[A-Za-z0-9_+\-]+")
_SELECTOR = re.compile(r"\[(\*|-?[0-9]+)\]")


def parse_path(text: str) -> tuple[Step, ...]:
    """``'buildings.left.floors[*].eccentricity'`` → ('buildings', 'left', 'floors', Index(None),
    'eccentricity'). Keys are bare (letters, digits, _ + -) or double-quoted JSON strings
    (``materials."C30.37".elastic_modulus``); each may be followed by selectors ``[i]``, ``[*]``.
    Raises ValueError saying where the text stops making sense."""
    steps: list[Step] = []
    pos = 0
    while True:
        if text.startswith('"', pos):
            try:
                key, end = json.JSONDecoder().raw_decode(text, pos)
            except json.JSONDecodeError:
                raise ValueError(f"unterminated quoted key at character {pos + 1}") from None
            if not isinstance(key, str) or not key:
                raise ValueError(f"empty quoted key at character {pos + 1}")
            steps.append(key)
            pos = end
        else:
            match = _BARE.match(text, pos)
            if match is None:
                raise ValueError(_expected_key(text, pos))
            steps.append(match.group())
            pos = match.end()
        while (sel := _SELECTOR.match(text, pos)) is not None:
            steps.append(Index(None if sel.group(1) == "*" else int(sel.group(1))))
            pos = sel.end()
        if pos == len(text):
            return tuple(steps)
        if text[pos] != ".":
            raise ValueError(
                f"unexpected {text[pos]!r} at character {pos + 1}: after a key come '.', "
                "'[i]' or '[*]' (quote keys holding other characters: \"C30.37\")"
            )
        pos += 1


def _expected_key(text: str, pos: int) -> str:
    if not text:
        return "empty path; write a dotted path into the model, e.g. excitation.angle"
    where = f"at character {pos + 1}"
    return (f"expected a key {where} (letters, digits, _ + -, or a quoted \"key\"); paths look like "
            "excitation.angle, buildings.left.floors[*].eccentricity")  # fmt: skip


def path_text(steps: tuple[Step, ...]) -> str:
    """The canonical text of a parsed path (bare keys where possible)."""
    out = ""
    for step in steps:
        if isinstance(step, Index):
            out += str(step)
        else:
            key = step if _BARE.fullmatch(step) else json.dumps(step)
            out += ("." if out else "") + key
    return out


def _check_path(value: Any) -> Any:
    if isinstance(value, str):
        parse_path(value)
    return value


PathKey = Annotated[str, StrictType(), Field(max_length=500), BeforeValidator(_check_path)]
"""A dotted path into the model document, e.g. "buildings.left.floors[*].eccentricity"."""


# --- values ------------------------------------------------------------------------------


def _plain_json(value: Any) -> Any:
    """TOML dates and times become ISO text (as record definitions take them); floats that
    are not finite are refused."""
    if isinstance(value, (datetime.date, datetime.time)):
        return value.isoformat()
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"expected a finite number, got {value}")
    if isinstance(value, list):
        return [_plain_json(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain_json(v) for k, v in value.items()}
    return value


Value = Annotated[
    JsonValue, BeforeValidator(_plain_json), WithJsonSchema({"description": "Any value the model field takes."})
]
"""A value for a model field: number, string, boolean, list or table."""


def _number(value: Any) -> int | float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"expected a number; got {value!r:.80}")
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"expected a finite number; got {value}")
    if isinstance(value, int) and abs(value) > MAX_FLOAT:  # it could not become a model's number
        raise ValueError(f"expected a number below 1.8e308 in magnitude; got a whole number of {len(str(abs(value)))} digits")
    return value


MAX_FLOAT = 1.7976931348623157e308
"""The largest float: a sweep's numbers become the model's, which are floats."""


Number = Annotated[int | float, PlainValidator(_number), WithJsonSchema({"type": "number"})]
"""A finite number; an integer stays an integer (so that ranges of integers give integers)."""


def _rounded(value: float) -> float:
    return float(f"{value:.{ROUND_DIGITS}g}") + 0.0  # + 0.0: no -0.0


class Range(Strict):
    """Values start, start + step, start + 2·step, … up to stop, which is included when it
    falls on a step (within 1e-9 of a step). Integers throughout give integers."""

    start: Number
    """First value, in the unit of the field."""

    stop: Number
    """Last value (included if a whole number of steps from start), in the unit of the field."""

    step: Number
    """Increment, not 0, in the unit of the field; negative to count down."""

    @model_validator(mode="after")
    def _finite_count(self) -> "Range":
        if self.step == 0:
            raise ValueError("step is 0: give a step towards stop")
        span = (float(self.stop) - float(self.start)) / float(self.step)  # inf for 1e308 - (-1e308)
        if span < -1e-9:
            raise ValueError(f"step {self.step:g} goes away from stop {self.stop:g} (start {self.start:g})")
        if not span <= MAX_CASES:
            count = f"{math.floor(span) + 1}" if math.isfinite(span) else "more than 1e308"
            raise ValueError(f"{count} values; a parameter takes at most {MAX_CASES}")
        return self

    def values(self) -> list[float | int]:
        """The values, in order."""
        n = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
        if all(isinstance(v, int) for v in (self.start, self.stop, self.step)):
            return [int(self.start + k * self.step) for k in range(n)]
        return [_rounded(self.start + k * self.step) for k in range(n)]


class Linspace(Strict):
    """num values evenly spaced from start to stop, both included."""

    start: Real
    """First value, in the unit of the field."""

    stop: Real
    """Last value, in the unit of the field."""

    num: Annotated[Count, Field(ge=1, le=MAX_CASES)]
    """How many values (1 gives start alone)."""

    def values(self) -> list[float]:
        """The values, in order."""
        if self.num == 1:
            return [_rounded(self.start)]
        width = (self.stop - self.start) / (self.num - 1)
        return [_rounded(self.start + k * width) for k in range(self.num - 1)] + [_rounded(self.stop)]


def _values_kind(value: Any) -> str | None:
    """Which form a parameter's values take: "list", "range" (has step), "linspace" (has num)."""
    if isinstance(value, list):
        return "list"
    if isinstance(value, dict):
        return "linspace" if "num" in value else "range"
    if isinstance(value, (Range, Linspace)):
        return value.__class__.__name__.lower()
    return None


ParameterValues = Annotated[
    Annotated[Annotated[list[Value], Field(min_length=1, max_length=MAX_CASES)], Tag("list")]
    | Annotated[Range, Tag("range")]
    | Annotated[Linspace, Tag("linspace")],
    Discriminator(
        _values_kind,
        custom_error_type="parameter_values",
        custom_error_message="expected a list of values [a, b, ...], a range {start, stop, step} or a "
        "linspace {start, stop, num} (a single value belongs in `set`)",
    ),
]

CaseName = Annotated[str, StrictType(), Field(min_length=1, max_length=200, pattern=r"^[^/\x00-\x1f\x7f]+$")]
"""A case's name: any text without '/' or control characters."""

Overrides = dict[PathKey, Value]


def values_of(spec: list[Any] | Range | Linspace) -> list[Any]:
    """The list of values a parameter takes."""
    return spec.values() if isinstance(spec, (Range, Linspace)) else list(spec)


class Study(Strict):
    """One study: its named cases × the combinations of its parameters (either alone works)."""

    description: Annotated[str, StrictType(), Field(max_length=2000)] = ""
    """What the study is about (free text, kept in the summary's attributes)."""

    mode: Literal["grid", "zip"] = "grid"
    """How parameters combine: "grid", every combination (the first parameter varies
    slowest); "zip", the i-th value of every parameter together (all the same length)."""

    parameters: Annotated[dict[PathKey, ParameterValues], Field(max_length=100)] = {}
    """Path → the values it takes: a list, a range {start, stop, step} or a linspace
    {start, stop, num}."""

    cases: Annotated[dict[CaseName, Overrides], Field(max_length=MAX_CASES)] = {}
    """Named cases: case name → a table of path → value. With parameters, every case is
    run at every parameter combination."""

    set: Overrides = {}
    """Path → value given to every case of the study (after the sweep's own `set`)."""

    @model_validator(mode="after")
    def _something_varies(self) -> "Study":
        if not self.parameters and not self.cases:
            raise ValueError("nothing varies: give parameters, cases or both")
        counts = {path: len(values_of(spec)) for path, spec in self.parameters.items()}
        if self.mode == "zip" and len(set(counts.values())) > 1:
            listed = ", ".join(f"{p}: {n}" for p, n in counts.items())
            raise ValueError(f'mode = "zip" takes parameters with equal numbers of values; got {listed}')
        combos = math.prod(counts.values()) if self.mode == "grid" else max(counts.values(), default=1)
        total = combos * max(len(self.cases), 1)
        if total > MAX_CASES:
            raise ValueError(f"the study expands to {total} cases; a sweep runs at most {MAX_CASES}")
        return self


class SummarySettings(Strict):
    """What the summary table reports besides its fixed columns (docs/sweep.md, "Summary")."""

    columns: Annotated[dict[Name, Annotated[list[Name], Field(min_length=1)]], Field(max_length=1000)] = {}
    """Building name → column names whose peak interstorey deflections get one summary
    column per storey and direction, e.g. { left = ["C9"] }. Every building's largest peak
    (over all its columns and storeys) is in the summary regardless."""


ModelFile = Annotated[str, StrictType(), Field(min_length=1, max_length=4096, pattern=r"(?i)\.(toml|json)$")]


class SweepFile(Strict):
    """A sweep: a base model, and the settings that vary, as one study or several."""

    title: Annotated[str, StrictType(), Field(max_length=2000)] = ""
    """A one-line description of the sweep, kept in the summary."""

    base: ModelFile
    """The base model file (.toml or .json), relative to the sweep file. Values of the sweep
    are written into its document, so paths inside them (records) are relative to it."""

    set: Overrides = {}
    """Path → value given to every case (e.g. a shorter analysis.duration)."""

    mode: Literal["grid", "zip"] = "grid"
    """How parameters combine: "grid", every combination (the first parameter varies
    slowest); "zip", the i-th value of every parameter together. For a sweep of one study
    written at the top level; see studies."""

    parameters: Annotated[dict[PathKey, ParameterValues], Field(max_length=100)] = {}
    """Path → the values it takes: a list, a range {start, stop, step} or a linspace
    {start, stop, num}. For a sweep of one study written at the top level; see studies."""

    cases: Annotated[dict[CaseName, Overrides], Field(max_length=MAX_CASES)] = {}
    """Named cases: case name → a table of path → value. For a sweep of one study written at
    the top level; see studies."""

    studies: Annotated[dict[Name, Study], Field(max_length=1000)] = {}
    """Several studies by name, each with its own mode, parameters, cases and set; the sweep
    runs all of them (cases with identical inputs run once)."""

    summary: SummarySettings = SummarySettings()
    """Extra columns of the summary table."""

    suite: Annotated[str, StrictType(), Field(min_length=1, max_length=4096)] | None = None
    """A record suite: "far-field" or "near-field" (FEMA P695, the extra pounding-cli[suites])
    or the path of a suite file relative to the sweep file. Every case is run under each of
    its records (and orientations): its excitation.record becomes the record's, and the
    parameters excitation.record.name (the suite's case, e.g. RSN953-LT) and excitation.scale
    (the base model's scale times the record's factor, dimensionless) are summary columns."""

    @model_validator(mode="after")
    def _one_layout(self) -> "SweepFile":
        top = bool(self.parameters or self.cases)
        if top and self.studies:
            raise ValueError(
                "give either parameters and cases at the top level (one study) or [studies.NAME] tables, not both"
            )
        if not top and not self.studies and self.suite is None:
            raise ValueError("nothing varies: give parameters, cases, or [studies.NAME] tables")
        total = sum(_count(s) for s in self.all_studies().values())
        if total > MAX_CASES:
            raise ValueError(f"the sweep expands to {total} cases; a sweep runs at most {MAX_CASES}")
        return self

    def all_studies(self) -> dict[str, Study]:
        """Study name → study; a sweep written at the top level is one study named ""."""
        if self.studies:
            return dict(self.studies)
        if not self.parameters and not self.cases:  # a suite alone: one case per record (sweep.suites)
            return {"": Study.model_construct(mode=self.mode, parameters={}, cases={}, set={}, description="")}
        return {"": Study(mode=self.mode, parameters=self.parameters, cases=self.cases)}


def _count(study: Study) -> int:
    counts = [len(values_of(spec)) for spec in study.parameters.values()]
    combos = (math.prod(counts) if study.mode == "grid" else max(counts)) if counts else 1
    return combos * max(len(study.cases), 1)


# --- loading -----------------------------------------------------------------------------


@dataclass(frozen=True)
class LoadedSweep:
    """A validated sweep file and the file it came from (`base` is relative to it)."""

    sweep: SweepFile
    source: Path  # as the user named it: messages quote it so

    @property
    def base(self) -> Path:
        """The base model file."""
        return self.source.parent / self.sweep.base


def load_sweep(path: str | Path) -> LoadedSweep:
    """Read and validate a sweep file. Raises InputError naming the file and field."""
    path = Path(path)
    return validate_sweep(read_document(path), path)


def validate_sweep(data: dict[str, Any], source: str | Path) -> LoadedSweep:
    """Validate an already parsed sweep document that came from `source`."""
    source = Path(source)
    return LoadedSweep(sweep=validated(SweepFile, data, source, "a sweep file", _describe), source=source)


# The keys of these fields are paths, case names or names: messages quote them ["..."].
# A case's table is keyed by case name, then by path: two keyed steps.
_KEYED = {"parameters": 1, "cases": 2, "set": 1, "studies": 1, "columns": 1}


def format_sweep_loc(loc: tuple[Any, ...]) -> str:
    """('studies', '6.1', 'parameters', 'excitation.angle') → 'studies["6.1"].parameters["excitation.angle"]'.

    The keys of tables keyed by paths, case names or names are quoted in brackets."""
    out = ""
    keyed = 0
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
            keyed = 0
        elif keyed or not PLAIN_KEY.fullmatch(str(part)):  # keyed, or a key of spaces or odd characters
            out += f"[{json.dumps(part, ensure_ascii=False)}]" if out else json.dumps(part, ensure_ascii=False)
            keyed = max(keyed - 1, 0)
        else:
            out += ("." if out else "") + str(part)
            keyed = _KEYED.get(part, 0)
    return out or "(top level)"


def _plain_loc(loc: tuple[Any, ...]) -> tuple[Any, ...]:
    """The error's location without pydantic's own steps through unions and validators
    ('list[...]', 'function-before[...]', 'Range', 'Linspace', '[key]')."""
    internal = ("list[", "function-", "json-or-python[", "[key]")
    tags = ("list", "range", "linspace")
    out = []
    for i, part in enumerate(loc):
        if isinstance(part, str) and (part.startswith(internal) or (part in tags and i >= 2 and loc[i - 2] in _KEYED)):
            continue
        out.append(part)
    return tuple(out)


_PATTERNS = {
    "base": "expected the path of a .toml or .json model file",
    "cases": "a case name is text without '/' or control characters",
}


def _describe(source: Path, error: dict[str, Any]) -> str:
    """A sweep file's error (describe_error), located without pydantic's own steps through
    unions and validators, with the keys of tables keyed by paths and names quoted."""
    return describe_error(source, {**error, "loc": _plain_loc(tuple(error["loc"]))}, SweepFile,
                          where=format_sweep_loc, text_for=_text_for, unknown_key_note=_unknown_key_note)  # fmt: skip


def _text_for(kind: str, loc: tuple[Any, ...]) -> str | None:
    """A sweep file's own wording of an error kind."""
    if kind == "string_pattern_mismatch":
        field = next((p for p in reversed(loc) if p in _PATTERNS), None)
        return _PATTERNS.get(field, FRIENDLIER[kind])
    if kind == "too_short":
        return "expected at least one value"
    return None


def _unknown_key_note(owner: type[BaseModel], key: str) -> str:
    """A model path written where a sweep's own keys go."""
    if owner in (SweepFile, Study) and ("." in key or "[" in key):
        return " (paths into the model go under parameters, cases or set)"
    return ""
