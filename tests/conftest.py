"""Shared fixtures: the shipped example, and small models built as dicts."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest

from pounding_cli.model import LoadedModel, read_document, validate_model

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"
EXAMPLE = INPUTS / "paper_wide_gap.toml"
RECORD = "records/ridgecrest2019_ccc.mseed"  # relative to inputs/
SHARED = ROOT.parent / "shared"


def example_doc() -> dict[str, Any]:
    """The shipped example as a fresh dict (edit freely)."""
    return copy.deepcopy(read_document(EXAMPLE))


def load_doc(doc: dict[str, Any]) -> LoadedModel:
    """Validate a model dict as if it were a file in inputs/ (so record paths resolve)."""
    return validate_model(doc, INPUTS / "test-model.toml")


def square_building(
    name: str = "b",
    size: float = 8.0,
    storeys: int = 1,
    eccentricity: tuple[float, float] = (0.0, 0.0),
    origin: tuple[float, float] = (0.0, 0.0),
    rotation: float = 0.0,
    section: tuple[float, float] = (0.35, 0.35),
) -> dict[str, Any]:
    """A square building on a 3×3 column grid, floors of 1000 kg/m²."""
    return {
        "name": name,
        "origin": list(origin),
        "rotation": rotation,
        "floors": [
            {
                "repeat": storeys,
                "height": 3.0,
                "slab": [[0, 0], [size, 0], [size, size], [0, size]],
                "mass_per_area": 1000.0,
                "eccentricity": list(eccentricity),
                "column_grid": {
                    "x": [0, size / 2, size],
                    "y": [0, size / 2, size],
                    "section": list(section),
                    "material": "concrete",
                },
            }
        ],
    }


def model_doc(*buildings: dict[str, Any], angle: float = 0.0, components=("L", "T"), **analysis) -> dict[str, Any]:
    """A model dict with the given buildings under the shipped Ridgecrest record."""
    return {
        "materials": {"concrete": {"elastic_modulus": 21e9, "poisson_ratio": 0.2}},
        "buildings": list(buildings) or [square_building()],
        "excitation": {
            "angle": angle,
            "components": list(components),
            "record": {
                "L": {"file": RECORD, "trace": "HNE", "units": "m/s2"},
                "T": {"file": RECORD, "trace": "HNN", "units": "m/s2"},
            },
        },
        "analysis": analysis,
    }


@pytest.fixture
def example() -> dict[str, Any]:
    return example_doc()
