"""
pounding_cli.records.cosmos - CSMIP / COSMOS V1 and V2 text read support for ObsPy
==================================================================================

Reads the strong-motion text files written by the California Strong Motion
Instrumentation Program (CSMIP, California Geological Survey) processing and
distributed by CESMD, COSMOS and USGS: Volume 1 (``.V1``, ``.RAW``, "Uncorrected
Accelerogram Data") and Volume 2 (``.V2``, "Corrected accelerogram"). Once pound is
installed the format is registered with ObsPy under the name ``COSMOS`` (entry points
in ``pyproject.toml``), so ``obspy.read("CICCC.RAW")`` finds it without a ``format``
argument, and so does pound's ``read_accelerogram``.

Not read here: the "COSMOS Strong-Motion Data Format" v1.20 (first line
``Corrected acceleration    (Format v01.20 with 13 text lines)``, one channel per
file, ``(10I8)`` / ``(5F15.6)`` headers), the SMC format (``2 CORRECTED ACCELEROGRAM``)
and GeoNet's V1A/V2A files. They are different layouts; detection says False on them.

File layout
-----------

A file holds one or more channels one after another. Each channel has:

1. a text header. Its first line starts with ``Uncorrected Accelerogram`` (V1) or
   ``Corrected accelerogram`` (V2). The reader takes from it, wherever they appear:
   ``Start time:  7/06/19, 03:19:37.0 UTC (GPS)`` (two-digit years 70-99 are 19yy,
   00-69 are 20yy), ``Chan  1:  90 Deg`` or ``Chan  3:  Up``, a SEED-like record id
   such as ``38457511.CI.CCC.--.HN`` (network, station, location), ``Station Id. CCC``
   or ``Station No. 89146`` with the coordinates ``35.525N, 117.365W`` and, on the
   next line, the station name;
2. an integer header (``16i5``) and a real header (``8f10``), which are skipped;
3. one data block (V1: acceleration) or three (V2: acceleration, velocity and
   displacement), each a data-count line followed by the values::

       35430 Accelerogram points at 100 pts/sec in units of g.       Format: (8f9.6)
       12000 points of accel data equally spaced at  .005 sec, in cm/sec2. (8f10.6)
       12000 points of veloc data equally spaced at  .005 sec, in cm/sec.  (8f10.7)
       12000 points of displ data equally spaced at  .005 sec, in cm.      (8f10.7)

   The values are read by the Fortran format given (``8f9.6``: 8 values per line,
   9 columns each), by column and not by splitting on white space, because
   neighbouring values can touch (``1.171726-12.626200``);
4. an end line starting with ``/&`` (optional after the last channel).

Channels may have different lengths. Windows (CRLF) line endings are accepted.

What is returned
----------------

A :class:`~obspy.core.stream.Stream` with one trace per channel (acceleration only by
default; see ``quantities`` below), in file order:

- ``data``: float64 in SI units converted from the file's units: acceleration in
  **m/s²** (g x 9.80665, cm/s² x 0.01), velocity in m/s, displacement in m.
  ``stats.cosmos.units_in_file``, ``stats.cosmos.factor`` and ``stats.cosmos.units``
  say which; ``stats.calib`` stays 1. Callers that apply their own unit factor
  (pound's ``read_accelerogram(..., units=...)``) must therefore say ``units="m/s2"``.
  V1 data are uncorrected (``stats.cosmos.processing``): remove the mean or baseline
  and filter before use;
- ``starttime``: the header's start time when it is given in UTC (or GMT);
  otherwise 1970-01-01T00:00:00 and ``stats.cosmos.starttime_in_file`` is False.
  The time as written is ``stats.cosmos.start_time_text``, the clock quality (``GPS``)
  ``stats.cosmos.time_quality``;
- ``delta``: from ``pts/sec`` (V1) or ``equally spaced at ... sec`` (V2);
- ``network``, ``station``, ``location``: from the record id when there is one,
  otherwise network and location are empty and the station is the ``Station Id.`` /
  ``Station No.`` code (at most 5 characters);
- ``channel``: band code from the sampling rate (``H`` from 80 Hz up to 250 Hz, ``B``
  from 10 Hz, ``C``/``G`` above 250 / 1000 Hz, ``M``/``L`` below 10 / 1 Hz), then an
  instrument code telling the quantity: ``N`` acceleration (SEED's accelerometer
  code), ``V`` velocity, ``D`` displacement (these two are pound's own convention:
  SEED has no code for quantities integrated from an accelerometer), then the
  orientation: azimuth 360 (or 0) -> ``N``, 90 -> ``E``, ``Up``/``Down`` -> ``Z``, any
  other azimuth -> ``1`` if nearer the north-south axis, else ``2``;
  header without an orientation -> ``1``. So CI.CCC gives ``HNE``, ``HNN``, ``HNZ``.
  If two traces of a file would get the same id (a building array with several
  sensors along the same axis), the location of every trace of that file is set to
  the two-digit channel number (``01``, ``02``, ...);
- ``stats.cosmos``: ``volume`` (1 or 2), ``processing``, ``channel_number``,
  ``azimuth`` (degrees clockwise from north as written, e.g. ``90.0``, ``360.0``; the
  string ``"Up"`` or ``"Down"`` for a vertical channel; None if not given), ``dip``
  (SEED convention: 0 horizontal, -90 up, 90 down), ``orientation`` (as written),
  ``quantity``, ``units_in_file``, ``units``, ``factor``, ``starttime_in_file``,
  ``start_time_text``, ``time_quality``, ``seed_id``, ``station_name``, ``latitude``,
  ``longitude`` (degrees, north and east positive), ``header_line`` and ``data_line``
  (1-based lines of the channel's first line and of the block's data-count line).

Options: ``quantities`` chooses what a V2 file gives: ``"acceleration"`` (default),
``"velocity"``, ``"displacement"``, a list of them or ``"all"`` - e.g.
``obspy.read("x.V2", quantities="all")``. ``headonly=True`` returns the headers
(``npts`` included) without converting the values.

Errors
------

A file that is not valid raises :class:`ValueError` naming the file and the line (and
the columns of a bad value): a channel that does not start with the expected line, a
malformed data-count line (with the form expected), unknown units, a value that is
not a number, fewer data lines than the count announces (file truncated, or another
header where data were expected) and more values than announced. Detection
(``_is_cosmos``) reads the first 8 KB only: the first non-blank line must start with
``Uncorrected Accelerogram`` / ``Corrected accelerogram`` and the 8 KB must hold a
data-count line or the word ``CSMIP``.

Example
-------

>>> import obspy                                                      # doctest: +SKIP
>>> st = obspy.read("CICCC.RAW")                                      # doctest: +SKIP
>>> [(tr.id, tr.stats.npts, tr.stats.cosmos.azimuth) for tr in st]    # doctest: +SKIP
[('CI.CCC..HNE', 35430, 90.0), ('CI.CCC..HNN', 35402, 360.0), ('CI.CCC..HNZ', 35406, 'Up')]
"""
