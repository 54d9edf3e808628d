"""Processing of one record component with obspy, in a fixed order.

The order (each step only when the record's ``processing`` asks for it):

1. ``demean``: remove the mean (obspy ``detrend("demean")``);
2. ``detrend``: remove the least-squares straight line (``detrend("linear")``);
3. ``taper``: cosine taper over that fraction of the length at each end
   (``taper(max_percentage=..., type="cosine")``), so the filter starts and ends at rest;
4. ``filter``: Butterworth band-pass (both corners), high-pass (``freqmin`` only) or
   low-pass (``freqmax`` only), ``corners`` poles, forwards and backwards when
   ``zerophase`` (``filter("bandpass" | "highpass" | "lowpass", ...)``);
5. ``window``: keep ``start``..``end`` s after the first sample, each end at the nearest
   sample (``trim(..., nearest_sample=True)``).

Filtering before windowing keeps the filter's start-up transient out of the window. The
steps after these, which concern both components together (common Δt, common span,
scaling), are in :mod:`pounding_cli.records.combine`.

Problems are :class:`ProcessingError` naming the field of ``processing`` at fault.
"""

from __future__ import annotations

import numpy as np

from pounding_cli.errors import RecordReadError
from pounding_cli.model.record import Processing
from pounding_cli.records.read import Accelerogram, with_values

NYQUIST_MARGIN = 1e-6
"""obspy turns a band-pass whose freqmax is within this fraction of the Nyquist frequency
into a high-pass, with a warning; pound refuses such a freqmax instead."""


class ProcessingError(RecordReadError):
    """A processing setting does not suit a component; ``field`` is under ``processing``."""


def process(record: Accelerogram, processing: Processing) -> Accelerogram:
    """The component after steps 1-5 (m/s², same Δt); `record` itself if none applies."""
    if not (processing.demean or processing.detrend or processing.taper or processing.filter
            or processing.window):  # fmt: skip
        return record
    from obspy import Trace  # slow import: only when a record is processed

    trace = Trace(data=np.array(record.acceleration, dtype=np.float64), header={"delta": record.dt})
    if processing.demean:
        trace.detrend("demean")
    if processing.detrend:
        trace.detrend("linear")
    if processing.taper:
        trace.taper(max_percentage=processing.taper, type="cosine")
    if processing.filter is not None:
        _filter(trace, processing, record)
    if processing.window is not None:
        _window(trace, processing, record)
    return with_values(record, trace.data, note="processed")


def _filter(trace: object, processing: Processing, record: Accelerogram) -> None:
    """Apply the Butterworth filter; refuse corners at or above the Nyquist frequency."""
    f = processing.filter
    nyquist = 0.5 / record.dt
    for name, value in (("freqmin", f.freqmin), ("freqmax", f.freqmax)):
        if value is not None and value >= nyquist * (1.0 - NYQUIST_MARGIN):
            raise ProcessingError(
                f"{record.source}: filter.{name} = {value:g} Hz is not below the Nyquist frequency "
                f"{nyquist:g} Hz of the record (Δt = {record.dt:g} s)",
                field=f"filter.{name}",
            )
    options = {"corners": f.corners, "zerophase": f.zerophase}
    if f.freqmin is not None and f.freqmax is not None:
        trace.filter("bandpass", freqmin=f.freqmin, freqmax=f.freqmax, **options)
    elif f.freqmin is not None:
        trace.filter("highpass", freq=f.freqmin, **options)
    else:
        trace.filter("lowpass", freq=f.freqmax, **options)


def _window(trace: object, processing: Processing, record: Accelerogram) -> None:
    """Cut to the window; refuse a window outside the record or shorter than two samples."""
    w = processing.window
    duration = record.duration
    end = duration if w.end is None else w.end
    if w.start >= duration or end > duration + 0.5 * record.dt:
        raise ProcessingError(
            f"{record.source}: window {w.start:g}-{end:g} s is not inside the record, which lasts "
            f"{duration:g} s from its first sample",
            field="window.end" if w.start < duration else "window.start",
        )
    first = trace.stats.starttime
    trace.trim(first + w.start, first + end, nearest_sample=True)
    if trace.stats.npts < 2:
        raise ProcessingError(
            f"{record.source}: window {w.start:g}-{end:g} s holds {trace.stats.npts} sample(s) "
            f"at Δt = {record.dt:g} s; a record needs at least two",
            field="window",
        )
