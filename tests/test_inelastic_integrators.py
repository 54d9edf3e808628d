"""The hybrid integrator with yielding columns against the central difference method
(inputs/paper_inelastic.toml: the paper's two buildings, every column bilinear with an
elliptical yield surface, 1 cm yield deflection, 5 % hardening; issue 6, "Time stepping").

The hybrid propagates exactly while every member is bounded away from its yield surface and
hands the state to the CDM around yielding (and contacts). The comparison runs the example
shortened (the Ridgecrest record's strong motion starts at about 7 s: the left building's
columns first yield at 7.37 s; no impact happens before 20 s at the 5 cm gap):

* default: 8 s, the CDM at the same Δt as the hybrid's CDM phases — its yielding step
  (0.0125 · 2/ω_max of the structure, 0.139 ms; no contact is possible before 20 s, so the
  contact step, 6.5× smaller, is never used) — so any difference comes from the exact
  phases (substeps of 1.1 ms; column peaks between them interpolated, members' peaks taken at
  their ends) and the hand-overs (6 switches).
  Measured: peak column deflections 1.5e-6 (left) and 2.0e-6 (right; 3.1e-5 with the peaks
  taken at the substeps' ends only) relative; member peaks
  (δ and f, of the largest per quantity) 4.5e-6 and 1.6e-4; residual deflection 9.4e-6 of
  the largest; member deflection histories 3.4e-6 of the peak; hysteretic energy 1.7e-6.
* slow: 10 s, the CDM at a quarter of the contact step (5.34e-6 s, 1.9 million steps), a
  converged reference: the hybrid's yielding step is 26× coarser, and yield events make its
  error first order in that step (halving it halves the errors). Measured: peak column
  deflections 7.3e-5 relative; member peaks 3.2e-4; member histories 1.2e-4.
Both assert 1e-3: relative on peaks and the hysteretic energy, of the largest value for
ductilities, member peaks, residual deflections (or of 1 mm) and member histories; the
energy balance of both runs < 1e-3 (measured: hybrid 3.6e-5 / 2.3e-5, CDM < 1e-8).
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from pounding_cli import run_model
from pounding_cli.model import read_document, validate_model

from conftest import INPUTS

MODEL = INPUTS / "paper_inelastic.toml"
TOL = 1e-3


def run(duration: float, integrator: str = "auto", dt: float | str = "auto"):
    doc = copy.deepcopy(read_document(MODEL))
    doc["analysis"].update(duration=duration, integrator=integrator, dt=dt)
    result = run_model(validate_model(doc, MODEL))
    assert result.complete, result.status
    return result


def compare(hybrid, cdm) -> None:
    d = hybrid.diagnostics
    assert d["integrator"] == "hybrid" and cdm.diagnostics["integrator"] == "cdm"  # the model's names
    # the hybrid actually switched: exact substeps while elastic, the CDM around yielding
    assert d["switches"] >= 2 and d["exact_substeps"] > 0 and d["cdm_steps"] > 0
    for r in (hybrid, cdm):
        assert r.balance_error_ratio < 1e-3
    yielded = False
    for name, bh in hybrid.buildings.items():
        bc = cdm.buildings[name]
        # peak interstorey deflections of every column and storey, x and y
        ph, pc = bh.interstorey_deflection[:, :, :2], bc.interstorey_deflection[:, :, :2]
        assert np.abs(ph - pc).max() < TOL * pc.max(), name
        np.testing.assert_allclose(bh.peak_displacement[:, :2], bc.peak_displacement[:, :2], rtol=TOL,
                                   atol=TOL * bc.peak_displacement[:, :2].max())  # fmt: skip
        yh, yc = bh.yielding, bc.yielding
        assert yh is not None and yc is not None
        assert np.abs(yh.ductility - yc.ductility).max() < TOL * yc.ductility.max(), name
        assert np.all(np.abs(yh.peak - yc.peak) <= TOL * yc.peak.max(axis=0)), name  # δ and f, per column
        assert np.array_equal(yh.ductility >= 1.0, yc.ductility >= 1.0), name
        yielded |= bool((yc.ductility > 1.0).any())
        res = np.abs(yc.residual_deflection).max()
        assert np.abs(yh.residual_deflection - yc.residual_deflection).max() <= TOL * max(res, 1e-3), name
        # member histories at the output interval
        assert np.abs(yh.deflection - yc.deflection).max() < TOL * yc.peak[:, 2].max(), name
    assert yielded  # some column went past its yield point
    eh, ec = hybrid.energy_column("hysteretic")[-1], cdm.energy_column("hysteretic")[-1]
    assert ec > 0
    assert eh == pytest.approx(ec, rel=TOL)


def test_hybrid_against_cdm_same_step():
    hybrid = run(8.0)
    cdm = run(8.0, "cdm", hybrid.diagnostics["yield_dt"])  # no contact within 8 s: the yielding step throughout
    assert hybrid.diagnostics["yield_dt"] > 5 * hybrid.diagnostics["dt"], "the contact does not limit yielding phases"
    assert cdm.diagnostics["dt"] == pytest.approx(hybrid.diagnostics["yield_dt"], rel=1e-12)
    compare(hybrid, cdm)


@pytest.mark.slow
def test_hybrid_against_cdm_quarter_step():
    hybrid = run(10.0)
    cdm = run(10.0, "cdm", hybrid.diagnostics["dt"] / 4)
    assert cdm.diagnostics["dt"] == pytest.approx(hybrid.diagnostics["dt"] / 4, rel=1e-12)
    compare(hybrid, cdm)
