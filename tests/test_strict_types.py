"""Every scalar field of every input file is strict, checked field by field from the schemas.

pydantic's lax mode turns "no", "off", 0 and 0.0 into False, "yes" and 1 into True, "3" into
3 and 2.0 into 2: a model with `[contact] enabled = "no"` would silently switch pounding off.
pound's input models declare every scalar strict (model/base.py: Flag, Count, Real, Text,
Name). This test is generated from the committed JSON Schemas of model, record definition and
sweep files (schemas/*.schema.json), so a field added later is covered without editing it:

- FULL documents hold an instance of every object ($defs entry) of each schema: the test fails
  if a schema gains an object they do not hold;
- for every property of every object (and the first element of a list-valued one, and of a
  list in it), each substitute of another JSON type (a string for a boolean: "no", "yes",
  "true", "0", "1"; a number for a boolean: 0, 1, 0.0; a string for a number: "3", "1e3";
  a boolean for a number or a string; a number for a string; 2.0 for a whole number) that the
  schema refuses must be refused by pound too, exit 2 style: an InputError naming that field.
"""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any, Iterator

import pytest
from jsonschema import Draft202012Validator
from pydantic import ValidationError

from pounding_cli.errors import InputError
from pounding_cli.model import read_document, validate_model
from pounding_cli.model.load import format_loc
from pounding_cli.model.record import validate_record
from pounding_cli.model.sweep import format_sweep_loc, validate_sweep

from conftest import INPUTS, ROOT

SCHEMAS = ROOT / "schemas"

SUBSTITUTES: list[Any] = ["no", "yes", "true", "false", "off", "on", "0", "1", "3", "3.5", "1e3", "auto!",
                          0, 1, 0.0, 1.0, 2.0, 3.5, True, False, ["x"], {"a": 1}]  # fmt: skip
"""Values of every JSON type that pydantic's lax mode would coerce into some scalar."""


def full_model() -> dict[str, Any]:
    """A valid model holding every object of model.schema.json: the isolated building and its
    moat, inelastic columns, explicit columns beside a grid, a building placed beside another,
    an obstacle, an inline record with every processing step."""
    doc = read_document(INPUTS / "isolated_moat.toml")
    doc["hysteresis"] = {"rc": {"yield_deflection": [0.01, 0.01], "post_yield_ratio": 0.05}}
    neighbour = doc["buildings"][1]
    neighbour["floors"][0]["columns"] = [{"name": "X1", "x": 6.0, "y": 2.0, "section": [0.3, 0.3],
                                          "material": "concrete", "hysteresis": "rc", "angle": 10.0}]  # fmt: skip
    neighbour["floors"][0]["rotational_inertia"] = 1e6
    placed = {key: copy.deepcopy(value) for key, value in neighbour.items() if key not in ("origin", "rotation")}
    placed.update(name="placed", place={"beside": "neighbour", "side": "+x", "gap": 0.1, "align": "centre",
                                        "offset": 0.0, "rotation": 0.0})  # fmt: skip
    doc["buildings"].append(placed)
    doc["buildings"][0]["isolation"]["isolators"] = [{"name": "J1", "x": 2.0, "y": 2.0, "bearing": "lrb"}]
    doc["obstacles"] = [{"name": "wall", "polygon": [[0.0, -2.0], [8.0, -2.0], [8.0, -1.0], [0.0, -1.0]],
                         "elevation": [0.0, 20.0], "material": "concrete", "k_normal": 1e9}]  # fmt: skip
    record = doc["excitation"]["record"]
    record["L"]["azimuth"] = 90.0
    record["T"]["azimuth"] = 0.0
    record["L"]["dt"] = 0.01
    record["magnitude"] = 7.1
    record["processing"] = {"demean": True, "taper": 0.05, "filter": {"freqmin": 0.1, "freqmax": 20.0},
                            "window": {"start": 0.0, "end": 30.0}, "scale": 1.0}  # fmt: skip
    doc["analysis"]["duration"] = 1.0
    return doc


def full_record() -> dict[str, Any]:
    return copy.deepcopy(full_model()["excitation"]["record"])


def full_sweep() -> dict[str, Any]:
    return {
        "title": "t", "base": "isolated_moat.toml", "set": {"analysis.duration": 0.5},
        "studies": {
            "a": {"description": "d", "mode": "grid", "parameters": {"excitation.angle": {"start": 0, "stop": 90, "step": 45}},
                  "cases": {"one": {"contact.enabled": False}}, "set": {"excitation.scale": 1.0}},
            "b": {"parameters": {"excitation.scale": {"start": 0.5, "stop": 1.0, "num": 3}}},
        },
        "summary": {"columns": {"isolated": ["C1"]}},
    }  # fmt: skip


FILES = {
    "model": (full_model, lambda doc: validate_model(doc, INPUTS / "strict.toml")),
    "record": (full_record, lambda doc: validate_record(doc, INPUTS / "strict.record.toml")),
    "sweep": (full_sweep, lambda doc: validate_sweep(doc, INPUTS / "strict.sweep.toml")),
}
WHERE = {"model": format_loc, "record": format_loc, "sweep": format_sweep_loc}
"""How each kind's messages write a field's location."""


def _schema(kind: str) -> dict[str, Any]:
    return json.loads((SCHEMAS / f"{kind}.schema.json").read_text(encoding="utf-8"))


def _def_name(schema: dict[str, Any]) -> Iterator[str]:
    """The $defs entries a property's schema refers to (directly, in anyOf, items, values)."""
    if "$ref" in schema:
        yield schema["$ref"].rsplit("/", 1)[-1]
    for key in ("anyOf", "oneOf", "allOf", "prefixItems"):
        for sub in schema.get(key, []):
            yield from _def_name(sub)
    for key in ("items", "additionalProperties"):
        if isinstance(schema.get(key), dict):
            yield from _def_name(schema[key])
    for sub in schema.get("patternProperties", {}).values():
        yield from _def_name(sub)


def objects(doc: Any, schema: dict[str, Any], root: dict[str, Any], name: str, loc=()) -> Iterator[tuple[str, tuple]]:
    """(object name, location) of every object of the document, by following the schema."""
    if not isinstance(doc, dict):
        return
    yield name, loc
    for key, value in doc.items():
        prop = schema.get("properties", {}).get(key)
        if prop is None:
            continue
        for target in dict.fromkeys(_def_name(prop)):
            sub = root["$defs"][target]
            if sub.get("type") != "object":
                continue
            if isinstance(value, dict) and "properties" in sub and set(value) <= set(sub["properties"]):
                yield from objects(value, sub, root, target, (*loc, key))
            elif isinstance(value, dict):  # a table of named objects (materials, bearings)
                for k, v in value.items():
                    yield from objects(v, sub, root, target, (*loc, key, k))
            elif isinstance(value, list):
                for i, v in enumerate(value):
                    yield from objects(v, sub, root, target, (*loc, key, i))


def _get(doc: Any, loc: tuple) -> Any:
    for part in loc:
        doc = doc[part]
    return doc


def slots(value: Any, loc: tuple) -> Iterator[tuple]:
    """The property itself, and the first element of a list in it, down to two levels."""
    yield loc
    if isinstance(value, list) and value:
        yield from slots(value[0], (*loc, 0))


def _subschema(schema: dict[str, Any], rel: tuple) -> dict[str, Any]:
    """The schema of the slot `rel` (a property, then list indices) within an object's schema."""
    sub = schema["properties"][rel[0]]
    for _ in rel[1:]:
        sub = _element(sub)
    return sub


def _element(schema: dict[str, Any]) -> dict[str, Any]:
    """The schema of a list's first element (of any list branch of anyOf/oneOf)."""
    if "prefixItems" in schema:
        return schema["prefixItems"][0]
    if "items" in schema:
        return schema["items"]
    for key in ("anyOf", "oneOf"):
        branches = [_element(b) for b in schema.get(key, []) if b.get("type") == "array"]
        if branches:
            return branches[0]
    return {}


def cases(kind: str) -> list[tuple[str, tuple, tuple, Any]]:
    """(object name, its location, the slot within it, substitute) for every substitute the
    schema refuses at every slot of every property of every object of the FULL document."""
    make, _ = FILES[kind]
    doc, root = make(), _schema(kind)
    assert Draft202012Validator(root).is_valid(doc), list(Draft202012Validator(root).iter_errors(doc))[:3]
    first: dict[str, tuple] = {}
    for name, loc in objects(doc, root, root, root.get("title", kind)):
        first.setdefault(name, loc)
    missing = sorted(set(root.get("$defs", {})) - set(first) - NOT_OBJECTS)
    assert not missing, f"FULL {kind} document holds no {missing}: add one, so that their fields are checked"
    out = []
    for name, loc in first.items():
        schema = root if loc == () else root["$defs"][name]
        obj = _get(doc, loc)
        for prop in schema.get("properties", {}):
            for rel in slots(obj.get(prop), (prop,)):
                checker = Draft202012Validator({**_subschema(schema, rel), "$defs": root.get("$defs", {})})
                out.extend((name, loc, rel, sub) for sub in SUBSTITUTES if not checker.is_valid(sub))
    return out


NOT_OBJECTS: set[str] = set()
"""$defs entries that are not objects of a document (none today)."""


def _set(doc: Any, loc: tuple, value: Any) -> None:
    _get(doc, loc[:-1])[loc[-1]] = copy.deepcopy(value)


def _classes() -> dict[str, type]:
    """The pydantic model of each schema object, by name."""
    from pounding_cli.model.base import Strict

    found: dict[str, type] = {}
    todo = [Strict]
    while todo:
        cls = todo.pop()
        found.setdefault(cls.__name__, cls)
        todo.extend(cls.__subclasses__())
    return found


ROOTS = {"model": "PoundModel", "record": "Record", "sweep": "SweepFile"}


@pytest.mark.parametrize("kind", sorted(FILES))
def test_every_field_refuses_other_types(kind: str) -> None:
    """Each substitute the schema refuses, set in its object of the FULL document, is refused
    by that object's model with an error at that slot (or in it: a list's element)."""
    make, validate = FILES[kind]
    validate(make())  # the FULL document itself is valid, as pound reads it
    classes = _classes()
    found = cases(kind)
    assert len(found) > (1000 if kind == "model" else 100), len(found)
    doc = make()
    wrong = []
    for name, loc, rel, sub in found:
        cls = classes[ROOTS[kind] if loc == () else name]
        obj = copy.deepcopy(_get(doc, loc))
        _set(obj, rel, sub)
        try:
            cls.model_validate(obj)
        except ValidationError as exc:
            locs = [_plain(tuple(e["loc"])) for e in exc.errors()]
            if not any(l[: len(rel)] == rel or (rel[0] not in _get(doc, loc) and l[:1] == rel[:1]) for l in locs):
                wrong.append(f"{format_loc(loc + rel)} = {sub!r} ({name}): refused at {locs}")
            continue
        wrong.append(f"{format_loc(loc + rel)} = {sub!r} ({name}): accepted, the schema refuses it")
    assert not wrong, "\n".join(wrong[:30])


def _plain(loc: tuple) -> tuple:
    """A pydantic location without the steps through unions and validators."""
    from pounding_cli.model.load import UNION_TAGS
    from pounding_cli.model.sweep import _plain_loc

    loc = _plain_loc(loc)
    return tuple(p for i, p in enumerate(loc) if not (i and (loc[i - 1], p) in UNION_TAGS)
                 and not (isinstance(p, str) and p in ("list", "range", "linspace")))


@pytest.mark.parametrize("value", ["no", "yes", "false", 0, 1, 0.0])
def test_contact_enabled_is_a_boolean(value: Any) -> None:
    """The issue's case: `enabled = "no"` or `enabled = 0` switched pounding off, exit 0."""
    doc = full_model()
    doc["contact"]["enabled"] = value
    with pytest.raises(InputError, match=r"contact\.enabled: Input should be a valid boolean"):
        validate_model(doc, INPUTS / "strict.toml")


def test_a_sweep_cannot_set_a_boolean_to_a_string(tmp_path: Path) -> None:
    """A sweep's values are checked as the model's fields: "no" for contact.enabled is refused."""
    from pounding_cli.sweep import run_sweep

    doc = {"base": str(INPUTS / "paper_wide_gap.toml"), "parameters": {"contact.enabled": ["no", True]}}
    with pytest.raises(InputError, match=r"contact\.enabled"):
        run_sweep(validate_sweep(doc, tmp_path / "s.sweep.toml"), dry_run=True)
