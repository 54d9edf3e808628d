"""Ground acceleration in global axes from the record's components (paper eq. 2, with azimuths).

Each applied component c has a unit direction d_c in the global (X, Y) plane, and

    a_X(t) = s · Σ_c a_c(t)·d_c,X,      a_Y(t) = s · Σ_c a_c(t)·d_c,Y

with s the excitation's ``scale``. The direction is the record-frame direction u_c turned
counter-clockwise by the excitation angle θ, d_c = R(θ)·u_c (docs/theory.md §5):

- without azimuths, u_L = (1, 0) and u_T = (0, 1): L along θ, T along θ + 90°, which is
  eq. (2), a_X = a_L cos θ − a_T sin θ, a_Y = a_L sin θ + a_T cos θ;
- with azimuths α_c (degrees clockwise from north, X east, Y north), u_c = (sin α_c, cos α_c):
  at θ = 0 a component of azimuth 90° acts along +X and one of 360° along +Y.

Sines and cosines of multiples of 90° are taken exactly (cos 90° = 0, not 6e-17), so a
record aligned with the axes puts nothing on the other axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..model import LoadedModel
from ..model.excitation import missing_component_problem
from ..model.record import Record, load_record
from ..records import Accelerogram
from ..records.combine import RecordMotion, RecordOrigin, record_motion


@dataclass(frozen=True)
class GroundMotion:
    """The applied ground acceleration, sampled every `dt` from t = 0.

    Between samples it is linear; after the last sample the ground is at rest.
    """

    dt: float  # s
    acceleration: np.ndarray  # (n, 2) global X, Y, m/s², scaled
    components: dict[str, Accelerogram]  # the applied components as read, m/s²
    file_sha256: dict[str, str] = field(default_factory=dict)  # component (or "definition") -> hash
    notes: tuple[str, ...] = ()
    record: Record | None = None  # the record definition, resolved
    record_file: Path | None = None  # the record definition file, if the model names one
    directions: dict[str, tuple[float, float]] = field(default_factory=dict)  # component -> unit (X, Y)
    record_factor: float = 1.0  # the record's own scale or target_pga factor

    @property
    def duration(self) -> float:
        """Time of the last sample, s."""
        return (self.acceleration.shape[0] - 1) * self.dt


def resolve_record(loaded: LoadedModel) -> tuple[Record, RecordOrigin, Path | None]:
    """The model's record (inline, or read from the file it names) and where it is defined.

    A record file's errors name that file and its field, after the model file and
    ``excitation.record``; a component listed in ``components`` that the file lacks is an
    error of the model's ``excitation.components``.
    """
    excitation = loaded.model.excitation
    if isinstance(excitation.record, Record):
        return excitation.record, RecordOrigin(loaded.source, "excitation.record.", base=loaded.folder), None
    path = loaded.resolve(excitation.record)
    try:
        record = load_record(path)
    except InputError as exc:
        raise InputError(str(exc), file=loaded.source, field="excitation.record") from None
    try:
        missing_component_problem(excitation.components, record, str(path))
    except ValueError as exc:
        raise InputError(str(exc), file=loaded.source, field="excitation.components") from None
    return record, RecordOrigin(path, "", (loaded.source, "excitation.record")), path


def ground_motion(loaded: LoadedModel) -> GroundMotion:
    """Read the record and combine its applied components into global X, Y acceleration, m/s²."""
    excitation = loaded.model.excitation
    record, origin, record_file = resolve_record(loaded)
    motion = record_motion(record, origin)
    directions = {name: component_direction(record, name, excitation.angle) for name in excitation.components}
    acc = np.zeros((motion.points, 2))
    for name in excitation.components:  # in the order L, T: a_X = a_L cos θ − a_T sin θ bit for bit
        dx, dy = directions[name]
        acc[:, 0] += motion.acceleration[name] * dx
        acc[:, 1] += motion.acceleration[name] * dy
    acc *= excitation.scale
    return GroundMotion(
        motion.dt, acc, {n: motion.read[n] for n in excitation.components}, _hashes(motion, record_file),
        motion.notes, record, record_file, directions, motion.factor,
    )  # fmt: skip


def _hashes(motion: RecordMotion, record_file: Path | None) -> dict[str, str]:
    import hashlib

    hashes = dict(motion.file_sha256)
    if record_file is not None:
        from ..files import read_regular
        from ..model.load import MAX_MODEL_BYTES

        hashes["definition"] = hashlib.sha256(read_regular(record_file, MAX_MODEL_BYTES)).hexdigest()
    return hashes


def component_direction(record: Record, name: str, angle: float) -> tuple[float, float]:
    """Unit vector (X, Y) of component `name` at excitation angle θ = `angle` degrees."""
    spec = getattr(record, name)
    if spec is None or spec.azimuth is None:
        u = (1.0, 0.0) if name == "L" else (0.0, 1.0)
    else:
        u = (exact_sin(spec.azimuth), exact_cos(spec.azimuth))
    c, s = exact_cos(angle), exact_sin(angle)
    return (c * u[0] - s * u[1], s * u[0] + c * u[1])


def exact_cos(degrees: float) -> float:
    """cos of an angle in degrees, exactly 0 or ±1 at multiples of 90°."""
    quarter = _quarter_turns(degrees)
    return (1.0, 0.0, -1.0, 0.0)[quarter] if quarter is not None else float(np.cos(np.radians(degrees)))


def exact_sin(degrees: float) -> float:
    """sin of an angle in degrees, exactly 0 or ±1 at multiples of 90°."""
    quarter = _quarter_turns(degrees)
    return (0.0, 1.0, 0.0, -1.0)[quarter] if quarter is not None else float(np.sin(np.radians(degrees)))


def _quarter_turns(degrees: float) -> int | None:
    """k mod 4 if `degrees` is k·90° exactly, else None."""
    quarter = degrees / 90.0
    return int(quarter) % 4 if quarter == math.floor(quarter) else None
