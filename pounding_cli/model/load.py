"""Reading model files (TOML or JSON) into a validated :class:`PoundModel`.

Every problem becomes an :class:`~pounding_cli.errors.InputError` whose text reads
``file: path.to.field: what was expected``, one line per problem.
"""

from __future__ import annotations

import datetime
import difflib
import json
import re
import tomllib
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, TypeVar

from pydantic import BaseModel, ValidationError

from ..errors import InputError
from ..files import FileRefused, read_regular, resolve_in
from .root import PoundModel

M = TypeVar("M", bound=BaseModel)

MAX_MODEL_BYTES = 50_000_000


@dataclass(frozen=True)
class LoadedModel:
    """A validated model and the file it came from (record paths are relative to it)."""

    model: PoundModel
    source: Path  # as the user named it: messages quote it so
    folder: Path | None = field(default=None, compare=False)
    """The model file's folder, absolute, fixed when the model is loaded: paths in the model
    are relative to it, whatever the current directory is later."""

    def __post_init__(self) -> None:
        if self.folder is None:
            object.__setattr__(self, "folder", Path(self.source).parent.resolve())

    def resolve(self, relative: str) -> Path:
        """A path named in the model (relative to the model file, or absolute), resolved
        against the model file's folder, never against the current directory."""
        return resolve_in(self.folder, relative)


def read_document(path: str | Path) -> dict[str, Any]:
    """Parse a TOML or JSON file into a dict, with errors that name the file and the line or
    field. Only a regular file is read, and at most MAX_MODEL_BYTES + 1 bytes of it (files.py);
    a UTF-8 byte-order mark is dropped; a key given twice in one JSON object is refused, as
    TOML refuses it; a whole number of more digits than Python converts is refused naming
    its field."""
    path = Path(path)
    if path.is_dir():
        raise InputError("is a directory, expected a .toml or .json model file", file=path)
    try:
        raw = read_regular(path, MAX_MODEL_BYTES)
    except FileRefused as exc:
        raise InputError(exc.reason, file=path) from None
    suffix = path.suffix.lower()
    if suffix not in (".json", ".toml"):
        raise InputError(f"unknown file type {path.suffix!r}: expected a .toml or .json file", file=path)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputError(f"line {line}: not UTF-8 text; save the file as UTF-8", file=path) from None
    data = _parse_json(text, path) if suffix == ".json" else _parse_toml(text, path)
    if not isinstance(data, dict):
        raise InputError(f"expected a table of settings at the top, got a {type(data).__name__}", file=path)
    _refuse_markers(data, path)
    if suffix == ".toml":
        _dates_as_text(data)
    return data


def _dates_as_text(data: dict[str, Any]) -> None:
    """Replace, in place, every TOML date, date-time and time (tomllib gives datetime objects)
    by its RFC 3339 / ISO 8601 text, e.g. 1995-01-17 -> "1995-01-17": wherever pound takes
    text (a record's `date`), an unquoted TOML date is the same as the quoted one, and a
    number field says it got text (iterative, as a document may be nested deeply)."""
    stack: list[Any] = [data]
    while stack:
        node = stack.pop()
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        for key, value in list(items):
            if isinstance(value, (datetime.date, datetime.time)):  # datetime.datetime is a date
                node[key] = value.isoformat()
            elif isinstance(value, (dict, list)):
                stack.append(value)


MAX_DIGITS = 4300
"""Most digits of a whole number in an input file: Python's own limit on converting digits
to an integer (sys.get_int_max_str_digits), which guards against its quadratic cost. Every
number pound takes is below 1e308, a number of 309 digits."""


class _TooManyDigits:
    """What the parsers give for a whole number of more than MAX_DIGITS digits: a marker that
    _refuse_markers finds, so that the message names its field."""

    def __init__(self, text: str):
        self.digits = sum(c.isdigit() for c in text)


class _RepeatedKeys(dict):  # type: ignore[type-arg]
    """A JSON object in which a key appears twice: the keys, for _refuse_markers."""

    repeated: list[str]


def _json_object(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """object_pairs_hook: the object as a dict, or a _RepeatedKeys naming the repeated keys
    (JSON allows them, and the last would silently win)."""
    out = dict(pairs)
    if len(out) == len(pairs):
        return out
    seen: set[str] = set()
    marked = _RepeatedKeys(out)
    marked.repeated = [k for k, _ in pairs if k in seen or seen.add(k)]  # type: ignore[func-returns-value]
    return marked


def _json_int(text: str) -> int | _TooManyDigits:
    return int(text) if len(text) <= MAX_DIGITS else _TooManyDigits(text)


def _parse_json(text: str, path: Path) -> Any:
    try:
        return json.loads(text, object_pairs_hook=_json_object, parse_int=_json_int)
    except json.JSONDecodeError as exc:
        raise InputError(f"line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}", file=path) from None
    except RecursionError:
        raise InputError("invalid JSON: nested too deeply", file=path) from None


LONG_INTEGER = re.compile(r"(?<![\w.])([+-]?[0-9][0-9_]{%d,})(?![\w.])" % MAX_DIGITS)


def _toml_float(text: str) -> float | _TooManyDigits:
    digits = text.removesuffix(".0")  # as LONG_INTEGER wrote a whole number
    return _TooManyDigits(digits) if sum(c.isdigit() for c in digits) > MAX_DIGITS else float(text)


def _parse_toml(text: str, path: Path) -> Any:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(toml_problem(str(exc), text), file=path) from None
    except RecursionError:
        raise InputError("invalid TOML: nested too deeply", file=path) from None
    except ValueError:  # a whole number of more than MAX_DIGITS digits (int() refuses it)
        pass
    # read again with each over-long whole number written as a float, which tomllib hands to
    # parse_float: the marker it returns names the field (_refuse_markers)
    try:
        return tomllib.loads(LONG_INTEGER.sub(r"\1.0", text), parse_float=_toml_float)
    except (tomllib.TOMLDecodeError, ValueError):
        found = LONG_INTEGER.search(text)
        line = f"line {text.count(chr(10), 0, found.start()) + 1}: " if found else ""
        raise InputError(f"{line}a whole number of more than {MAX_DIGITS} digits; {_DIGITS_ADVICE}", file=path) from None


_DIGITS_ADVICE = "every number pound takes is below 1e308: write a large value with an exponent (e.g. 1e30)"


def _refuse_markers(data: Any, path: Path) -> None:
    """InputError naming the field of the first repeated JSON key or over-long whole number
    (depth first, in the file's order; iterative, as a document may be nested deeply)."""
    stack: list[tuple[tuple[Any, ...], Any]] = [((), data)]
    while stack:
        loc, node = stack.pop()
        if isinstance(node, _TooManyDigits):
            raise InputError(f"a whole number of {node.digits} digits, more than the {MAX_DIGITS} an input may "
                             f"hold; {_DIGITS_ADVICE}", file=path, field=format_loc(loc))  # fmt: skip
        if isinstance(node, _RepeatedKeys):
            keys = ", ".join(repr(k) for k in dict.fromkeys(node.repeated))
            raise InputError(f"the key {keys} appears twice in one object; give each key once (JSON would "
                             "silently keep the last)", file=path, field=format_loc(loc))  # fmt: skip
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        stack.extend(((*loc, key), value) for key, value in reversed(list(items)))


def document_kind(data: dict[str, Any]) -> str:
    """What an input document is, by its top-level keys: "sweep" (it names a `base` model),
    "record" (a record definition: components `L`/`T` and no buildings) or "model"."""
    if "base" in data and "buildings" not in data:
        return "sweep"
    if ("L" in data or "T" in data) and "buildings" not in data:
        return "record"
    return "model"


def load_model(path: str | Path) -> LoadedModel:
    """Read and validate a model file. Raises InputError naming the file and field."""
    path = Path(path)
    return validate_model(read_document(path), path)


def validate_model(data: dict[str, Any], source: str | Path) -> LoadedModel:
    """Validate an already parsed model document that came from `source`."""
    source = Path(source)
    model = validated(PoundModel, data, source, "a model", _describe)
    problems = [f"{source}: {field}: {message}" for field, message in model.cross_reference_problems()]
    if problems:
        raise InputError("\n".join(problems))
    from ..gap.placement import resolve_placements

    return LoadedModel(model=resolve_placements(model, source), source=source)


# --- messages -------------------------------------------------------------------------


def toml_problem(message: str, text: str) -> str:
    """tomllib's "Invalid value (at line 3, column 9)" as "line 3, column 9: invalid TOML:
    Invalid value", the way JSON errors read; "(at end of document)" names the last line."""
    found = re.fullmatch(r"(?s)(.*) \(at line (\d+), column (\d+)\)", message)
    if found:
        return f"line {found[2]}, column {found[3]}: invalid TOML: {found[1]}"
    found = re.fullmatch(r"(?s)(.*) \(at end of document\)", message)
    if found:
        return f"line {text.count(chr(10)) + 1}, at the end of the file: invalid TOML: {found[1]}"
    return f"invalid TOML: {message}"


def format_loc(loc: tuple[Any, ...]) -> str:
    """('buildings', 0, 'floors', 2, 'mass') -> 'buildings[0].floors[2].mass'.

    Pydantic marks an invalid dict key with a trailing '[key]': ('materials', 'C30/37',
    '[key]') -> 'materials["C30/37"]'. A key with spaces or other characters no name may hold
    is quoted too: ('analysis', 'dt ') -> 'analysis["dt "]', ('dt ',) -> '"dt "'.
    """
    out = ""
    for i, part in enumerate(loc):
        if part == "[key]":
            continue
        if isinstance(part, int):
            out += f"[{part}]"
        elif i + 1 < len(loc) and loc[i + 1] == "[key]":
            out += f"[{json.dumps(part)}]"
        elif not PLAIN_KEY.fullmatch(str(part)):  # a key of spaces or odd characters: quoted
            out += f"[{json.dumps(str(part), ensure_ascii=False)}]" if out else json.dumps(str(part), ensure_ascii=False)
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


PLAIN_KEY = re.compile(r"[A-Za-z0-9_.+\-]+")
"""Keys written as they are in a field path: those a name may hold (model.base.Name)."""


FRIENDLIER = {
    "string_pattern_mismatch": "expected a name of letters, digits and _ . + - (no spaces, no slashes)",
    "model_type": "expected a table of settings (TOML [section] or {...}, JSON object)",
    "model_attributes_type": "expected a table of settings (TOML [section] or {...}, JSON object)",
    "dict_type": "expected a table of settings (TOML [section] or {...}, JSON object)",
    "float_type": "expected a number",
    "int_type": "expected a whole number",
    "tuple_type": "expected a list [...]",
    "list_type": "expected a list [...]",
}


def validated(schema: type[M], data: dict[str, Any], source: Path, what: str,
              describe: Callable[[Path, dict[str, Any]], str]) -> M:
    """`data` validated by `schema`; InputError with one ``file: field: message`` line per
    problem (`describe` words them), or saying that the document is nested too deeply to be
    `what` (Python's recursion limit, reached by a fuzzed file of thousands of nested lists).
    A top-level "$schema" (the JSON Schema an editor checks the file against) is ignored."""
    if "$schema" in data:
        if not isinstance(data["$schema"], str):
            raise InputError('expected the URL or path of the JSON Schema the file follows, as text (pound ignores it; '
                             'editors read it)', file=source, field='"$schema"')  # fmt: skip
        data = {key: value for key, value in data.items() if key != "$schema"}
    try:
        return schema.model_validate(data)
    except ValidationError as exc:
        raise InputError("\n".join(describe(source, e) for e in exc.errors())) from None
    except RecursionError:
        raise InputError(f"nested too deeply to be {what}", file=source) from None


def describe_error(source: Path, error: dict[str, Any], root: type[BaseModel], *,
                   where: Callable[[tuple[Any, ...]], str] = format_loc,
                   text_for: Callable[[str, tuple[Any, ...]], str | None] = lambda kind, loc: None,
                   unknown_key_note: Callable[[type[BaseModel], str], str] = lambda owner, key: "") -> str:
    """``file: field: message`` for one pydantic error of a file validated by `root`: an
    unknown key with the closest valid name (or the valid ones), otherwise what was expected,
    what was given and the first sentence of the field's description (which gives its unit).
    `where` writes the location, `text_for` may word an error kind its own way, and
    `unknown_key_note` adds to an unknown key's message."""
    loc = tuple(error["loc"])
    kind = error["type"]
    if kind == "extra_forbidden":
        owner = _model_at(root, loc[:-1])
        key = str(loc[-1])
        text = f"unknown key {key!r}"
        if owner is not None:
            fields = list(owner.model_fields)
            close = difflib.get_close_matches(key, fields, n=1, cutoff=0.6)
            text += f"; did you mean {close[0]!r}?" if close else f"; valid keys: {', '.join(fields)}"
            text += unknown_key_note(owner, key)
        return f"{source}: {where(loc)}: {text}"
    msg = error["msg"].removeprefix("Value error, ").removeprefix("Assertion failed, ")
    text = "required field missing" if kind == "missing" else text_for(kind, loc) or FRIENDLIER.get(kind, msg)
    value = error.get("input")
    if kind != "missing" and "got " not in text:  # else the validator already quoted the value
        if not isinstance(value, (dict, list)):
            text += f"; got {value!r:.80}"
        elif kind.startswith(("too_", "list_")):
            text += f"; got {type(value).__name__} of {len(value)} items"
    hint = _description(root, loc)
    if hint:
        text += f" ({hint})"
    return f"{source}: {where(loc)}: {text}"


UNION_TAGS = {("elevation", "level"), ("elevation", "range")}
"""(field, tag) of the model's tagged unions: pydantic puts the tag of the branch it tried
into the error's location (obstacles[0].elevation.range[0]); messages leave it out."""


def _describe(source: Path, error: dict[str, Any]) -> str:
    """A model file's error (describe_error), located without the tags of tagged unions."""
    loc = tuple(error["loc"])
    plain = tuple(p for i, p in enumerate(loc) if not (i and (loc[i - 1], p) in UNION_TAGS))
    return describe_error(source, {**error, "loc": plain}, PoundModel)


def _description(root: type[BaseModel], loc: tuple[Any, ...]) -> str:
    """First sentence of the description of the field named last in `loc` (list indices after
    it skipped), in the file validated by `root`: it gives the field's unit."""
    for cut in range(len(loc), 0, -1):
        if isinstance(loc[cut - 1], str):
            owner = _model_at(root, loc[: cut - 1])
            if owner is not None and loc[cut - 1] in owner.model_fields:
                return _first_sentence(" ".join((owner.model_fields[loc[cut - 1]].description or "").split()))
            return ""
    return ""


def _first_sentence(text: str) -> str:
    """Up to the first full stop that ends a sentence: followed by a capital or the end (so
    not those of "e.g. 21e9" or "eqs. (6)")."""
    match = re.search(r"\.(\s+(?=[A-Z])|$)", text)
    return text[: match.start()] if match else text


def _model_at(cls: type[BaseModel], loc: tuple[Any, ...]) -> type[BaseModel] | None:
    """The pydantic model class found by following `loc` from `cls`, or None."""
    current: Any = cls
    for part in loc:
        current = _unwrap(current)
        if isinstance(part, str) and isinstance(current, type) and issubclass(current, BaseModel):
            field = current.model_fields.get(part)
            if field is None:
                return None
            current = field.annotation
        elif isinstance(part, (int, str)):
            current = _element(current)
            if current is None:
                return None
    current = _unwrap(current)
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _unwrap(tp: Any) -> Any:
    """Strip Annotated and Optional: Annotated[X | None, ...] -> X."""
    while True:
        origin = typing.get_origin(tp)
        if origin is typing.Annotated:
            tp = typing.get_args(tp)[0]
        elif origin in (typing.Union, types.UnionType):
            args = [a for a in typing.get_args(tp) if a is not type(None)]
            models = [a for a in args if isinstance(a, type) and issubclass(a, BaseModel)]
            tp = models[0] if models else args[0]
        else:
            return tp


def _element(tp: Any) -> Any:
    """The element type of list[X], tuple[X, ...] or dict[K, X]."""
    args = typing.get_args(_unwrap(tp))
    origin = typing.get_origin(_unwrap(tp))
    if origin in (list, tuple) and args:
        return args[0]
    if origin is dict and len(args) == 2:
        return args[1]
    return None
