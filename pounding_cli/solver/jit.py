"""The decorators of pound's compiled kernels: `kernel`, and `phase` for the named phases of
a kernel (inlined by LLVM), with `INTERNAL` for kernels only compiled code calls.

`kernel` is numba's njit with:
- cache=True: compiled once per installation (see kernel_cache for keeping it fresh);
- _nrt=False: no reference counting of arrays. The kernels allocate nothing, so numba's
  runtime has nothing to track, but with it enabled every call that passes arrays pays
  atomic increments and decrements: the contact phase of a step with three idle pairs cost
  1.5 µs with them and 0.01–0.3 µs without (measured in a 10⁶-call loop). The option is
  numba's own (leading underscore); it is set here only, should it ever change.
- error_model="numpy": a division never raises (every one is guarded anyway);
- forceinline=False, stated so that no kernel inherits a phase's.

Dense products (the exact propagator, the storey stiffness, the CDM's block solve) take
`fastmath=REASSOCIATE`: LLVM may reorder their sums and fuse multiply-adds, which lets it
vectorise the dot products. Results then differ from strictly sequential summation in the
last bits, identically from run to run on one machine. No other fast-math flag is set: NaN
and infinity keep their meaning, on which the divergence checks rely. Which CPU's vector
instructions LLVM may use is fixed (cpu_target), so that these last bits are the same on every
machine that runs them.
"""

from __future__ import annotations

from numba import njit
from numba.core import config

config.reload_config()  # the CPU target pound's import chose (cpu_target), should numba have been imported before it

REASSOCIATE = {"reassoc", "contract"}
"""fast-math flags for dense sums: reorder and fuse, nothing else."""


def kernel(*args, **options):
    """njit(cache=True, _nrt=False, error_model="numpy", forceinline=False, **options).

    forceinline is set explicitly so that a kernel never inherits it from a phase that calls
    it (numba passes it down to the callees it compiles)."""
    settings = {"cache": True, "_nrt": False, "error_model": "numpy", "forceinline": False, **options}
    if args and callable(args[0]):
        return njit(**settings)(args[0])
    return njit(*args, **settings)


INTERNAL = {"no_cpython_wrapper": True, "no_cfunc_wrapper": True}
"""Options of a kernel called from compiled code only: no Python wrapper, whose code to unpack
every array of every record it takes costs more to compile than many a kernel itself."""


def phase(function):
    """A named phase of a kernel (a step of the time loop, say): compiled once as a kernel of
    its own and inlined by LLVM into its caller (forceinline: LLVM's alwaysinline), so that it
    costs no call at all, whatever records it takes. It is never called from Python, so it
    gets no Python wrapper, whose code to unpack every array of every record would cost more
    to compile than the phase itself. (numba's own inline="always" inlines earlier, on numba's
    IR, at every call site: measured on the time loop, that made a cold compile 20–27 % longer
    than the same code written out in one function.)"""
    return kernel(forceinline=True, **INTERNAL)(function)
