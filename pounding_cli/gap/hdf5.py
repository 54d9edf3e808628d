"""pound gap's HDF5 file: the required separation of every candidate pair, under /gap.

    /                 attrs: pound_version, input_sha256, model (resolved, JSON), units = "SI",
                      status = "complete", content = "pound gap"
    /gap              attrs: sample_interval_s, refine_tolerance_s, governing (row of /gap/pairs
                      with the least margin; −1 without pairs), method
    /gap/time         (nt,) s: the samples of the contact-free run
    /gap/approach     (nt, n_pairs) m: clear distance at rest + σ*(t), the gap each pair needs
                      at each sample (required = its maximum, refined between samples)
    /gap/pairs        table, one row per candidate pair: body_a, floor_a, body_b, floor_b,
                      storey_b, kind, elevation, xi, clear_distance, direction_x, direction_y,
                      required, time, margin, u_a, u_b, rho, abs, srss, ddc, simulated

Lengths in m, times in s; each dataset carries `units`. Written atomically (atomic.py).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import __version__
from ..atomic import atomic_path, hdf5_writer
from .required import REFINE_TOL, GapResult

FIELDS = [("body_a", object, ""), ("floor_a", np.int64, ""), ("body_b", object, ""), ("floor_b", np.int64, ""),
          ("storey_b", np.int64, ""), ("kind", object, ""), ("elevation", np.float64, "m"), ("xi", np.float64, ""),
          ("clear_distance", np.float64, "m"), ("direction_x", np.float64, ""), ("direction_y", np.float64, ""),
          ("required", np.float64, "m"), ("time", np.float64, "s"), ("margin", np.float64, "m"),
          ("u_a", np.float64, "m"), ("u_b", np.float64, "m"), ("rho", np.float64, ""), ("abs", np.float64, "m"),
          ("srss", np.float64, "m"), ("ddc", np.float64, "m"), ("simulated", np.bool_, "")]  # fmt: skip
"""(column, type, unit) of /gap/pairs."""


def pair_table(result: GapResult) -> np.ndarray:
    """/gap/pairs as a structured array (strings as variable-length UTF-8)."""
    import h5py

    text = h5py.string_dtype()
    dtype = np.dtype([(name, text if kind is object else kind) for name, kind, _ in FIELDS])
    rows = []
    for p in result.pairs:
        row = {**p.__dict__, "direction_x": p.direction[0], "direction_y": p.direction[1]}
        rows.append(tuple(row[name] for name, _, _ in FIELDS))
    return np.array(rows, dtype=dtype)


def read_pairs(f) -> list[dict[str, object]]:  # type: ignore[no-untyped-def]
    """The rows of /gap/pairs of an open gap file, as dicts of Python values."""
    table = f["gap/pairs"][()]
    out = []
    for row in table:
        values = {}
        for name, kind, _ in FIELDS:
            v = row[name]
            values[name] = v.decode() if isinstance(v, bytes) else (str(v) if kind is object else v.item())
        out.append(values)
    return out


def write_gap(result: GapResult, path: str | Path, attrs: dict[str, object] | None = None) -> Path:
    """Write pound gap's file to `path` atomically, with `attrs` added to the root's
    attributes (a suite's case adds its own: suites.gap_cases); returns the path."""
    path = Path(path)
    run = result.run
    with atomic_path(path) as tmp:
        with hdf5_writer(tmp, track_order=True) as f:
            f.attrs.update(pound_version=__version__, input_sha256=run.input_sha256, model=run.model_json, units="SI",
                           status="complete", content="pound gap")  # fmt: skip
            f.attrs.update(attrs or {})
            g = f.create_group("gap")
            g.attrs.update(sample_interval_s=result.sample, refine_tolerance_s=REFINE_TOL,
                           governing=-1 if result.governing is None else result.governing,
                           method="contact off; ray cast on the Minkowski difference of the moving outlines along the "
                                  "direction of the clear distance at rest, at every sample, crests refined on the "
                                  "quintic Hermite interpolant of the motion")  # fmt: skip
            g.create_dataset("time", data=result.time).attrs["units"] = "s"
            approach = g.create_dataset("approach", data=result.approach)
            approach.attrs.update(units="m", columns="one per row of /gap/pairs")
            pairs = g.create_dataset("pairs", data=pair_table(result))
            pairs.attrs["units"] = ", ".join(f"{name}: {unit}" for name, _, unit in FIELDS if unit)
    return path
