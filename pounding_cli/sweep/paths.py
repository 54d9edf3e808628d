"""Dotted paths into a model document: what they select, and setting values through them.

A path (parsed by :func:`pounding_cli.model.sweep.parse_path`) is walked step by step from
the top of the document as written in the model file (a dict of TOML tables and lists):

- a key on a table selects that entry; the last key may be one the document lacks (an
  optional field left at its default), and a missing table before it is created;
- a key on a list of named tables (buildings, obstacles, columns) selects the item whose
  ``name`` is the key: ``buildings.left`` is the building named "left";
- ``[i]`` selects item i of a list (0-based; negative counts from the end);
- ``[*]`` selects every item of a list, or every entry of a table.

Each selected place is a *location*: the tuple of keys and list indices from the top,
e.g. ``('buildings', 0, 'floors', 0, 'eccentricity')``, which is also how validation errors
name fields (``buildings[0].floors[0].eccentricity``).
"""

from __future__ import annotations

import copy
from typing import Any

from ..model.load import format_loc
from ..model.sweep import Index, Step, path_text

Location = tuple[str | int, ...]


class PathError(ValueError):
    """A path does not fit the document; the message says where and why."""


def assign(document: dict[str, Any], steps: tuple[Step, ...], value: Any) -> list[Location]:
    """Set `value` (a fresh copy at each place) at every location `steps` selects in
    `document`, in place; return the locations."""
    *head, last = steps
    places = _walk([((), document)], tuple(head), steps, create=True)
    written = []
    for where, node in places:
        for slot in _slots(node, last, where, steps):
            node[slot] = copy.deepcopy(value)
            written.append(where + (slot,))
    return written


def select(document: dict[str, Any], steps: tuple[Step, ...]) -> list[tuple[Location, Any]]:
    """(location, value) of every place `steps` selects; raises PathError if one is missing."""
    return _walk([((), document)], steps, steps, create=False)


def location_text(location: Location) -> str:
    """('buildings', 0, 'floors', 0, 'eccentricity') → 'buildings[0].floors[0].eccentricity'."""
    return format_loc(location)


def overlaps(a: Location, b: Location) -> bool:
    """True if one location lies within (or is) the other."""
    n = min(len(a), len(b))
    return a[:n] == b[:n]


def _walk(
    places: list[tuple[Location, Any]], steps: tuple[Step, ...], whole: tuple[Step, ...], create: bool
) -> list[tuple[Location, Any]]:
    for k, step in enumerate(steps):
        following = steps[k + 1] if k + 1 < len(steps) else None
        nxt = []
        for where, node in places:
            for slot in _slots(node, step, where, whole):
                if create and isinstance(node, dict) and slot not in node:
                    node[slot] = [] if isinstance(following, Index) else {}
                if isinstance(node, dict) and slot not in node:
                    raise PathError(_missing(whole, where, slot, node))
                nxt.append((where + (slot,), node[slot]))
        places = nxt
    return places


def _slots(node: Any, step: Step, where: Location, whole: tuple[Step, ...]) -> list[str | int]:
    """The keys or indices of `node` that `step` selects."""
    at = location_text(where) if where else "the model's top level"
    if isinstance(step, Index):
        if isinstance(node, list):
            if step.i is None:
                if not node:
                    raise PathError(f"{path_text(whole)}: {at} is an empty list, so [*] selects nothing")
                return list(range(len(node)))
            if not -len(node) <= step.i < len(node):
                raise PathError(f"{path_text(whole)}: {at} has {len(node)} items (indices 0 to {len(node) - 1}), "
                                f"so [{step.i}] selects nothing")  # fmt: skip
            return [step.i % len(node)]
        if isinstance(node, dict):
            if step.i is None:
                if not node:
                    raise PathError(f"{path_text(whole)}: {at} is an empty table, so [*] selects nothing")
                return list(node)
            raise PathError(f"{path_text(whole)}: {at} is a table, not a list: select its entries by key, "
                            f"e.g. {at}.{next(iter(node), 'key')}")  # fmt: skip
        raise PathError(f"{path_text(whole)}: {at} is {_kind(node)}, not a list")
    if isinstance(node, dict):
        return [step]  # a missing key: created by assign, or refused by _walk
    if isinstance(node, list):
        return [_named_item(node, step, where, whole, at)]
    raise PathError(f"{path_text(whole)}: {at} is {_kind(node)}, so it has no entry {step!r}")


def _named_item(node: list[Any], name: str, where: Location, whole: tuple[Step, ...], at: str) -> int:
    """Index of the item of a list of named tables whose name is `name`."""
    names = [item.get("name") if isinstance(item, dict) else None for item in node]
    if not any(isinstance(n, str) for n in names):
        raise PathError(f"{path_text(whole)}: {at} is a list of unnamed items: select them with [i] "
                        f"(0 to {len(node) - 1}) or [*]")  # fmt: skip
    if name not in names:
        known = ", ".join(str(n) for n in names if isinstance(n, str))
        raise PathError(f"{path_text(whole)}: {at} has no item named {name!r}; names: {known}")
    if names.count(name) > 1:
        raise PathError(f"{path_text(whole)}: {at} has several items named {name!r}")
    return names.index(name)


def _missing(whole: tuple[Step, ...], where: Location, key: str, node: dict[str, Any]) -> str:
    at = location_text(where) if where else "the model's top level"
    keys = ", ".join(node) or "none"
    return f"{path_text(whole)}: {at} has no entry {key!r} (its entries: {keys})"


def _kind(node: Any) -> str:
    return f"a value ({node!r:.40})" if not isinstance(node, (dict, list)) else type(node).__name__
