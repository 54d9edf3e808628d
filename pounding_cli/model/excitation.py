"""Ground excitation: a two-component record applied at an angle (paper eq. 2).

The record (model/record.py) is given inline or as the path of a record definition file;
a path is read when the ground motion is assembled (assembly/ground.py), so the checks that
need the record's components (``components`` lists a component the record gives) are made
there for a record file, and here for an inline record.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, ValidatorFunctionWrapHandler, field_validator, model_validator

from .base import Positive, Real, Strict
from .record import Record, RecordComponent, RecordPath, Units, check_record_path

__all__ = ["Excitation", "Record", "RecordComponent", "Units"]


class Excitation(Strict):
    """Ground motion: I_L = I_X cos θ + I_Y sin θ, I_T = −I_X sin θ + I_Y cos θ (eq. 2)."""

    record: Record | RecordPath
    """The record whose components are applied: a table, or the path of a record definition
    file (.toml or .json) relative to the model file."""

    angle: Real = 0.0
    """Excitation angle θ, degrees, counter-clockwise: the direction of component L from the
    global X axis (without azimuths), or the turn applied to the whole record (with azimuths)."""

    components: Annotated[list[Literal["L", "T"]], Field(min_length=1, max_length=2)] = ["L", "T"]
    """Which components shake the buildings: ["L", "T"], ["L"] or ["T"]."""

    scale: Annotated[Positive, Field(le=1000.0)] = 1.0
    """Factor applied to both components, dimensionless, on top of the record's own
    scale or target_pga."""

    @field_validator("record", mode="wrap")
    @classmethod
    def _record_or_path(cls, value: Any, handler: ValidatorFunctionWrapHandler) -> Record | str:
        """A table is validated as a Record, so that errors name excitation.record.<field>
        (not the branch of the union that failed); a string must name a .toml/.json file."""
        if isinstance(value, Record):
            return value
        if isinstance(value, str):
            return check_record_path(value)
        if not isinstance(value, dict):
            raise ValueError(
                "expected a record table or the path of a record definition file (.toml or .json), "
                f"got {value!r:.80}"
            )
        return Record.model_validate(value)

    @model_validator(mode="after")
    def _components_defined(self) -> "Excitation":
        if len(set(self.components)) != len(self.components):
            raise ValueError(f"components repeat: {self.components}")
        if isinstance(self.record, Record):
            missing_component_problem(self.components, self.record, "record")
        return self


def missing_component_problem(components: list[str], record: Record, where: str) -> None:
    """Raise ValueError if `components` lists a component that `record` does not give."""
    missing = [c for c in components if getattr(record, c) is None]
    if missing:
        raise ValueError(f"components lists {', '.join(missing)} but {where}.{missing[0]} is not given")
