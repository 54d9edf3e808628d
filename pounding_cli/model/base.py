"""The strict base every input node derives from, and the number types of input fields.

Unknown keys are errors (``extra="forbid"``), NaN and infinity are rejected, and the
docstring under each field becomes its JSON-Schema description, which carries the unit.
Every scalar is strict: ``true`` or ``"3.0"`` is not a number (an integer is), ``2.0`` is not
a whole number, ``0`` or ``"no"`` is not a boolean, ``3`` is not a string
(tests/test_strict_types.py checks every field of every input file, from the schemas).
"""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, Strict as StrictType

Real = Annotated[float, StrictType()]
"""A finite real number (integers accepted, booleans and strings not)."""

Positive = Annotated[float, StrictType(), Field(gt=0)]
"""A finite real number > 0."""

MIN_SAMPLE_INTERVAL = 1e-6
"""Shortest accepted record sample interval, s (1 MHz; accelerographs sample at 50-1000 Hz).
A shorter one is a damaged header or a unit slip, and would make the step count overflow."""

MAX_SAMPLE_INTERVAL = 1.0
"""Longest accepted record sample interval, s (1 Hz cannot describe ground shaking)."""

SampleInterval = Annotated[float, StrictType(), Field(ge=MIN_SAMPLE_INTERVAL, le=MAX_SAMPLE_INTERVAL)]
"""A record's sample interval, s, between MIN_SAMPLE_INTERVAL and MAX_SAMPLE_INTERVAL."""

Count = Annotated[int, StrictType()]
"""An integer (booleans, strings and floats such as 2.0 are not)."""

Flag = Annotated[bool, StrictType()]
"""true or false: not 0 or 1, not "no", "yes", "off" or "true" (pydantic's lax bool takes
them all, and "no" would silently switch a setting off)."""

Text = Annotated[str, StrictType()]
"""A string (numbers, booleans and bytes are not)."""

Name = Annotated[str, StrictType(), Field(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9_.+\-]+$")]
"""A name used in paths and HDF5 groups: letters, digits and _ . + -."""


class Strict(BaseModel):
    """Base of all input models: strict keys, finite numbers, documented fields."""

    model_config = ConfigDict(
        extra="forbid",
        allow_inf_nan=False,
        validate_assignment=True,
        use_attribute_docstrings=True,
        populate_by_name=False,
    )
