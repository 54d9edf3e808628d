"""How far a run is from the reference: the errors `pound bench` reports."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..results import RunResult

FLOOR = 1e-2
"""Peaks smaller than this fraction of their building's largest (per component) are compared
against that fraction, so that near-zero peaks (a twist of 1e-9 rad in a symmetric building)
do not turn rounding into large relative errors."""


@dataclass(frozen=True)
class Errors:
    """Errors of a run against the reference."""

    peak_deflection: float  # largest relative error of any peak interstorey deflection (x, y, θ)
    peak_deflection_norm: float  # largest error of one, relative to its building's largest (per component)
    peak_force: float  # relative error of the largest impact force (0 without impacts)
    impact_count: int  # impacts − reference impacts
    energy_balance: float  # the run's own balance error / input energy


def compare(run: RunResult, reference: RunResult) -> Errors:
    """Errors of `run` against `reference` (same model)."""
    worst = 0.0
    norm = 0.0
    for name, ref in reference.buildings.items():
        got = run.buildings[name].interstorey_deflection
        want = ref.interstorey_deflection
        for k in range(3):
            w = want[:, :, k]
            scale = np.nanmax(np.abs(w)) if np.isfinite(w).any() else 0.0
            if scale == 0.0:
                continue
            difference = np.abs(got[:, :, k] - w)
            worst = max(worst, float(np.nanmax(difference / np.maximum(np.abs(w), FLOOR * scale))))
            norm = max(norm, float(np.nanmax(difference)) / scale)
    f_ref = reference.contact.peak_force
    force = abs(run.contact.peak_force - f_ref) / f_ref if f_ref > 0 else float(run.contact.peak_force > 0)
    return Errors(
        peak_deflection=worst,
        peak_deflection_norm=norm,
        peak_force=force,
        impact_count=run.contact.impact_count - reference.contact.impact_count,
        energy_balance=run.balance_error_ratio,
    )
