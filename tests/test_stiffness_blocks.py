"""The buildings' dense K and C blocks (solver/integrate.py: stiffness_blocks), built for all
buildings at once, one product per column index: against the products with one unit entry
at a time, bit for bit (buildings share no storey and no damping link, so each entry is the
same sum of the same storey terms in the same order)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pounding_cli.api import prepare
from pounding_cli.solver.integrate import building_dofs, damping_times, stiffness_blocks, stiffness_times

REPO = Path(__file__).resolve().parents[1]


def _one_unit_entry_at_a_time(structure, times):
    starts, counts = building_dofs(structure)
    x = np.zeros(structure.mass.size + 3)
    blocks = []
    for d0, n in zip(starts, counts):
        k = np.empty((n, n))
        for j in range(n):
            x[:] = 0.0
            x[d0 + j] = 1.0
            k[:, j] = times(structure, x)[d0 : d0 + n]
        blocks.append(k)
    return blocks


@pytest.mark.parametrize("model", ["city_block.toml", "isolated_moat.toml", "mismatched_floors.toml"])
@pytest.mark.parametrize("times", [stiffness_times, damping_times])
def test_blocks_of_all_buildings_at_once_are_those_of_one_at_a_time(model, times):
    """city_block: 100 buildings of 2–6 storeys (blocks of different sizes); isolated_moat:
    isolators' damping links; mismatched_floors: storeys of different heights."""
    structure = prepare(REPO / "inputs" / model).system
    expected = _one_unit_entry_at_a_time(structure, times)
    found = stiffness_blocks(structure, times)
    assert len(found) == len(expected) == len(structure.floor_start) - 1
    for k, (a, b) in enumerate(zip(found, expected)):
        assert np.array_equal(a, b), k
