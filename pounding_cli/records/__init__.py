"""Ground-motion records: read an accelerogram file into an :class:`Accelerogram` in m/s².

``read_accelerogram`` reads whatever obspy reads (MiniSEED, SAC, ...) and plain
text (one value per line with a given ``dt``, or ``time value`` columns).
obspy is imported only when a file is read, not when this package is imported.
"""

from pounding_cli.records.read import UNIT_FACTORS, Accelerogram, read_accelerogram

__all__ = ["UNIT_FACTORS", "Accelerogram", "read_accelerogram"]
