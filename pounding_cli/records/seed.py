"""SEED channel naming shared by pound's readers."""

from __future__ import annotations


def band_code(sampling_rate: float) -> str:
    """SEED band code for a strong-motion sensor sampled at ``sampling_rate`` Hz."""
    for limit, code in ((1000.0, "G"), (250.0, "C"), (80.0, "H"), (10.0, "B"), (1.0, "M")):
        if sampling_rate >= limit - 1e-9:
            return code
    return "L"
