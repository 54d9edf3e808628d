"""Analysis settings: duration, time step and output interval."""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Field, PlainValidator, WithJsonSchema

from .base import Flag, Positive, Strict


def _dt_or_auto(value: Any) -> float | Literal["auto"]:
    if value == "auto":
        return "auto"
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if math.isfinite(value) and 0 < value <= 1.0:
            return float(value)
    raise ValueError(f'expected a time step in s (a number in (0, 1]) or "auto", got {value!r}')


TimeStep = Annotated[
    float | Literal["auto"],
    PlainValidator(_dt_or_auto),
    WithJsonSchema(
        {
            "anyOf": [
                {"type": "number", "exclusiveMinimum": 0, "maximum": 1.0},
                {"const": "auto", "type": "string"},
            ]
        }
    ),
]


class Analysis(Strict):
    """How long and how finely to integrate, and how often to store the state."""

    duration: Positive | None = None
    """Length of the analysis, s. Default: the length of the shortest applied record
    component. After a record ends the ground is at rest (free vibration). Rounded up to a
    whole number of output intervals."""

    dt: TimeStep = "auto"
    """Time step of the central difference method, s, or "auto": the finest of 0.05 × the
    structure's stability limit 2/ω_max (0.0125 × with yielding members) and 0.00625 × the
    contact's 2/ω_contact where contact is possible, adjusted so that it divides the output
    interval (the hybrid's substep); `pound validate` says which limit governs (see
    docs/theory.md §6). A given step applies to every CDM step."""

    integrator: Literal["auto", "hybrid", "cdm"] = "auto"
    """"hybrid" (what "auto" chooses): the buildings advance exactly by their state-transition
    matrices while no contact is possible, and by the central difference method at the
    contact time step around impacts. "cdm": the central difference method at every step
    (the paper's method)."""

    output_interval: Annotated[Positive, Field(le=10.0)] = 0.01
    """Interval of the stored time histories, s; rounded to a whole number of time steps.
    Peaks are taken at every step regardless."""

    column_force_histories: Flag = False
    """Whether to store every column's shear forces along its local axes (N) and end moments
    (N·m) at the output interval, besides their peaks, which are always stored: 4 numbers per
    column and storey per sample, counted in the result file's size (the resource limits).
    Storey shears and the base shear are always stored as histories."""

    history_precision: Literal["double", "single"] = "double"
    """Floating-point precision of the buildings' stored time histories (displacements,
    velocities, accelerations, storey and base shears, column forces, yielding members'
    deflections and forces): "double" (float64, 16 significant digits) or "single" (float32,
    7 digits, relative rounding ≤ 6e-8: about half the file; writing, bound by the file's
    metadata, takes as long). The
    solver computes in double precision either way, and the peaks, impact log, contact
    histories, energies and ground motion are always stored in double precision."""
