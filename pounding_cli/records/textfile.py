"""File access shared by pound's text-format readers (AT2, CSMIP/COSMOS): a path or any file
object obspy passes (open binary or text files, BytesIO), detection reads that restore the
position, and text decoding that never fails."""

from __future__ import annotations

import re
from pathlib import PurePath
from typing import Any

from ..files import MAX_RECORD_BYTES, FileRefused, read_regular, read_start

BINARY = re.compile(r"[\x00-\x08\x0e-\x1f\x7f]")  # control characters other than \t \n \v \f \r


def source_name(source: Any) -> str:
    """How to name ``source`` in messages: its path, a file object's name, or a placeholder."""
    if isinstance(source, (str, PurePath)):
        return str(source)
    name = getattr(source, "name", None)
    return str(name) if isinstance(name, (str, PurePath)) else f"<{type(source).__name__}>"


def decode(raw: bytes | str) -> str:
    """Text of the file: UTF-8 (a BOM is dropped), else Latin-1, which never fails."""
    if isinstance(raw, str):
        return raw.lstrip("\ufeff")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def read_head(source: Any, size: int) -> str | None:
    """The first ``size`` bytes as text, restoring a file object's position; None if unreadable."""
    if isinstance(source, (str, PurePath)):
        try:
            return decode(read_start(source, size))
        except FileRefused:
            return None
    if not (hasattr(source, "read") and hasattr(source, "seek") and hasattr(source, "tell")):
        return None
    position = source.tell()
    try:
        return decode(source.read(size))
    finally:
        source.seek(position, 0)


def read_all(source: Any, name: str, kind: str) -> str:
    """The whole file (path or file object, read from its current position) as text."""
    if isinstance(source, (str, PurePath)):
        try:
            raw = read_regular(source, MAX_RECORD_BYTES)
        except FileRefused as exc:
            raise ValueError(f"{name}: {exc.reason}") from None
    elif hasattr(source, "read"):
        raw = source.read()
    else:
        raise TypeError(f"{name}: expected a path or a file object, got {type(source).__name__}")
    if not isinstance(raw, (bytes, bytearray, str)):
        raise TypeError(f"{name}: reading the file object gave {type(raw).__name__}, "
                        "not bytes or str")
    text = decode(bytes(raw) if isinstance(raw, bytearray) else raw)
    binary = BINARY.search(text)
    if binary:
        line = text.count("\n", 0, binary.start()) + 1
        raise ValueError(f"{name}: line {line}: control character {binary.group()!r}; "
                         f"not {kind}")
    return text
