"""How well the paper's Kobe example converges as the contact step shrinks, with and without
friction (quoted in docs/bench.md).

    python docs/kobe_sensitivity.py

Runs the hybrid integrator (exact between impacts, so only the contact phases depend on Δt)
at three contact steps, 0.0125, 0.00625 and 0.003125 × 2/ω, and prints, per building and
component, how far the peak interstorey deflections of the two coarser runs are from the
finest, relative to the largest peak of that building and component. Needs the Kobe record
in ../shared/records (see inputs/paper_kobe.toml).
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np

from pounding_cli.api import execute, prepare
from pounding_cli.bench.run import Setting, with_setting
from pounding_cli.model import read_document, validate_model

MODEL = Path(__file__).resolve().parents[1] / "inputs" / "paper_kobe.toml"
FRACTIONS = (0.0125, 0.00625, 0.003125)


def runs(doc):
    base = prepare(validate_model(doc, MODEL))
    return [execute(with_setting(base, Setting("x", "hybrid", dt_fraction=f, sampling=0.1))) for f in FRACTIONS]


def main() -> None:
    doc = read_document(MODEL)
    frictionless = copy.deepcopy(doc)
    frictionless["contact"].update(friction_static=0.0, friction_kinetic=0.0)
    for label, d in (("with friction (μ_s = 0.8, μ_k = 0.6)", doc), ("without friction", frictionless)):
        rs = runs(d)
        print(f"{label}: impacts {[r.contact.impact_count for r in rs]}, peak force "
              f"{', '.join(f'{r.contact.peak_force / 1e6:.2f}' for r in rs)} MN")  # fmt: skip
        for name in ("left", "right"):
            peaks = [r.buildings[name].interstorey_deflection for r in rs]
            for k, comp in enumerate("xyθ"):
                scale = np.nanmax(np.abs(peaks[-1][:, :, k]))
                diffs = [np.nanmax(np.abs(p[:, :, k] - peaks[-1][:, :, k])) / scale for p in peaks[:2]]
                print(f"  {name} {comp}: {diffs[0]:.1e} at {FRACTIONS[0]}, {diffs[1]:.1e} at {FRACTIONS[1]}")


if __name__ == "__main__":
    main()
