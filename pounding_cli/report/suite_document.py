"""`pound report` on the result of `pound gap --suite` (OUTPUT/gap-suite.h5, or the folder):
the distribution of each pair's required separation over the suite, and the pounding
fragility plot (empirical and lognormal fit, suites.plot)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..errors import InputError
from .tables import TableSpec

RESULT = "gap-suite.h5"
CONTENT = "pound gap --suite"


def suite_file(path: Path) -> Path | None:
    """The suite result file that `path` is or holds, None if it is neither."""
    import h5py

    candidate = path / RESULT if path.is_dir() else path
    if not candidate.is_file():
        return None
    try:
        with h5py.File(candidate, "r") as f:
            return candidate if str(f.attrs.get("content", "")) == CONTENT else None
    except OSError:
        return None


def suite_document(path: Path) -> dict[str, Any]:
    """The report's JSON document: the suite, and per pair its statistics (m)."""
    from ..suites.hdf5 import read_gap_suite
    from ..suites.plot import pair_name

    data = read_gap_suite(path)
    pairs = []
    for row in data["pairs"]:
        values = {name: _plain(row[name]) for name in row.dtype.names}
        pairs.append({"pair": pair_name(row), **values})
    return {"file": str(path), "suite": data["suite"], "pairs": pairs}


def suite_tables(doc: dict[str, Any]) -> list[TableSpec]:
    """One table: per pair the gap, the required separation's θ, β, 84 %, and P(pound)."""
    mm = lambda v: "–" if v is None else f"{1e3 * v:.4g}"  # noqa: E731
    rows = [[p["pair"], mm(p["clear_distance"]), mm(p["required_median"]), "–" if p["required_beta"] is None
             else f"{p['required_beta']:.3f}", mm(p["required_p84"]), f"{p['p_pound_empirical']:.3f}",
             f"{p['p_pound_fit']:.3f}"] for p in doc["pairs"]]  # fmt: skip
    s = doc["suite"]
    title = (f"Suite {s['suite']} ({s['cases']} cases, scaling {s['scaling']['method']}): required separation, mm "
             "(lognormal θ, β, 84th percentile) and the probability of pounding at the gap as built")  # fmt: skip
    return [TableSpec(title, ["pair", "gap", "θ", "β", "84 %", "P records", "P fit"], rows, {1, 2, 3, 4, 5, 6})]


def write_fragility(path: Path, plots: Path, fmt: str) -> Path:
    """Draw the fragility plot of the suite file into the folder `plots`."""
    from ..suites.hdf5 import read_gap_suite
    from ..suites.plot import fragility_figure
    from .style import save_figure

    data = read_gap_suite(path)
    try:
        plots.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder ({exc.strerror})", file=plots) from None
    out = plots / f"fragility.{fmt}"
    title = f"pounding fragility under {data['suite']['suite']} (dotted: the gap as built)"
    save_figure(fragility_figure(data["pairs"], data["gap"], data["empirical"], data["fit"], title), out)
    return out


def _plain(value: Any) -> Any:
    if isinstance(value, bytes):
        return value.decode()
    value = value.item() if hasattr(value, "item") else value
    return None if isinstance(value, float) and not math.isfinite(value) else value


__all__ = ["suite_document", "suite_file", "suite_tables", "write_fragility"]
