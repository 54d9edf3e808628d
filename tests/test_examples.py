"""Every shipped example runs to completion at its default time step with the energy
balance closed within 1 % of the input energy (the contact-aware automatic Δt must keep
impacts resolved)."""

from __future__ import annotations

import pytest

import pounding_cli as pound

from conftest import INPUTS, SHARED

# *.record.toml / *.record.json are record definitions, not models (tests/records/ reads them);
# *.sweep.toml are sweep files (tests/test_sweep_run.py runs them)
EXAMPLES = [p for p in sorted(INPUTS.glob("*.toml")) + sorted(INPUTS.glob("*.json"))
            if not p.name.endswith((".record.toml", ".record.json", ".sweep.toml", ".sweep.json"))]


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_runs_with_closed_energy_balance(path, tmp_path):
    if "shared/records" in path.read_text() and not SHARED.exists():
        pytest.skip("the model reads a record kept in ../shared, which is absent")
    result = pound.run_model(path, output=tmp_path / "out.h5")
    assert result.complete, result.status
    assert result.balance_error_ratio < 0.01
    assert (tmp_path / "out.h5").exists()
