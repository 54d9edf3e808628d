"""Stability stress cases (`pound bench --stability`): each completes with a closed energy
balance, or is refused before it starts, or stops marked as failed — never garbage."""

from __future__ import annotations

import pytest

from pounding_cli.bench.stability import BALANCE_OK, CASES, run_case


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_stress_case_is_never_silently_wrong(case):
    outcome = run_case(case)
    assert outcome.acceptable, outcome
    if "stability limit" in case.name:
        factor = float(case.name.split("at ")[1].split(" ×")[0])
        if factor >= 1.0:
            assert outcome.result.startswith("refused: ") and "stability limit" in outcome.result
        else:
            assert outcome.result == "complete" and outcome.energy_balance < BALANCE_OK


@pytest.mark.slow
def test_an_unstable_contact_stops_marked_failed():
    """A step far above the contact's stability limit (k_N × 1000, Δt given) must not return
    a result as if it were complete: the run stops as failed, or its balance stays closed."""
    from pounding_cli.bench.stability import Case, _both, _set

    case = Case("Δt = 2e-4 s, k_N = 2e13", _both(_set("analysis.dt", 2e-4), _set("analysis.integrator", "cdm"),
                                                 _set("contact.k_normal", 2e13)))  # fmt: skip
    outcome = run_case(case)
    assert outcome.result.startswith("failed: ") or outcome.energy_balance < BALANCE_OK, outcome
