"""`pound gap --suite`'s result file, OUTPUT/gap-suite.h5, group /gap_suite.

    /                      attrs: pound_version, input_sha256 (the base model's), model (its
                           resolved model, JSON), units = "SI", status = "complete" or
                           "failed: n of N cases", content = "pound gap --suite"
    /gap_suite             attrs: suite (JSON: name, title, orientations, scaling, period_s,
                           records, cases), fit = the lognormal fit's definition
    /gap_suite/cases       table, one row per case: case, record, orientation, factor, status,
                           file (its `pound gap` file, relative to OUTPUT)
    /gap_suite/required, /abs, /srss, /ddc
                           (n_cases, n_pairs) m: each case's required separation and code-style
                           estimates of each pair; NaN for a failed case
    /gap_suite/pairs       table, one row per pair: body_a, floor_a, body_b, floor_b, storey_b,
                           kind, elevation, xi, clear_distance, direction_x, direction_y; then
                           for q in required, abs, srss, ddc: q_median, q_beta, q_p84 (m, -, m);
                           n, n_positive; p_pound_empirical, p_pound_fit (at the clear distance)
    /gap_suite/fragility/gap        (ng,) m
    /gap_suite/fragility/empirical  (ng, n_pairs): fraction of cases whose required > gap
    /gap_suite/fragility/fit        (ng, n_pairs): the lognormal fit's probability

Written atomically (atomic.py).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..atomic import atomic_path, hdf5_writer
from .fragility import __doc__ as FIT_DOC
from .gap_suite import IDENTITY, QUANTITIES, GapSuiteResult

PAIR_UNITS = {"elevation": "m", "clear_distance": "m"}


def pair_table(result: GapSuiteResult) -> np.ndarray:
    """/gap_suite/pairs as a structured array."""
    import h5py

    names = list(IDENTITY) + [f"{q}_{s}" for q in QUANTITIES for s in ("median", "beta", "p84")]
    names += ["n", "n_positive", "p_pound_empirical", "p_pound_fit"]
    kinds = {"body_a": h5py.string_dtype(), "body_b": h5py.string_dtype(), "kind": h5py.string_dtype(),
             "floor_a": np.int64, "floor_b": np.int64, "storey_b": np.int64, "n": np.int64, "n_positive": np.int64}  # fmt: skip
    dtype = np.dtype([(n, kinds.get(n, np.float64)) for n in names])
    rows = []
    for p in result.pairs:
        flat = dict(p) | {f"{q}_{s}": p[q][s] for q in QUANTITIES for s in ("median", "beta", "p84")}
        flat |= {"n": p["required"]["n"], "n_positive": p["required"]["n_positive"]}
        rows.append(tuple(np.nan if flat[n] is None else flat[n] for n in names))
    return np.array(rows, dtype=dtype)


def case_table(result: GapSuiteResult) -> np.ndarray:
    import h5py

    text = h5py.string_dtype()
    dtype = np.dtype([("case", text), ("record", text), ("orientation", text), ("factor", np.float64),
                      ("status", text), ("file", text)])  # fmt: skip
    return np.array([(c["case"], c["record"], c["orientation"], c["factor"], c["status"], c["file"])
                     for c in result.cases], dtype=dtype)  # fmt: skip


def write_gap_suite(result: GapSuiteResult, path: Path, scene: Any) -> Path:
    """Write the suite's file atomically; `scene` is the base model's (its hash and model)."""
    from ..api import input_sha256, stored_json

    failed = len(result.failed)
    status = "complete" if not failed else f"failed: {failed} of {len(result.cases)} cases"
    with atomic_path(path) as tmp:
        with hdf5_writer(tmp, track_order=True) as f:
            f.attrs.update(pound_version=__version__, input_sha256=input_sha256(scene.loaded, scene.ground),
                           model=stored_json(scene.loaded.model), units="SI", status=status,
                           content="pound gap --suite")  # fmt: skip
            g = f.create_group("gap_suite")
            g.attrs.update(suite=json.dumps(result.suite.describe(), ensure_ascii=False), fit=FIT_DOC or "")
            g.create_dataset("cases", data=case_table(result)).attrs["units"] = "factor: -"
            for q in QUANTITIES:
                ds = g.create_dataset(q, data=result.values[q])
                ds.attrs.update(units="m", rows="one per row of /gap_suite/cases", columns="one per row of /gap_suite/pairs")
            pairs = g.create_dataset("pairs", data=pair_table(result))
            pairs.attrs["units"] = "elevation, clear_distance, *_median, *_p84: m; *_beta, p_*: -"
            fr = g.create_group("fragility")
            fr.create_dataset("gap", data=result.gaps).attrs["units"] = "m"
            fr.create_dataset("empirical", data=result.fragility_empirical).attrs["units"] = "-"
            fr.create_dataset("fit", data=result.fragility_fit).attrs["units"] = "-"
    return path


def read_gap_suite(path: str | Path) -> dict[str, Any]:
    """The fragility part of a suite file: {"pairs": structured rows, "gap", "empirical", "fit"}."""
    import h5py

    with h5py.File(path, "r") as f:
        g = f["gap_suite"]
        return {"suite": json.loads(g.attrs["suite"]), "pairs": g["pairs"][()], "gap": g["fragility/gap"][()],
                "empirical": g["fragility/empirical"][()], "fit": g["fragility/fit"][()],
                "required": g["required"][()]}  # fmt: skip
