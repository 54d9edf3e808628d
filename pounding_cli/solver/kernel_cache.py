"""Keep numba's on-disk cache of the compiled kernels consistent with their source.

numba checks a cached kernel only against the file that defines it, so a kernel that
inlines code from another module (the contact kernel inlines the geometry kernel) would
keep stale machine code when only that other module changes, for instance after an
upgrade that leaves old cache files behind. Before any kernel is loaded, this compares a
hash of every solver source file with the one stamped in __pycache__ and, if they differ,
deletes the cached kernels so that numba compiles them afresh.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

HERE = Path(__file__).resolve().parent


def sources_digest() -> str:
    """sha256 over the solver package's Python sources, in name order."""
    h = hashlib.sha256()
    for path in sorted(HERE.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def drop_stale_kernels() -> None:
    """Delete cached kernels compiled from other sources (silently, if the folder is read-only)."""
    cache = HERE / "__pycache__"
    stamp = cache / "pound-kernels.sha256"
    digest = sources_digest()
    try:
        if stamp.read_text() == digest:
            return
    except OSError:
        pass
    try:
        for path in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            path.unlink()
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:
        pass
