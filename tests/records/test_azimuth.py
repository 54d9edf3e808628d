"""Where a component lands: azimuth (clockwise from north, X east, Y north) turned by θ.

A unit pulse on one component, the other zero, goes through the real pipeline (record files on
disk, a model, `ground_motion`) and is checked per global axis: it must appear on X and Y
as the direction R(θ)·(sin α, cos α) says (docs/theory.md §5), and once through a run.
Angles that are whole quarter turns are exact (the trigonometry is exact there), others to
1e-15 (one rounding in each of sin, cos and the rotation's two products).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import pounding_cli as pound
from pounding_cli.assembly.ground import component_direction, ground_motion
from pounding_cli.model import validate_model
from pounding_cli.model.record import Record

from conftest import square_building

DT = 0.01
N = 101
PULSE_AT = 20  # sample index of the unit pulse


def write_pulse_records(folder: Path) -> tuple[Path, Path]:
    """Two one-column text records (m/s²): a unit pulse, and zeros."""
    pulse = np.zeros(N)
    pulse[PULSE_AT] = 1.0
    one, zero = folder / "pulse.txt", folder / "zero.txt"
    one.write_text("\n".join(f"{v:g}" for v in pulse) + "\n")
    zero.write_text("\n".join("0" for _ in range(N)) + "\n")
    return one, zero


def pulse_model(folder: Path, on: str, azimuths: tuple[float, float] | None, angle: float, duration=None) -> dict:
    """A one-storey model whose record has the pulse on component `on` ("L" or "T")."""
    one, zero = write_pulse_records(folder)
    files = {"L": one if on == "L" else zero, "T": one if on == "T" else zero}
    record = {}
    for k, name in enumerate(("L", "T")):
        record[name] = {"file": files[name].name, "units": "m/s2", "dt": DT}
        if azimuths is not None:
            record[name]["azimuth"] = azimuths[k]
    return {
        "materials": {"concrete": {"elastic_modulus": 21e9, "poisson_ratio": 0.2}},
        "buildings": [square_building()],
        "excitation": {"angle": angle, "record": record},
        "analysis": {} if duration is None else {"duration": duration},
    }


def expected_direction(azimuth: float | None, default: tuple[float, float], angle: float) -> tuple[float, float]:
    """R(θ)·u with u = (sin α, cos α), or the default record-frame direction, in floats."""
    u = default if azimuth is None else (math.sin(math.radians(azimuth)), math.cos(math.radians(azimuth)))
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    return (c * u[0] - s * u[1], s * u[0] + c * u[1])


CASES = [
    # (component with the pulse, azimuths of L and T or None, θ, exact X, exact Y or None)
    ("L", (90.0, 360.0), 0.0, (1.0, 0.0)),     # east -> +X
    ("T", (90.0, 360.0), 0.0, (0.0, 1.0)),     # north -> +Y
    ("T", (90.0, 0.0), 0.0, (0.0, 1.0)),       # 0 is north too
    ("L", (90.0, 360.0), 90.0, (0.0, 1.0)),    # east turned by 90° -> +Y
    ("T", (90.0, 360.0), 90.0, (-1.0, 0.0)),   # north turned by 90° -> -X
    ("L", (0.0, 90.0), 0.0, (0.0, 1.0)),       # Kobe 000 with its azimuth: +Y at θ = 0 ...
    ("L", (0.0, 90.0), -90.0, (1.0, 0.0)),     # ... and +X at θ = -90°
    ("T", (0.0, 90.0), -90.0, (0.0, -1.0)),    # but 090 then on -Y: the paper's layout is a mirror
    ("L", (180.0, 270.0), 0.0, (0.0, -1.0)),   # south -> -Y
    ("T", (180.0, 270.0), 0.0, (-1.0, 0.0)),   # west -> -X
    ("L", (45.0, 135.0), 0.0, None),           # north-east
    ("T", (45.0, 135.0), 30.0, None),          # south-east turned by 30°
    ("L", (10.0, 70.0), 200.0, None),          # components not at right angles
    ("L", None, 0.0, (1.0, 0.0)),              # no azimuths: L along θ ...
    ("T", None, 0.0, (0.0, 1.0)),              # ... T along θ + 90°
    ("L", None, 90.0, (0.0, 1.0)),
    ("T", None, 90.0, (-1.0, 0.0)),
    ("L", None, 30.0, None),
    ("T", None, 135.0, None),
]


@pytest.mark.parametrize(("on", "azimuths", "angle", "exact"), CASES,
                         ids=[f"{c[0]}-az{c[1]}-theta{c[2]:g}" for c in CASES])
def test_unit_pulse_lands_on_the_expected_axes(tmp_path, on, azimuths, angle, exact):
    loaded = validate_model(pulse_model(tmp_path, on, azimuths, angle), tmp_path / "m.toml")
    ground = ground_motion(loaded)
    default = (1.0, 0.0) if on == "L" else (0.0, 1.0)
    azimuth = None if azimuths is None else azimuths[0 if on == "L" else 1]
    want = exact if exact is not None else expected_direction(azimuth, default, angle)
    others = np.delete(ground.acceleration, PULSE_AT, axis=0)
    assert not others.any(), "the pulse spread to other samples"
    got = ground.acceleration[PULSE_AT]
    for axis, name in enumerate("XY"):
        if exact is not None:
            assert got[axis] == want[axis], f"{name}: {got[axis]!r} != {want[axis]!r} (exact at quarter turns)"
        else:
            assert got[axis] == pytest.approx(want[axis], abs=1e-15), name
    assert math.hypot(*got) == pytest.approx(1.0, abs=1e-15)


def test_record_at_east_and_north_equals_l_and_t_without_azimuths(tmp_path):
    """Azimuths 90°/360° are pound's L/T convention: the same ground motion bit for bit, at any θ."""
    for angle in (0.0, 30.0, 90.0, 247.5):
        with_az = ground_motion(validate_model(pulse_model(tmp_path, "L", (90.0, 360.0), angle), tmp_path / "a.toml"))
        without = ground_motion(validate_model(pulse_model(tmp_path, "L", None, angle), tmp_path / "b.toml"))
        assert np.array_equal(with_az.acceleration, without.acceleration), angle


def test_component_direction_is_a_unit_vector_turned_by_theta():
    record = Record.model_validate({
        "L": {"file": "x", "units": "g", "azimuth": 30.0}, "T": {"file": "y", "units": "g", "azimuth": 120.0},
    })  # fmt: skip
    for angle in (0.0, 15.0, -60.0, 400.0):
        lx, ly = component_direction(record, "L", angle)
        tx, ty = component_direction(record, "T", angle)
        assert math.hypot(lx, ly) == pytest.approx(1.0, abs=1e-15)
        assert lx * tx + ly * ty == pytest.approx(0.0, abs=1e-15)  # 30° and 120° stay at right angles
        # T is L turned clockwise by 90° (azimuth grows clockwise): (tx, ty) = (ly, -lx)
        assert (tx, ty) == pytest.approx((ly, -lx), abs=1e-15)


def test_a_run_applies_the_turned_component(tmp_path):
    """Through `run_model`: a record with L at azimuth 45° and θ = 30° shakes the ground along
    75° from north turned... i.e. along R(30°)(sin 45°, cos 45°) = direction 75° from X; the
    symmetric building moves along that line only (no eccentricity, so no twist)."""
    doc = pulse_model(tmp_path, "L", (45.0, 135.0), 30.0, duration=0.5)
    result = pound.run_model(validate_model(doc, tmp_path / "m.toml"))
    want = expected_direction(45.0, (1.0, 0.0), 30.0)  # (cos 75°, sin 75°)
    assert want == pytest.approx((math.cos(math.radians(75.0)), math.sin(math.radians(75.0))), abs=1e-15)
    ground = result.ground_acceleration
    peak = int(np.argmax(np.hypot(ground[:, 0], ground[:, 1])))
    assert ground[peak] == pytest.approx(want, abs=1e-15)
    u = result.buildings["b"].displacement[:, 0, :]  # (nt, 3): u_x, u_y, θ_z of the floor
    moving = np.hypot(u[:, 0], u[:, 1]) > 1e-3 * np.abs(u[:, :2]).max()
    # the floor moves along ±(cos 75°, sin 75°): its cross product with that direction vanishes
    cross = u[moving, 0] * want[1] - u[moving, 1] * want[0]
    assert np.abs(cross).max() <= 1e-9 * np.abs(u[:, :2]).max()
    assert np.abs(u[:, 2]).max() <= 1e-9 * np.abs(u[:, :2]).max() / 8.0  # no twist (per m of slab)
