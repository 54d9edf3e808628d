"""The description of a record that ``pound record`` prints, as a document with a JSON Schema.

:func:`describe_record` is the Python API behind the command: it returns the JSON document
of ``pound record --json`` (validated by ``schemas/record-summary.schema.json``, written by
``pound schema`` from :class:`RecordSummary`). Intensity measures: :mod:`.metrics`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict

from pounding_cli.records.inspect import RecordData, open_record
from pounding_cli.records.metrics import G, metrics

INTEGRATION = (
    "velocity and displacement integrate the acceleration exactly as linear between samples, "
    "from rest, after the record's processing and with no further baseline correction; "
    "peaks are taken at the samples"
)


class _Output(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)


class Metadata(_Output):
    """What the record is: from its definition, or from a record file's header."""

    name: str
    """Label of the record (a record file: its file name)."""
    event: str
    """The earthquake."""
    date: str
    """Date (or origin time) of the event, as text."""
    magnitude: float | None
    """Magnitude of the event, dimensionless."""
    station: str
    """Recording station."""
    network: str
    """Network or agency."""
    source: str
    """Where the record comes from."""
    notes: str
    """Anything else."""


class ComponentSummary(_Output):
    """One component: where it comes from, and its intensity measures (SI units)."""

    name: str
    """"L" or "T" for a record definition; the trace id for a record file."""
    file: str
    """The file the component was read from."""
    trace_id: str | None
    """obspy trace id (NET.STA.LOC.CHA); null for plain text."""
    azimuth_deg: float | None
    """Direction of positive motion, degrees clockwise from north: the definition's
    azimuth, or the file's for a record file; null if not known."""
    units_in_file: str | None
    """Units of the values in the file, as read (converted to m/s²)."""
    header: dict[str, Any]
    """What the file's header says (station, event, azimuth, ...)."""
    dt_s: float
    """Sample interval, s."""
    points: int
    """Number of samples."""
    duration_s: float
    """Time from the first to the last sample, s."""
    pga_m_s2: float
    """Peak ground acceleration, m/s²."""
    pga_g: float
    """Peak ground acceleration, g (9.80665 m/s²)."""
    pga_time_s: float
    """Time of the PGA, s from the first sample."""
    pgv_m_s: float
    """Peak ground velocity, m/s."""
    pgv_time_s: float
    """Time of the PGV, s."""
    pgd_m: float
    """Peak ground displacement, m."""
    pgd_time_s: float
    """Time of the PGD, s."""
    arias_intensity_m_s: float
    """Arias intensity π/(2g)∫a²dt, m/s."""
    significant_duration_s: float
    """5-95 % significant duration D5-95 = t95 − t5, s."""
    t5_s: float
    """Time at which 5 % of the Arias intensity is reached, s."""
    t95_s: float
    """Time at which 95 % of the Arias intensity is reached, s."""


class RecordSummary(_Output):
    """The document ``pound record --json`` prints."""

    file: str
    """The record definition or record file described."""
    kind: Literal["definition", "record file"]
    """What the file is."""
    metadata: Metadata
    """What the record is."""
    processing: list[str]
    """The definition's processing steps, in the order applied; empty for a record file."""
    scale_factor: float
    """Factor of the definition's scale or target_pga, dimensionless (1 if none)."""
    notes: list[str]
    """What pound did that changes the record: resampling, cutting to a common span, scaling."""
    integration: str
    """How PGV and PGD were obtained."""
    components: list[ComponentSummary]
    """Each component, in order (L, T; or the file's traces)."""


def summarise(data: RecordData) -> RecordSummary:
    """The intensity measures of every component of `data`, with its metadata."""
    components = []
    for c in data.components:
        m = metrics(c.acceleration, c.dt)
        components.append(ComponentSummary(
            name=c.name, file=c.file, trace_id=c.read.trace_id, azimuth_deg=c.azimuth,
            units_in_file=c.read.units_in_file, header=c.read.header, dt_s=m.dt, points=m.points,
            duration_s=m.duration, pga_m_s2=m.pga, pga_g=m.pga / G, pga_time_s=m.pga_time,
            pgv_m_s=m.pgv, pgv_time_s=m.pgv_time, pgd_m=m.pgd, pgd_time_s=m.pgd_time,
            arias_intensity_m_s=m.arias_intensity, significant_duration_s=m.significant_duration,
            t5_s=m.t5, t95_s=m.t95,
        ))  # fmt: skip
    return RecordSummary(
        file=str(data.source), kind=data.kind, metadata=Metadata(**data.metadata),
        processing=data.processing, scale_factor=data.factor, notes=data.notes,
        integration=INTEGRATION, components=components,
    )  # fmt: skip


def describe_record(
    path: str | Path,
    *,
    trace: str | None = None,
    units: str | None = None,
    format: str = "auto",
    dt: float | None = None,
) -> dict[str, Any]:
    """The ``pound record --json`` document of a record definition or record file."""
    data = open_record(path, trace=trace, units=units, format=format, dt=dt)
    return summarise(data).model_dump(mode="json")


def summary_schema() -> dict[str, Any]:
    """JSON Schema of :class:`RecordSummary` (the ``pound record --json`` document)."""
    return RecordSummary.model_json_schema(mode="serialization")
