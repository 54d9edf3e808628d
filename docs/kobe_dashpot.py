"""The Kobe example with a tangential dashpot: how the stick–slip switching and the peaks converge
as the contact step shrinks (quoted in docs/bench.md, "A tangential dashpot").

    python docs/kobe_dashpot.py

The paper's model (μ_s = 0.8, μ_k = 0.6, no dashpot in either direction of its friction) with
`contact.damping_tangential` c_T = 0, 2·10³, 2·10⁴ and 2·10⁵ N·s/m: the hybrid integrator at 1,
1/4, 1/16 and 1/64 × the automatic contact step against the hybrid at 1/256 of it. For each,
the impacts, the slip phases of all impacts together (the impact log's `slips`), and the
largest relative error of any peak interstorey deflection and of the peak impact force (bench's
metrics, pounding_cli.bench.metrics), and the least energy the contacts held over the run (the
contact account of the energy balance: it must not fall below zero, a contact is no source). A
run that fails (the solver's energy check) is shown as such; a failed reference stops the script. Needs the Kobe record in ../shared/records (see
inputs/paper_kobe.toml). Writes docs/bench/kobe-dashpot.md, which docs/bench.md includes; the
docs build does not rerun it (minutes of runs at fine steps).
"""

from __future__ import annotations

import copy
from pathlib import Path

from kobe_sensitivity import MODEL, pct, run

from pounding_cli.bench.metrics import compare
from pounding_cli.model import read_document

OUT = Path(__file__).resolve().parents[1] / "docs" / "bench" / "kobe-dashpot.md"
DAMPING = (0.0, 2e3, 2e4, 2e5)
SCALES = (1.0, 1 / 4, 1 / 16, 1 / 64)
REFERENCE = 1 / 256


def main() -> None:
    base = read_document(MODEL)
    rows = []
    for c_t in DAMPING:
        doc = copy.deepcopy(base)
        if c_t > 0:
            doc["contact"]["damping_tangential"] = c_t
        reference = run(doc, REFERENCE)
        if not reference.complete:
            raise SystemExit(f"c_T = {c_t:g}: the reference at {REFERENCE:g} × the step {reference.status}")
        cells = []
        for scale in SCALES:
            result = run(doc, scale)
            slips = int(result.contact.events["slips"].sum())
            if result.complete:
                errors = compare(result, reference)
                cells.append((result.contact.impact_count, slips, errors.peak_deflection, errors.peak_force,
                              least_contact_energy(result)))  # fmt: skip
            else:
                cells.append((result.contact.impact_count, slips, result.status, None, None))
            print(f"c_T = {c_t:g}, {scale:g} × the step: {cells[-1]}", flush=True)
        rows.append((c_t, reference.contact.impact_count, int(reference.contact.events["slips"].sum()),
                     least_contact_energy(reference), cells))  # fmt: skip
    OUT.write_text(markdown(rows), encoding="utf-8")
    print(f"wrote {OUT}")


def least_contact_energy(result) -> float:
    """The least the contacts' energy account held over the run, over the largest input, J/J."""
    from pounding_cli.solver.layout import ENERGY_NAMES

    energy = result.energy
    return float(energy[:, ENERGY_NAMES.index("contact")].min() / max(energy[:, ENERGY_NAMES.index("input")].max(),
                                                                       1e-300))  # fmt: skip


def markdown(rows: list) -> str:
    """Per c_T and contact step: impacts / slip phases, then the peak deflection and peak force
    errors against the run at 1/256 of the automatic contact step (or how the run failed), and
    the least contact energy of all the c_T's runs."""
    head = " | ".join(f"{s:g} × the step" + (" (default)" if s == 1 else "") for s in SCALES)
    lines = [f"| c_T (N·s/m) | at 1/256: impacts / slips | {head} | least contact energy / input |",
             "| ---: | ---: |" + " ---: |" * len(SCALES) + " ---: |"]  # fmt: skip
    for c_t, impacts, slips, least, cells in rows:
        text = [f"{n} / {s}: {pct(d)}, {pct(f)}" if f is not None else f"{n} / {s}: {d}" for n, s, d, f, _ in cells]
        lowest = min([least] + [e for *_, e in cells if e is not None])
        lines.append(f"| {c_t:g} | {impacts} / {slips} | " + " | ".join(text) + f" | {lowest:.2g} |")
    return ("\n".join(lines) + "\n\nEach cell: impacts / slip phases: the largest relative error of any peak "
            "interstorey deflection, and of the peak impact force, against the run at 1/256 of the automatic "
            "contact step. The last column: the least the contacts' energy account held at any output instant of "
            "any of the row's runs, over the largest input energy (below zero, the contacts would have given out "
            "energy they were not given). Written by `python docs/kobe_dashpot.py`.\n")  # fmt: skip


if __name__ == "__main__":
    main()
