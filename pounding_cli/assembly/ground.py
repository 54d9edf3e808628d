"""Ground acceleration in global axes from the record's L and T components (paper eq. 2).

a_X = a_L·cos θ − a_T·sin θ,  a_Y = a_L·sin θ + a_T·cos θ, which is
−M(I_L·a_L + I_T·a_T) with I_L = I_X cos θ + I_Y sin θ, I_T = −I_X sin θ + I_Y cos θ.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, RecordReadError
from ..model import LoadedModel
from ..records import Accelerogram, read_accelerogram


@dataclass(frozen=True)
class GroundMotion:
    """The applied ground acceleration, sampled every `dt` from t = 0.

    Between samples it is linear; after the last sample the ground is at rest.
    """

    dt: float  # s
    acceleration: np.ndarray  # (n, 2) global X, Y, m/s², scaled
    components: dict[str, Accelerogram]  # the applied components as read, m/s²
    file_sha256: dict[str, str] = field(default_factory=dict)  # component -> file hash
    notes: tuple[str, ...] = ()

    @property
    def duration(self) -> float:
        """Time of the last sample, s."""
        return (self.acceleration.shape[0] - 1) * self.dt


def read_components(loaded: LoadedModel) -> tuple[dict[str, Accelerogram], dict[str, str]]:
    """Read the applied components (m/s²) and the sha256 of each file."""
    excitation = loaded.model.excitation
    out, hashes = {}, {}
    for name in excitation.components:
        spec = getattr(excitation.record, name)
        path = loaded.resolve(spec.file)
        field_path = f"excitation.record.{name}"
        try:
            out[name] = read_accelerogram(
                path, trace=spec.trace, units=spec.units, format=spec.format, dt=spec.dt
            )
            hashes[name] = hashlib.sha256(path.read_bytes()).hexdigest()
        except RecordReadError as exc:
            raise InputError(str(exc), file=loaded.source, field=f"{field_path}.{exc.field}") from None
    return out, hashes


def ground_motion(loaded: LoadedModel) -> GroundMotion:
    """Read the record and combine its components into global X, Y acceleration, m/s²."""
    excitation = loaded.model.excitation
    components, hashes = read_components(loaded)
    dt = min(c.dt for c in components.values())
    span = min((c.acceleration.size - 1) * c.dt for c in components.values())
    n = int(np.floor(span / dt + 1e-9)) + 1
    t = np.arange(n) * dt
    notes = []
    same_dt = all(abs(c.dt - dt) <= 1e-9 * dt for c in components.values())
    if not same_dt:
        notes.append(f"components have different sample intervals; resampled linearly to {dt:g} s")
    if max(c.duration for c in components.values()) - span > 0.5 * dt:
        notes.append(f"components have different lengths; cut to the common {span:g} s")
    resampled = {}
    for name, comp in components.items():
        if abs(comp.dt - dt) <= 1e-9 * dt:
            resampled[name] = comp.acceleration[:n]
        else:
            tc = np.arange(comp.acceleration.size) * comp.dt
            resampled[name] = np.interp(t, tc, comp.acceleration)
    theta = np.radians(excitation.angle)
    a_l = resampled.get("L", np.zeros(n))
    a_t = resampled.get("T", np.zeros(n))
    acc = np.empty((n, 2))
    acc[:, 0] = a_l * np.cos(theta) - a_t * np.sin(theta)
    acc[:, 1] = a_l * np.sin(theta) + a_t * np.cos(theta)
    acc *= excitation.scale
    return GroundMotion(dt, acc, components, hashes, tuple(notes))
