"""How well the paper's Kobe example converges as the contact step shrinks, and how sensitive
its peaks are to the input itself (quoted in docs/bench.md, "The Kobe example").

    python docs/kobe_sensitivity.py

For the paper's friction (μ_s = 0.8, μ_k = 0.6), for μ_s = μ_k = 0.6 and without friction:
the hybrid integrator (exact between impacts, so only the contact phases depend on Δt) at
8, 4, 2, 1, 1/2 and 1/8 × the automatic contact step, against the hybrid at 1/128 of it (whose
own error is shown by 1/256); then, at 1/8 of the step, the change of the peaks when the
record is scaled by 1 + 10⁻⁴ (a change far below what any record is known to). Errors are
bench's (pounding_cli.bench.metrics): the largest relative error of any peak interstorey
deflection, and normwise (relative to its building's largest peak of that component). Needs
the Kobe record in ../shared/records (see inputs/paper_kobe.toml). Writes the result file
docs/bench/kobe-sensitivity.md, which docs/bench.md includes (through docs/build.py); the docs
build does not rerun it (minutes of runs at fine steps).
"""

from __future__ import annotations

import copy
from pathlib import Path

from pounding_cli.api import execute, prepare
from pounding_cli.bench.metrics import compare
from pounding_cli.bench.run import Setting, with_setting
from pounding_cli.model import read_document, validate_model

MODEL = Path(__file__).resolve().parents[1] / "inputs" / "paper_kobe.toml"
OUT = Path(__file__).resolve().parents[1] / "docs" / "bench" / "kobe-sensitivity.md"
SCALES = (8.0, 4.0, 2.0, 1.0, 1 / 2, 1 / 8)
REFERENCE = 1 / 128
FINE = 1 / 8
PERTURBATION = 1e-4


def run(doc, dt_scale):
    return execute(with_setting(prepare(validate_model(doc, MODEL)), Setting("x", "hybrid", dt_scale=dt_scale)))


def line(label, errors):
    return (f"  {label:<34} peaks {errors.peak_deflection:.1e} (normwise {errors.peak_deflection_norm:.1e}), "
            f"peak force {errors.peak_force:.1e}, impacts {errors.impact_count:+d}")  # fmt: skip


def main() -> None:
    base = read_document(MODEL)
    variants = {"the paper's friction, μ_s = 0.8, μ_k = 0.6": base}
    for label, (mu_s, mu_k) in (("μ_s = μ_k = 0.6", (0.6, 0.6)), ("without friction", (0.0, 0.0))):
        doc = copy.deepcopy(base)
        doc["contact"].update(friction_static=mu_s, friction_kinetic=mu_k)
        variants[label] = doc
    measured = {}
    for label, doc in variants.items():
        reference = run(doc, REFERENCE)
        print(f"{label}: reference ({REFERENCE:g} of the contact step) {reference.contact.impact_count} impacts, "
              f"peak force {reference.contact.peak_force / 1e6:.2f} MN")  # fmt: skip
        own = compare(run(doc, REFERENCE / 2), reference)
        print(line(f"{REFERENCE / 2:g} of the step (the reference's own error)", own))
        errors = {}
        for scale in SCALES:
            errors[scale] = compare(run(doc, scale), reference)
            print(line(f"{scale:g} × the automatic contact step", errors[scale]))
        fine = run(doc, FINE)
        shaken = copy.deepcopy(doc)
        shaken["excitation"]["scale"] = shaken["excitation"].get("scale", 1.0) * (1 + PERTURBATION)
        moved = compare(run(shaken, FINE), fine)
        print(line(f"record × (1 + {PERTURBATION:g}), at {FINE:g} of the step", moved))
        measured[label] = (own, errors, moved)
    OUT.write_text(markdown(measured), encoding="utf-8")
    print(f"wrote {OUT}")


def markdown(measured: dict) -> str:
    """The result file: the largest relative error of any peak interstorey deflection at each
    contact step (as a fraction of 2/ω_contact), then the default's errors in full."""
    fraction = 0.00625  # the automatic contact step, × 2/ω_contact
    steps = [f"{fraction * s:g}" + (" (default)" if s == 1 else "") for s in SCALES]
    lines = ["| | 1/256 (the reference's error) | " + " | ".join(steps)
             + f" | record × (1 + 10⁻⁴), at {fraction * FINE:g} |",
             "| --- |" + " ---: |" * (len(SCALES) + 2)]  # fmt: skip
    for label, (own, errors, moved) in measured.items():
        cells = [sci(own.peak_deflection)] + [pct(errors[s].peak_deflection) for s in SCALES] + [pct(moved.peak_deflection)]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines += ["", "At the default step (1 × the automatic contact step):", "",
              "| | peak deflections | normwise | peak force | impacts Δ | peak force at 1/2 of the step |",
              "| --- | ---: | ---: | ---: | ---: | ---: |"]  # fmt: skip
    for label, (_, errors, _) in measured.items():
        e = errors[1.0]
        lines.append(f"| {label} | {pct(e.peak_deflection)} | {pct(e.peak_deflection_norm)} | {pct(e.peak_force)} | "
                     f"{e.impact_count:+d} | {pct(errors[0.5].peak_force)} |")  # fmt: skip
    return "\n".join(lines) + "\n\nWritten by `python docs/kobe_sensitivity.py`.\n"


SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def sci(value: float) -> str:
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa} × 10{str(int(exponent)).translate(SUPERSCRIPT)}"


def pct(ratio: float) -> str:
    """A relative error in per cent, two significant digits: 0.26 %, 2.8 × 10⁻⁴ %."""
    value = 100 * ratio
    return f"{value:.2g} %" if value >= 1e-3 else f"{sci(value)} %"


if __name__ == "__main__":
    main()
