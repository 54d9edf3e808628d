"""What ``pound record`` looks at: a record definition made into samples, or a record file as read.

- A **record definition** (``.toml`` / ``.json``): its components L and T after the
  definition's processing, common Δt, common span and scaling — exactly what a model that
  names it applies before the excitation angle and the model's ``scale``.
- A **record file** in any format pound reads: every trace of it (or the one ``trace``
  names) as read, unprocessed, in m/s². Files that do not declare their units (MiniSEED,
  SAC, plain text) need ``units``; plain text with one value per line needs ``dt``.

Every problem is an :class:`~pounding_cli.errors.InputError` naming the file and the field
(for a definition) or the option (``--units``, ``--trace``, ``--dt``, ``--format``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from pounding_cli.errors import InputError, RecordReadError
from pounding_cli.model.record import RECORD_SUFFIXES, Record, load_record
from pounding_cli.records.combine import RecordOrigin, record_motion
from pounding_cli.records.read import Accelerogram, read_accelerogram, read_accelerograms


@dataclass(frozen=True)
class Component:
    """One component as analysed: `acceleration` (m/s²) every `dt` s from its first sample."""

    name: str  # "L", "T", or the trace id in a record file
    dt: float
    acceleration: np.ndarray
    read: Accelerogram  # as read from its file, before processing
    file: str
    azimuth: float | None  # degrees clockwise from north: the definition's, or the file's

    @property
    def time(self) -> np.ndarray:
        """Times of the samples, s from the first."""
        return np.arange(self.acceleration.size) * self.dt


@dataclass(frozen=True)
class RecordData:
    """A record ready to describe: where it came from, its metadata and its components."""

    source: Path
    kind: Literal["definition", "record file"]
    metadata: dict[str, Any]  # METADATA keys: the definition's, or what the file's header says
    components: list[Component]
    processing: list[str] = field(default_factory=list)  # the definition's steps, in words
    factor: float = 1.0  # the definition's scale or target_pga factor
    notes: list[str] = field(default_factory=list)


METADATA = ("name", "event", "date", "magnitude", "station", "network", "source", "notes")
"""The descriptive fields of a record definition."""


def open_record(
    path: str | Path,
    *,
    trace: str | None = None,
    units: str | None = None,
    format: str = "auto",
    dt: float | None = None,
) -> RecordData:
    """A record definition (by its suffix .toml/.json) or a record file, ready to describe."""
    path = Path(path)
    if path.suffix.lower() in RECORD_SUFFIXES:
        given = [f"--{k}" for k, v in (("trace", trace), ("units", units), ("dt", dt)) if v is not None]
        if format != "auto":
            given.append("--format")
        if given:
            raise InputError(
                f"{', '.join(given)} apply to record files; a record definition says these for "
                "each component (L, T) itself",
                file=path,
            )
        return _definition(path)
    return _record_file(path, trace, units, format, dt)


def _definition(path: Path) -> RecordData:
    return describe_definition(load_record(path), path)


def describe_definition(record: Record, path: Path) -> RecordData:
    """A validated record definition read from `path` (its files relative to it), ready to
    describe: components after its processing and scaling."""
    motion = record_motion(record, RecordOrigin(path))
    components = [
        Component(name, motion.dt, values, motion.read[name], str(getattr(record, name).file),
                  getattr(record, name).azimuth)
        for name, values in motion.acceleration.items()
    ]  # fmt: skip
    metadata = {key: getattr(record, key) for key in METADATA}
    return RecordData(path, "definition", metadata, components, record.processing.steps(), motion.factor,
                      list(motion.notes))


def _record_file(path: Path, trace: str | None, units: str | None, format: str, dt: float | None) -> RecordData:
    try:
        if trace is None:
            read = read_accelerograms(path, units=units, format=format, dt=dt)
        else:
            read = [read_accelerogram(path, trace=trace, units=units, format=format, dt=dt)]
    except RecordReadError as exc:
        option = "" if exc.field == "file" else f"--{exc.field}"
        raise InputError(str(exc), field=option or None) from None
    components = [
        Component(r.trace_id or "0", r.dt, r.acceleration, r, str(path), r.header.get("azimuth")) for r in read
    ]
    return RecordData(path, "record file", _metadata_of_file(path, read[0]), components)


def _metadata_of_file(path: Path, first: Accelerogram) -> dict[str, Any]:
    """The record's metadata as its file's header gives it (empty where it says nothing)."""
    h = first.header
    station = ", ".join(str(v) for v in dict.fromkeys((h.get("station"), h.get("station_name"))) if v)
    return {
        "name": path.name,
        "event": str(h.get("event", "")),
        "date": str(h.get("date") or h.get("origin_time") or ""),
        "magnitude": h.get("magnitude"),
        "station": station,
        "network": str(h.get("network", "")),
        "source": str(h.get("title", "")),
        "notes": "uncorrected (COSMOS V1): process before use" if h.get("processing") == "uncorrected" else "",
    }
