"""A record definition made into samples: read, process, put on one time axis, scale.

:func:`record_motion` reads every component the record gives (not only those a model
applies: a record is one thing, and switching T off must leave L as it was, which is how the
paper compares one and two components), processes each (:mod:`.process`, steps 1-5), then:

6. **common Δt**: if the components' intervals differ, each is resampled linearly to the
   smallest (``processing.resample = true``, the default, with a note). The ground motion
   pound applies is linear between samples, so resampling onto a finer grid that contains
   the coarse samples changes nothing, and onto any finer grid changes only where the
   samples fall. ``resample = false`` refuses the record instead;
7. **common span**: components of unequal length are cut to the shortest, with a note;
8. **scaling**: by ``scale``, or by the one factor that makes the larger PGA of the
   components equal ``target_pga`` (g).

Errors are :class:`~pounding_cli.errors.InputError` naming the file that defines the record
and the field (see :class:`RecordOrigin`).
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pounding_cli.errors import InputError, RecordReadError
from pounding_cli.files import MAX_RECORD_BYTES, FileRefused, read_regular, resolve_in
from pounding_cli.model.record import Record, RecordComponent
from pounding_cli.records.process import ProcessingError, process
from pounding_cli.records.read import UNIT_FACTORS, Accelerogram, read_accelerogram

G = UNIT_FACTORS["g"]
"""Standard gravity, m/s² per g."""

DT_REL_TOL = 1e-9
"""Sample intervals closer than this (relative) are the same interval."""


@dataclass(frozen=True)
class RecordOrigin:
    """Where a record is defined, so that errors name the right file and field.

    ``file`` holds the record's keys: the model file (``prefix`` "excitation.record.") or a
    record definition file (``prefix`` ""). ``referrer`` is (model file, its field) when a
    model names the record definition file, so its errors name both. ``folder`` is where the
    component files are looked up.
    """

    file: Path
    prefix: str = ""
    referrer: tuple[Path, str] | None = None
    base: Path | None = None
    """The folder component files are relative to (absolute), if not the file's own folder
    as it is when the origin is made: a model's folder as it was when the model was loaded."""

    @property
    def folder(self) -> Path:
        return self.base if self.base is not None else self.file.parent.resolve()

    def error(self, field: str, message: str) -> InputError:
        """An InputError about `field` of the record (relative to the record's keys)."""
        if self.referrer is None:
            return InputError(message, file=self.file, field=self.prefix + field)
        model, key = self.referrer
        return InputError(f"{self.file}: {field}: {message}", file=model, field=key)

    def resolve(self, relative: str) -> Path:
        """A component's file, relative to the file that defines the record."""
        return resolve_in(self.folder, relative)


@dataclass(frozen=True)
class RecordMotion:
    """The record's components on one time axis, processed and scaled (m/s²).

    ``acceleration[name][i]`` is the ground acceleration of component ``name`` at ``i·dt``;
    ``read`` holds the components as read from their files (before processing), ``factor``
    the scaling applied in step 8, ``notes`` what was done that the user should know.
    """

    record: Record
    origin: RecordOrigin
    dt: float
    acceleration: dict[str, np.ndarray]
    read: dict[str, Accelerogram]
    factor: float = 1.0
    notes: tuple[str, ...] = ()
    file_sha256: dict[str, str] = field(default_factory=dict)

    @property
    def points(self) -> int:
        return next(iter(self.acceleration.values())).size

    @property
    def duration(self) -> float:
        """Time of the last sample, s."""
        return (self.points - 1) * self.dt


def record_motion(record: Record, origin: RecordOrigin) -> RecordMotion:
    """Read, process, resample, cut and scale every component of `record` (steps 1-8)."""
    read, processed, hashes = {}, {}, {}
    for name, spec in record.components().items():
        read[name], hashes[name] = _read_component(name, spec, origin)
        try:
            processed[name] = process(read[name], record.processing)
        except ProcessingError as exc:
            raise origin.error(f"processing.{exc.field}", str(exc)) from None
    dt, notes = _common_dt(processed, record, origin)
    samples, span_note = _common_span(processed, dt)
    notes += span_note
    factor, scale_notes = _scale_factor(samples, record, origin)
    acceleration = {name: values * factor if factor != 1.0 else values for name, values in samples.items()}
    return RecordMotion(record, origin, dt, acceleration, read, factor, tuple(notes + scale_notes), hashes)


def _read_component(name: str, spec: RecordComponent, origin: RecordOrigin) -> tuple[Accelerogram, str]:
    """One component as read from its file (m/s²), and the file's sha256."""
    path = origin.resolve(spec.file)
    given = Path(os.path.normpath(origin.folder / spec.file))  # as the definition names it (no links followed)
    link = f" ({given} is a link to {path})" if path != given else ""
    try:
        record = read_accelerogram(path, trace=spec.trace, units=spec.units, format=spec.format, dt=spec.dt)
        digest = hashlib.sha256(read_regular(path, MAX_RECORD_BYTES)).hexdigest()
    except FileRefused as exc:
        raise origin.error(f"{name}.file", f"{path}: {exc.reason}{link}") from None
    except RecordReadError as exc:
        raise origin.error(f"{name}.{exc.field}", f"{exc}{link}") from None
    return record, digest


def _common_dt(components: dict[str, Accelerogram], record: Record, origin: RecordOrigin) -> tuple[float, list[str]]:
    """Step 6's target interval (the smallest), or an error if they differ and resampling is off."""
    dt = min(c.dt for c in components.values())
    if all(abs(c.dt - dt) <= DT_REL_TOL * dt for c in components.values()):
        return dt, []
    intervals = ", ".join(f"{n}: {c.dt:g} s" for n, c in components.items())
    if not record.processing.resample:
        raise origin.error(
            "processing.resample",
            f"the components have different sample intervals ({intervals}) and resample = false; "
            "allow resampling (resample = true: linear, to the smaller interval) or give components "
            "sampled alike",
        )
    return dt, [f"components have different sample intervals ({intervals}); resampled linearly to {dt:g} s"]


def _common_span(components: dict[str, Accelerogram], dt: float) -> tuple[dict[str, np.ndarray], list[str]]:
    """Steps 6-7: each component at interval `dt` over the span they all cover."""
    span = min(c.duration for c in components.values())
    n = int(np.floor(span / dt + 1e-9)) + 1
    out = {}
    for name, comp in components.items():
        if abs(comp.dt - dt) <= DT_REL_TOL * dt:
            out[name] = comp.acceleration[:n]
        else:
            out[name] = np.interp(np.arange(n) * dt, np.arange(comp.acceleration.size) * comp.dt, comp.acceleration)
    notes = []
    if max(c.duration for c in components.values()) - span > 0.5 * dt:
        lengths = ", ".join(f"{name}: {c.duration:g} s" for name, c in components.items())
        notes.append(f"components have different lengths ({lengths}); cut to the common {span:g} s")
    return out, notes


def _scale_factor(samples: dict[str, np.ndarray], record: Record, origin: RecordOrigin) -> tuple[float, list[str]]:
    """Step 8: the factor of `scale`, or the one that brings the larger PGA to `target_pga`."""
    p = record.processing
    if p.scale is not None:
        return p.scale, []
    if p.target_pga is None:
        return 1.0, []
    peaks = {name: float(np.abs(values).max()) for name, values in samples.items()}
    largest = max(peaks.values())
    if largest == 0.0:
        raise origin.error(
            "processing.target_pga",
            "the record's components are zero throughout, so no factor brings their PGA to "
            f"{p.target_pga:g} g",
        )
    factor = p.target_pga * G / largest
    which = max(peaks, key=peaks.get)
    return factor, [f"scaled by {factor:.6g} so that the PGA of {which} ({largest / G:.4g} g) becomes {p.target_pga:g} g"]
