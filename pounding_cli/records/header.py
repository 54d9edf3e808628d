"""What a record file says about itself: station, event, component azimuth, as plain JSON values.

Read from the obspy trace header (``stats``) that each reader fills: pound's AT2 and COSMOS
readers (``stats.at2``, ``stats.cosmos``), obspy's K-NET reader (``stats.knet``) and SAC
(``stats.sac``). Only what the file holds is reported; nothing is guessed. ``azimuth`` is
in degrees clockwise from north (pound's convention, docs/theory.md §5) and appears only
when the file gives a horizontal direction.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from obspy import Trace

SAC_UNSET = -12345.0
"""SAC's value for a header field that is not set."""

_KNET_DIRECTIONS = {"N-S": 0.0, "NS": 0.0, "E-W": 90.0, "EW": 90.0}


def file_header(trace: Trace) -> dict[str, Any]:
    """The record's description from its trace header (JSON-ready: str, float, int, bool)."""
    stats = trace.stats
    out: dict[str, Any] = {"format": str(stats.get("_format", ""))}
    for key in ("network", "station", "location", "channel"):
        if stats.get(key):
            out[key] = str(stats[key])
    out["start_time"] = str(stats.starttime)  # AT2 and COSMOS without a UTC time remove it
    for reader in (_at2, _cosmos, _knet, _sac):
        out.update(reader(stats))
    return {k: v for k, v in out.items() if v not in (None, "")}


def _at2(stats: Any) -> dict[str, Any]:
    info = stats.get("at2")
    if info is None:
        return {}
    from pounding_cli.records.at2.core import _angle

    angle = _angle(str(info.component).strip().upper())
    return {
        "title": info.title,
        "event": info.event,
        "date": info.date,
        "station_name": info.station,
        "component": info.component,
        "azimuth": None if angle is None else angle % 360.0,
        "start_time": None,
    }


def _cosmos(stats: Any) -> dict[str, Any]:
    info = stats.get("cosmos")
    if info is None:
        return {}
    azimuth = info.azimuth
    return {
        "volume": info.volume,
        "processing": info.processing,
        "channel_number": info.channel_number,
        "orientation": info.orientation,
        "azimuth": float(azimuth) if isinstance(azimuth, (int, float)) else None,
        "station_name": info.station_name,
        "latitude": info.latitude,
        "longitude": info.longitude,
        "start_time": str(stats.starttime) if info.starttime_in_file else None,
        "start_time_text": info.start_time_text,
    }


def _knet(stats: Any) -> dict[str, Any]:
    info = stats.get("knet")
    if info is None:
        return {}
    direction = str(stats.get("channel", "")).upper()
    return {
        "origin_time": str(info.get("evot")) if info.get("evot") is not None else None,
        "event_latitude": info.get("evla"),
        "event_longitude": info.get("evlo"),
        "event_depth_km": info.get("evdp"),
        "magnitude": info.get("mag"),
        "latitude": info.get("stla"),
        "longitude": info.get("stlo"),
        "peak_in_header_gal": info.get("accmax"),
        "azimuth": _KNET_DIRECTIONS.get(direction.rstrip("0123456789")),
    }


def _sac(stats: Any) -> dict[str, Any]:
    info = stats.get("sac")
    if info is None:
        return {}

    def value(key: str) -> Any:
        v = info.get(key)
        if isinstance(v, float) and (v == SAC_UNSET or not math.isfinite(v)):
            return None
        if isinstance(v, str) and v.strip() in ("", "-12345"):
            return None
        return v.strip() if isinstance(v, str) else v

    horizontal = value("cmpinc") in (None, 90.0)
    azimuth = value("cmpaz")
    return {
        "event": value("kevnm"),
        "magnitude": value("mag"),
        "latitude": value("stla"),
        "longitude": value("stlo"),
        "azimuth": float(azimuth) % 360.0 if azimuth is not None and horizontal else None,
    }
