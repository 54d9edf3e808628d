"""Ground-motion records: read, process and describe accelerograms.

- :func:`read_accelerogram` / :func:`read_accelerograms` (``read.py``): one trace, or every
  trace, of a file obspy reads (MiniSEED, SAC, K-NET, ... and pound's own plugins for PEER
  ``.AT2`` in ``at2/`` and CSMIP/COSMOS V1/V2 in ``cosmos/``) or of plain text, in m/s²;
- ``process.py`` and ``combine.py``: a record definition's processing (demean, detrend, taper,
  filter, window), common Δt and span, and scaling;
- ``inspect.py``, ``metrics.py``, ``spectrum.py``, ``summary.py``, ``plot.py``: what
  ``pound record`` prints and draws (``summary.describe_record`` is its Python API).

obspy is imported only when a file is read, not when this package is imported.
"""

from pounding_cli.records.read import UNIT_FACTORS, Accelerogram, read_accelerogram, read_accelerograms

__all__ = ["UNIT_FACTORS", "Accelerogram", "read_accelerogram", "read_accelerograms"]
