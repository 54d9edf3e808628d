"""A ground-motion record definition: metadata, the horizontal components L and T, and how
to process and scale them.

A record is written inline in a model (``[excitation.record]``) or in a file of its own
(``kobe.record.toml`` or ``.json``, the same keys at its top level) that a model names by
path: ``excitation.record = "kobe.record.toml"``. Component files are relative to the file
that defines the record.

Direction of a component (docs/theory.md §5): ``azimuth`` α is in degrees clockwise from
north, with the model's global X axis pointing east and Y north, so a component of azimuth
α points along (sin α, cos α) in (X, Y) before the excitation angle θ turns the whole record
counter-clockwise. Without azimuths, L points along θ and T along θ + 90°.
"""

from __future__ import annotations

import datetime
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, WithJsonSchema, model_validator
from pydantic import Strict as StrictType

from .base import Flag, Positive, Real, SampleInterval, Strict

Units = Literal["g", "m/s2", "cm/s2", "gal"]

Azimuth = Annotated[Real, Field(ge=0.0, le=360.0)]
"""Degrees clockwise from north, 0 to 360 (360 is north, as COSMOS headers write it)."""


def _index_as_text(value: object) -> object:
    return str(value) if isinstance(value, int) and not isinstance(value, bool) and value >= 0 else value


def _date_as_text(value: object) -> object:
    return value.isoformat() if isinstance(value, (datetime.date, datetime.datetime)) else value


TraceName = Annotated[
    str,
    StrictType(),
    Field(min_length=1, max_length=64),
    BeforeValidator(_index_as_text),
    WithJsonSchema({"anyOf": [{"type": "string", "minLength": 1, "maxLength": 64}, {"type": "integer", "minimum": 0}]}),
]

Text = Annotated[str, StrictType(), Field(max_length=2000)]

DateText = Annotated[
    str,
    StrictType(),
    Field(max_length=64),
    BeforeValidator(_date_as_text),
    # text; the formats let an editor (taplo) take an unquoted TOML date or date-time here
    WithJsonSchema({"anyOf": [{"type": "string", "format": "date"}, {"type": "string", "format": "date-time"},
                              {"type": "string", "maxLength": 64}]}),  # fmt: skip
]


class RecordComponent(Strict):
    """One horizontal component of a ground-motion record."""

    file: Annotated[str, StrictType(), Field(min_length=1)]
    """Path of the record file, relative to the file that defines the record (the model
    file, or the record definition file). Any format obspy reads (MiniSEED, SAC, K-NET, …),
    PEER NGA .AT2, CSMIP/COSMOS V1/V2 text, or plain text (one value per line with `dt`, or
    two columns time [s] and acceleration)."""

    trace: TraceName | None = None
    """Which trace of a multi-trace file: a SEED id NET.STA.LOC.CHA, a channel code (HNE)
    or a 0-based index (0). May be left out when the file holds one trace."""

    units: Units
    """Units of the values in the file: "g", "m/s2", "cm/s2" or "gal". Files that declare
    their units (AT2, COSMOS) are converted by their reader: write their own units or "m/s2"."""

    format: Annotated[str, StrictType()] = "auto"
    """File format: "auto" (obspy detects it, plain text as the fallback), "text", or an
    obspy format name such as "MSEED", "SAC", "AT2" or "COSMOS"."""

    dt: SampleInterval | None = None
    """Sample interval, s (10⁻⁶ to 1); needed for plain text with one value per line. If given for
    another file, it must agree with the file's own interval."""

    azimuth: Azimuth | None = None
    """Direction of positive motion, degrees clockwise from north (90 = east, 360 or 0 =
    north), with the model's X axis east and Y north; θ then turns the record. Give it for
    both components or for neither (then L is along θ and T along θ + 90°)."""


class Filter(Strict):
    """A Butterworth filter (obspy's bandpass, highpass or lowpass)."""

    freqmin: Positive | None = None
    """Lower corner frequency, Hz; alone it makes a high-pass filter."""

    freqmax: Positive | None = None
    """Upper corner frequency, Hz, below the Nyquist frequency 1/(2Δt); alone it makes a
    low-pass filter."""

    corners: Annotated[int, StrictType(), Field(ge=1, le=10)] = 4
    """Filter order (number of poles), 1 to 10."""

    zerophase: Flag = True
    """Filter forwards and backwards (no phase shift; the effective order doubles)."""

    @model_validator(mode="after")
    def _corners_given(self) -> "Filter":
        if self.freqmin is None and self.freqmax is None:
            raise ValueError("give freqmin (Hz), freqmax (Hz) or both")
        if self.freqmin is not None and self.freqmax is not None and self.freqmin >= self.freqmax:
            raise ValueError(f"freqmin = {self.freqmin:g} Hz must be below freqmax = {self.freqmax:g} Hz")
        return self


class Window(Strict):
    """A time window, in s from each component's first sample."""

    start: Annotated[Real, Field(ge=0.0)] = 0.0
    """Start of the window, s after the first sample (the nearest sample is kept)."""

    end: Positive | None = None
    """End of the window, s after the first sample (the nearest sample is kept); default:
    the end of the record."""

    @model_validator(mode="after")
    def _ordered(self) -> "Window":
        if self.end is not None and self.end <= self.start:
            raise ValueError(f"end = {self.end:g} s must be after start = {self.start:g} s")
        return self


class Processing(Strict):
    """Processing of both components, in this order: demean, detrend, taper, filter, window
    (each by obspy on each component), then resampling to a common Δt, cutting to the common
    span, and scaling (scale or target_pga)."""

    demean: Flag = False
    """Remove the mean (obspy detrend "demean")."""

    detrend: Flag = False
    """Remove a least-squares straight line (obspy detrend "linear")."""

    taper: Annotated[Real, Field(ge=0.0, le=0.5)] = 0.0
    """Cosine taper at each end, as a fraction of the length (obspy's max_percentage),
    0 to 0.5; 0: none."""

    filter: Filter | None = None
    """Butterworth filter; default none."""

    window: Window | None = None
    """Keep only this time window; default the whole record."""

    resample: Flag = True
    """If the components' sample intervals differ: true resamples them linearly to the
    smaller one (exact for the piecewise-linear ground motion pound applies) and notes it;
    false refuses the record."""

    scale: Annotated[Positive, Field(le=1000.0)] | None = None
    """Factor applied to both components, dimensionless; not with target_pga."""

    target_pga: Annotated[Positive, Field(le=10.0)] | None = None
    """Scale both components by one factor so that the larger horizontal PGA (of the
    components the record gives, after processing) is this value, g; not with scale."""

    @model_validator(mode="after")
    def _one_scaling(self) -> "Processing":
        if self.scale is not None and self.target_pga is not None:
            raise ValueError("give either scale or target_pga, not both")
        return self

    def steps(self) -> list[str]:
        """The processing steps in the order they are applied, in words (empty: none)."""
        out = []
        if self.demean:
            out.append("demean")
        if self.detrend:
            out.append("linear detrend")
        if self.taper:
            out.append(f"cosine taper {100 * self.taper:g} % at each end")
        if self.filter is not None:
            out.append(_describe_filter(self.filter))
        if self.window is not None:
            end = f"{self.window.end:g} s" if self.window.end is not None else "the end"
            out.append(f"window {self.window.start:g} s to {end}")
        if self.scale is not None:
            out.append(f"scale × {self.scale:g}")
        if self.target_pga is not None:
            out.append(f"scaled to a PGA of {self.target_pga:g} g")
        return out


def _describe_filter(f: Filter) -> str:
    phase = "zero-phase" if f.zerophase else "causal"
    if f.freqmin is not None and f.freqmax is not None:
        band = f"band-pass {f.freqmin:g}-{f.freqmax:g} Hz"
    elif f.freqmin is not None:
        band = f"high-pass {f.freqmin:g} Hz"
    else:
        band = f"low-pass {f.freqmax:g} Hz"
    return f"{band}, {f.corners}-pole Butterworth, {phase}"


class Record(Strict):
    """A two-component ground-motion record: what it is, its files, how to process it."""

    name: Text = ""
    """A label for the record (event, station), printed by validate and stored with the results."""

    event: Text = ""
    """The earthquake, e.g. "1995 Hyogo-ken Nanbu (Kobe)"."""

    date: DateText = ""
    """Date of the event, as text (e.g. "1995-01-17"; a TOML date is accepted)."""

    magnitude: Annotated[Real, Field(ge=-2.0, le=10.0)] | None = None
    """Magnitude of the event, dimensionless (say which scale, e.g. Mw, in notes)."""

    station: Text = ""
    """Recording station, e.g. "KJMA (JMA Kobe)"."""

    network: Text = ""
    """Network or agency that runs the station, e.g. "JMA" or "CI"."""

    source: Text = ""
    """Where the record comes from: database, record number, URL."""

    notes: Text = ""
    """Anything else: processing done before pound, terms of use, the magnitude scale."""

    L: RecordComponent | None = None
    """Component L: along the excitation angle θ from the global X axis, or along its
    azimuth turned by θ."""

    T: RecordComponent | None = None
    """Component T: along θ + 90°, or along its azimuth turned by θ."""

    processing: Processing = Processing()
    """Processing and scaling of both components; default none."""

    @model_validator(mode="after")
    def _components(self) -> "Record":
        if self.L is None and self.T is None:
            raise ValueError("a record needs at least one component: give L, T or both")
        given = [c for c in (self.L, self.T) if c is not None]
        if len(given) == 2 and (given[0].azimuth is None) != (given[1].azimuth is None):
            which = "L" if self.L.azimuth is not None else "T"
            other = "T" if which == "L" else "L"
            raise ValueError(
                f"{which}.azimuth is given but {other}.azimuth is not: give the azimuth of both "
                "components (degrees clockwise from north) or of neither (L along θ, T along θ + 90°)"
            )
        return self

    def components(self) -> dict[str, RecordComponent]:
        """The components given, by name ("L", "T")."""
        return {k: c for k, c in (("L", self.L), ("T", self.T)) if c is not None}


RECORD_SUFFIXES = (".toml", ".json")


def check_record_path(value: Any) -> Any:
    """Return `value` if it names a .toml or .json file; raise ValueError otherwise."""
    if isinstance(value, str) and not (value.lower().endswith(RECORD_SUFFIXES) and len(value) > 5):
        raise ValueError(
            f"expected a record table or the path of a record definition file (.toml or .json), got {value!r}"
        )
    return value


RecordPath = Annotated[
    str,
    StrictType(),
    BeforeValidator(check_record_path),
    WithJsonSchema({"type": "string", "pattern": r"\.([Tt][Oo][Mm][Ll]|[Jj][Ss][Oo][Nn])$"}),
]
"""The path of a record definition file (.toml or .json), relative to the model file."""


def load_record(path: str | Path) -> Record:
    """Read and validate a record definition file; InputError names the file and the field."""
    from .load import read_document  # the TOML/JSON reader of model files

    path = Path(path)
    return validate_record(read_document(path), path)


def validate_record(data: dict[str, Any], source: str | Path) -> Record:
    """Validate an already parsed record definition that came from `source`."""
    from .load import validated

    return validated(Record, data, Path(source), "a record definition", _describe)


def _describe(source: Path, error: dict[str, Any]) -> str:
    """A record definition's error, worded as model files word theirs."""
    from .load import describe_error

    return describe_error(source, error, Record)
