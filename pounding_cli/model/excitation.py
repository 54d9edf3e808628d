"""Ground excitation: a two-component record applied at an angle (paper eq. 2)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BeforeValidator, Field, WithJsonSchema, model_validator

from .base import Positive, Real, Strict

Units = Literal["g", "m/s2", "cm/s2", "gal"]


def _index_as_text(value: object) -> object:
    return str(value) if isinstance(value, int) and not isinstance(value, bool) and value >= 0 else value


TraceName = Annotated[
    str,
    Field(min_length=1, max_length=64),
    BeforeValidator(_index_as_text),
    WithJsonSchema({"anyOf": [{"type": "string", "minLength": 1, "maxLength": 64}, {"type": "integer", "minimum": 0}]}),
]


class RecordComponent(Strict):
    """One horizontal component of a ground-motion record."""

    file: Annotated[str, Field(min_length=1)]
    """Path of the record file, relative to the model file. Any format obspy reads
    (MiniSEED, SAC, K-NET, …) or plain text (one value per line with `dt`, or two columns
    time [s] and acceleration)."""

    trace: TraceName | None = None
    """Which trace of a multi-trace file: a SEED id NET.STA.LOC.CHA, a channel code (HNE)
    or a 0-based index (0). May be left out when the file holds one trace."""

    units: Units
    """Units of the values in the file: "g", "m/s2", "cm/s2" or "gal"."""

    format: str = "auto"
    """File format: "auto" (obspy detects it, plain text as the fallback), "text", or an
    obspy format name such as "MSEED" or "SAC"."""

    dt: Positive | None = None
    """Sample interval, s; needed for plain text with one value per line. If given for
    another file, it must agree with the file's own interval."""


class Record(Strict):
    """A two-component ground-motion record."""

    name: str = ""
    """A label for the record (event, station), printed by validate and stored with the results."""

    L: RecordComponent | None = None
    """Component L, applied along the excitation angle θ from the global X axis."""

    T: RecordComponent | None = None
    """Component T, applied along θ + 90°."""


class Excitation(Strict):
    """Ground motion: I_L = I_X cos θ + I_Y sin θ, I_T = −I_X sin θ + I_Y cos θ (eq. 2)."""

    record: Record
    """The record whose components are applied."""

    angle: Real = 0.0
    """Excitation angle θ: direction of component L from the global X axis, degrees,
    counter-clockwise."""

    components: Annotated[list[Literal["L", "T"]], Field(min_length=1, max_length=2)] = ["L", "T"]
    """Which components shake the buildings: ["L", "T"], ["L"] or ["T"]."""

    scale: Annotated[Positive, Field(le=1000.0)] = 1.0
    """Factor applied to both components, dimensionless."""

    @model_validator(mode="after")
    def _components_defined(self) -> "Excitation":
        if len(set(self.components)) != len(self.components):
            raise ValueError(f"components repeat: {self.components}")
        missing = [c for c in self.components if getattr(self.record, c) is None]
        if missing:
            raise ValueError(
                f"components lists {', '.join(missing)} but record.{missing[0]} is not given"
            )
        return self
