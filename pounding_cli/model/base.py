"""The strict base every input node derives from.

Unknown keys are errors (``extra="forbid"``), NaN and infinity are rejected, and the
docstring under each field becomes its JSON-Schema description, which carries the unit.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class Strict(BaseModel):
    """Base of all input models: strict keys, finite numbers, documented fields."""

    model_config = ConfigDict(
        extra="forbid",
        allow_inf_nan=False,
        validate_assignment=True,
        use_attribute_docstrings=True,
        populate_by_name=False,
    )
