"""A scene far from the origin runs as the same scene near it (assembly/origin.py).

Global plan coordinates of 1e7 m (UTM northings) or 3e8 m resolve 1e-9 and 6e-8 m: enough
for the geometry, but the overlap areas the time loop forms from them lost 2e-5 (1e7 m) and
0.8 % (3e8 m, 35 impacts instead of 32) of the peak force of the paper's buildings before the
scene was moved to a local origin. Coordinates that floats cannot resolve to 0.1 µm (beyond
about 1.07e9 m) are refused: tests/invalid/invalid_origin_beyond_resolution.toml (1e15 m).
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding_cli.api import run_model
from pounding_cli.assembly.origin import LOCAL_ORIGIN_FROM, reference_point

from conftest import load_doc, model_doc, square_building


def two_buildings(offset: float) -> dict:
    """A one-storey and a four-storey building 1 mm apart, under the shipped record's first
    6 s (12 impacts)."""
    return model_doc(square_building("a", origin=(offset, offset)),
                     square_building("b", size=6.0, storeys=4, origin=(offset + 8.001, offset + 1.0)), duration=6.0)  # fmt: skip


@pytest.mark.parametrize("offset, rtol", [(1e7, 1e-6), (3e8, 2e-4)])
def test_far_scene_runs_as_near_one(offset: float, rtol: float) -> None:
    """The same impacts and peaks to the input's own rounding: the 1 mm gap beside 3e8 m is
    resolved to 6e-8 m (6e-5 of it); without the local origin the peak force at 3e8 m was
    0.8 % off and the impacts 35, not 32 (the paper's buildings, 1 cm apart)."""
    near = run_model(load_doc(two_buildings(0.0)))
    far = run_model(load_doc(two_buildings(offset)))
    assert near.contact.impact_count > 0
    assert far.contact.impact_count == near.contact.impact_count
    np.testing.assert_allclose(far.contact.peak_force, near.contact.peak_force, rtol=rtol)
    for name in ("a", "b"):
        peaks = near.buildings[name].interstorey_deflection
        for k in range(3):  # x, y, θ: each to its own scale
            np.testing.assert_allclose(far.buildings[name].interstorey_deflection[..., k], peaks[..., k], rtol=rtol,
                                       atol=rtol * float(peaks[..., k].max()))  # fmt: skip
    # the impact log's points are global: the near ones moved by the offset
    np.testing.assert_allclose(far.contact.events["x"], near.contact.events["x"] + offset, atol=1e-6)
    np.testing.assert_allclose(far.contact.events["y"], near.contact.events["y"] + offset, atol=1e-6)


def test_scenes_near_the_origin_are_not_moved() -> None:
    """Within LOCAL_ORIGIN_FROM of the origin the time loop sees today's coordinates, bit for bit."""
    from pounding_cli.api import prepare

    near = prepare(load_doc(two_buildings(0.0)))
    assert not np.any(reference_point(near.system, near.contact))
    far = prepare(load_doc(two_buildings(10 * LOCAL_ORIGIN_FROM)))
    ref = reference_point(far.system, far.contact)
    assert np.all(ref == np.round(ref)) and np.all(np.abs(ref - 10 * LOCAL_ORIGIN_FROM) < 20)
