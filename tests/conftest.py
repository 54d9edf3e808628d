"""Shared fixtures: the shipped example, and small models built as dicts."""

from __future__ import annotations

import copy
import os
import signal
import subprocess
import sys
import time
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



def sweep_then_kill(sweep: Path, out: Path, new_files: int) -> None:
    """Run `pound sweep --jobs 2` in a subprocess and kill it with SIGKILL (its process group:
    the workers too) once `new_files` more case files than before exist in `out`."""
    before = len(list((out / "cases").glob("*.h5")))
    proc = subprocess.Popen([sys.executable, "-m", "pounding_cli", "sweep", str(sweep), "-o", str(out), "--jobs", "2"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)  # fmt: skip
    try:
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline and proc.poll() is None:
            if len(list((out / "cases").glob("*.h5"))) >= before + new_files:
                break
            time.sleep(0.02)
        assert proc.poll() is None, f"the sweep ended before it could be killed: {proc.stderr.read().decode()}"
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=60)

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
