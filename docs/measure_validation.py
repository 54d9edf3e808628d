"""Re-measure the figures quoted in docs/validation.md and docs/theory.md.

    python docs/measure_validation.py

Uses the test suite's independent references (tests/exact.py) on the same cases the tests
run; prints what the tests assert against their tolerances.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import pounding_cli as pound  # noqa: E402
from pounding_cli.assembly import assemble, ground_motion, timestep  # noqa: E402
from pounding_cli.solver import simulate  # noqa: E402
from test_time_history import _eccentric_case, _exact_peaks  # noqa: E402


def peak_errors(result_peaks: np.ndarray, exact: np.ndarray) -> list[float]:
    """Largest relative error per component (x, y, θ) over significant entries."""
    out = []
    for k in range(3):
        sig = exact[:, :, k] > 1e-3 * exact[:, :, k].max()
        out.append(float((np.abs(result_peaks[:, :, k] - exact[:, :, k])[sig] / exact[:, :, k][sig]).max()))
    return out


def main() -> None:
    loaded = _eccentric_case()
    system = assemble(loaded)
    ground = ground_motion(loaded)
    exact, _ = _exact_peaks(system.buildings[0], ground, substeps=20)
    print("peak interstorey deflection error against the exact solution (x, y, θ):")
    default = timestep.AUTO_DT_FRACTION
    for fraction in (0.2, 0.1, 0.05, 0.025):
        timestep.AUTO_DT_FRACTION = fraction
        result = pound.run_model(loaded)
        errs = peak_errors(result.buildings["b"].interstorey_deflection, exact)
        mark = "  <- default" if fraction == default else ""
        print(f"  dt = {fraction:5.3f}·2/ω_max = {result.diagnostics['dt'] * 1e3:.3f} ms: "
              + ", ".join(f"{100 * e:.4f} %" for e in errs)
              + f"; energy balance {result.balance_error_ratio:.2e}{mark}")
    timestep.AUTO_DT_FRACTION = default

    _, u_exact = _exact_peaks(system.buildings[0], ground, substeps=4)
    reference = u_exact[:4001:4]
    steps, errors = [], []
    for per_output in (8, 16, 32, 64):
        r = simulate(system, ground.acceleration, ground.dt, 0.01 / per_output, per_output, per_output * 1000)
        errors.append(np.abs(r.displacement - reference).max())
        steps.append(0.01 / per_output)
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    print(f"CDM convergence: max displacement error {', '.join(f'{e:.3g}' for e in errors)} m "
          f"at Δt = 1.25, 0.625, 0.3125, 0.156 ms; slope {slope:.4f}")

    example = pound.describe(ROOT / "inputs" / "paper_wide_gap.toml")
    for b in example["buildings"]:
        print(f"{b['name']}: periods " + ", ".join(f"{t:.4f}" for t in b["periods_s"]) + " s")


if __name__ == "__main__":
    main()
