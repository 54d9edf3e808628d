"""The one decorator of pound's compiled kernels.

`kernel` is numba's njit with:
- cache=True: compiled once per installation (see kernel_cache for keeping it fresh);
- _nrt=False: no reference counting of arrays. The kernels allocate nothing, so numba's
  runtime has nothing to track, but with it enabled every call that passes arrays pays
  atomic increments and decrements: the contact phase of a step with three idle pairs cost
  1.5 µs with them and 0.01–0.3 µs without (measured in a 10⁶-call loop). The option is
  numba's own (leading underscore); it is set here only, should it ever change.
- error_model="numpy": a division never raises (every one is guarded anyway).

Dense products (the exact propagator, the storey stiffness, the CDM's block solve) take
`fastmath=REASSOCIATE`: LLVM may reorder their sums and fuse multiply-adds, which lets it
vectorise the dot products. Results then differ from strictly sequential summation in the
last bits, identically from run to run on one machine. No other fast-math flag is set: NaN
and infinity keep their meaning, on which the divergence checks rely.
"""

from __future__ import annotations

from numba import njit

REASSOCIATE = {"reassoc", "contract"}
"""fast-math flags for dense sums: reorder and fuse, nothing else."""


def kernel(*args, **options):
    """njit(cache=True, _nrt=False, error_model="numpy", **options)."""
    settings = {"cache": True, "_nrt": False, "error_model": "numpy", **options}
    if args and callable(args[0]):
        return njit(**settings)(args[0])
    return njit(*args, **settings)
