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
    member_deflection: float = 0.0  # largest relative error of a yielding member's peak |δ| (0 without members)
    ductility: float = 0.0  # largest error of a member's peak ductility, relative to max(μ_ref, 1)
    members: int = 0  # yielding members (inelastic columns, isolators) compared


def member_errors(run: RunResult, reference: RunResult) -> tuple[float, float, int]:
    """Errors of the yielding members' peaks: (peak resultant deflection, peak ductility,
    members compared). Peak |δ| = √(δ_x² + δ_y²) at its largest over the run; peaks below
    FLOOR of their building's largest are compared against that. Peak ductility = the larger
    of a member's peak |δ_x|/δ_y,x and |δ_y|/δ_y,y; its error is taken relative to the
    reference's ductility, or to 1 (the yield deflection) for a member that stayed elastic."""
    deflection = 0.0
    ductility = 0.0
    members = 0
    for name, ref in reference.buildings.items():
        want = ref.yielding
        if want is None or want.peak.shape[0] == 0:
            continue
        got = run.buildings[name].yielding
        assert got is not None and got.peak.shape == want.peak.shape, f"{name}: yielding members differ"
        members += want.peak.shape[0]
        w = want.peak[:, 2]
        scale = float(np.max(w))
        if scale > 0.0:
            deflection = max(deflection, float(np.max(np.abs(got.peak[:, 2] - w) / np.maximum(w, FLOOR * scale))))
        mu_want = want.ductility.max(axis=1)
        mu_got = got.ductility.max(axis=1)
        ductility = max(ductility, float(np.max(np.abs(mu_got - mu_want) / np.maximum(mu_want, 1.0))))
    return deflection, ductility, members


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
    member_deflection, ductility, members = member_errors(run, reference)
    return Errors(
        peak_deflection=worst,
        peak_deflection_norm=norm,
        peak_force=force,
        impact_count=run.contact.impact_count - reference.contact.impact_count,
        energy_balance=run.balance_error_ratio,
        member_deflection=member_deflection,
        ductility=ductility,
        members=members,
    )
