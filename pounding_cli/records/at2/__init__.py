"""
pounding_cli.records.at2 - PEER NGA ``.AT2`` read support for ObsPy
===================================================================

Reads the acceleration files of the PEER NGA ground-motion databases (NGA-West1,
NGA-West2, ...), one component per file. Once pound is installed, the format is
registered with ObsPy under the name ``AT2`` (entry points in ``pyproject.toml``),
so ``obspy.read("RSN1106_KOBE_KJM000.AT2")`` finds it without a ``format`` argument,
and so does pound's ``read_accelerogram``.

File layout
-----------

Four header lines, then the values::

    PEER NGA STRONG MOTION DATABASE RECORD
    Kobe Japan, 1/16/1995, KJMA, 0
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=   7500, DT=   .0200 SEC,
      -.1416764E-03  -.1418977E-03  -.1421037E-03  -.1423125E-03  -.1425214E-03
      ...

1. a title (kept as ``stats.at2.title``);
2. ``event, date, station, component``, separated by commas. The last field is the
   component, the one before it the station; with four or more fields the first
   two are the event and the date. A line with fewer fields is accepted;
3. ``ACCELERATION TIME SERIES IN UNITS OF <units>`` (older files say ``TIME HISTORY``).
   Units ``G`` (the usual), ``CM/S/S``, ``CM/S2``, ``GAL`` or ``M/S2`` are accepted;
4. the number of points and the time step, either in the NGA-West2 form
   ``NPTS=   7500, DT=   .0200 SEC,`` (spaces around ``=`` and ``,`` are allowed:
   hand-edited files read ``NPTS =   7500 , DT =   .020 SEC ,``) or in the older
   form ``7500    .0200    NPTS, DT``.

The values follow, separated by white space, any number per line (PEER writes 5).
Their count must equal NPTS. Windows (CRLF) line endings are accepted.
PEER velocity and displacement files (``.VT2``, ``.DT2``) are not read: their third
line names velocity or displacement, and the reader says so.

What is returned
----------------

A :class:`~obspy.core.stream.Stream` with one trace:

- ``data``: float64 acceleration in **m/s²**, converted from the file's units
  (g x 9.80665, or cm/s² x 0.01). ``stats.at2.units_in_file`` names the file's
  units, ``stats.at2.factor`` the factor applied, ``stats.at2.units`` is ``"m/s2"``;
  ``stats.calib`` stays 1. Callers that apply their own unit factor (pound's
  ``read_accelerogram(..., units=...)``) must therefore say ``units="m/s2"``;
- ``delta``: DT (s); ``npts``: NPTS;
- ``starttime``: 1970-01-01T00:00:00 UTC, because an AT2 file holds no time of day
  (``stats.at2.starttime_in_file`` is False; the date of line 2, often the UTC date of
  the event, is kept as text in ``stats.at2.date``);
- ``network`` and ``location``: empty (the file names no network);
- ``station``: the station of line 2 reduced to a SEED code: upper-case letters and
  digits, at most 5 (``"KJMA"``); the full text is ``stats.at2.station``;
- ``channel``: band code from the sampling rate (``H`` from 80 Hz up, ``B`` from
  10 Hz to 80 Hz - so 50 Hz PEER records are ``BN?`` - and ``C``/``G`` above 250 /
  1000 Hz, ``M``/``L`` below 10 / 1 Hz), instrument code ``N`` (accelerometer), and an
  orientation code from the component: ``0``/``000``/``360`` -> ``N``, ``90``/``090``
  -> ``E``, ``UP``/``UD``/``V``/``VER``/``Z``/``DWN`` -> ``Z``; any other angle
  (``180``, ``270``, ``045``, ``N45E``...) -> ``1`` if it is nearer the north-south axis,
  ``2`` if nearer the east-west axis; a component that is not recognised -> ``1``.
  The component as written is always kept in ``stats.at2.component``, so a reversed
  polarity (``180``, ``270``, ``DWN``) can be told from it;
- ``stats.at2``: ``title``, ``event``, ``date``, ``station``, ``component``,
  ``units_in_file``, ``units``, ``factor``, ``starttime_in_file``.

``headonly=True`` returns the trace's header (``npts`` included) without reading the
values.

Errors
------

A file that is not valid AT2 raises :class:`ValueError` naming the file and the line:
a header line that does not have the expected form (with what was expected), unknown
units, a value that is not a number (its line), or a number of values different from
NPTS (a truncated file or a wrong header). Detection (``_is_at2``) reads the first
4 KB only; it accepts a text file whose third line is the units line or whose fourth
line names ``NPTS`` and ``DT``, so that a damaged AT2 file gets these messages rather
than "unknown format".

Example
-------

>>> import obspy                                                   # doctest: +SKIP
>>> st = obspy.read("RSN1106_KOBE_KJM000.AT2")                     # doctest: +SKIP
>>> tr = st[0]                                                     # doctest: +SKIP
>>> tr.id, tr.stats.delta, tr.stats.npts                           # doctest: +SKIP
('.KJMA..BNN', 0.02, 7500)
>>> abs(tr.data).max() / 9.80665                                   # doctest: +SKIP
0.8342...
"""
