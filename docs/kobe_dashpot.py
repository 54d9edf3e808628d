"""The Kobe example with a tangential dashpot: how the stick–slip switching and the peaks converge
as the contact step shrinks (quoted in docs/bench.md, "A tangential dashpot").

    python docs/kobe_dashpot.py

The paper's model (μ_s = 0.8, μ_k = 0.6, no dashpot in either direction of its friction) with
`contact.damping_tangential` c_T = 0, 2·10³, 2·10⁴ and 2·10⁵ N·s/m: the hybrid integrator at 1,
1/4, 1/16 and 1/64 × the automatic contact step against the hybrid at 1/256 of it. For each,
the impacts, the slip phases of all impacts together (the impact log's `slips`), and the
largest relative error of any peak interstorey deflection and of the peak impact force (bench's
metrics, pounding_cli.bench.metrics). Needs the Kobe record in ../shared/records (see
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
        cells = []
        for scale in SCALES:
            result = run(doc, scale)
            errors = compare(result, reference)
            slips = int(result.contact.events["slips"].sum())
            cells.append((result.contact.impact_count, slips, errors.peak_deflection, errors.peak_force))
            print(f"c_T = {c_t:g}, {scale:g} × the step: {cells[-1]}", flush=True)
        rows.append((c_t, reference.contact.impact_count, int(reference.contact.events["slips"].sum()), cells))
    OUT.write_text(markdown(rows), encoding="utf-8")
    print(f"wrote {OUT}")


def markdown(rows: list) -> str:
    """Per c_T and contact step: impacts / slip phases, then the peak deflection and peak force
    errors against the run at 1/256 of the automatic contact step."""
    head = " | ".join(f"{s:g} × the step" + (" (default)" if s == 1 else "") for s in SCALES)
    lines = [f"| c_T (N·s/m) | at 1/256: impacts / slips | {head} |", "| ---: | ---: |" + " ---: |" * len(SCALES)]
    for c_t, impacts, slips, cells in rows:
        text = [f"{n} / {s}: {pct(d)}, {pct(f)}" for n, s, d, f in cells]
        lines.append(f"| {c_t:g} | {impacts} / {slips} | " + " | ".join(text) + " |")
    return ("\n".join(lines) + "\n\nEach cell: impacts / slip phases: the largest relative error of any peak "
            "interstorey deflection, and of the peak impact force, against the run at 1/256 of the automatic "
            "contact step. Written by `python docs/kobe_dashpot.py`.\n")  # fmt: skip


if __name__ == "__main__":
    main()
