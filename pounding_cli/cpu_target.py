"""The CPU that pound's compiled code is generated for: one fixed target, so that a run gives
the same bits on every machine that can run that target.

numba compiles for the host CPU unless told otherwise, and the dense products of the time loop
may be reordered (solver/jit.py, fast-math `reassoc`): on a CPU with AVX-512 (AMD Zen 4 and 5,
Intel since Skylake-SP) LLVM sums them eight at a time, on one with AVX2 four at a time. The
results then differ in their last bits, and a contact problem grows such differences into
others: the isolated moat example of docs/inelastic.md counted 142 impacts of its base slab on
the wall on a Zen 3 and 143 on a Zen 5 (every other result of the page agreeing), a transcript
showed other digits, and the bit-for-bit pins (tests/test_bit_for_bit.py) could be compared on
one CPU family only. OpenBLAS, which numpy's and scipy's linear algebra use, likewise picks
its kernels by CPU, and numpy its own loops (its exp, sin, power... on AVX-512 are other
approximations than on AVX2: the slab–storey finite-element table of docs/validation.md read
4.3e-11 for 4.4e-11 on the Zen 5 until they were disabled).

On x86-64 machines with the x86-64-v3 instruction set (AVX2, FMA, BMI1 and 2, F16C, LZCNT,
MOVBE: every Intel core since Haswell, 2013, every AMD core since Zen, 2017) pound therefore
has numba compile for LLVM's "haswell", OpenBLAS use its Haswell kernels and numpy none of
its loops for AVX-512 (NPY_DISABLE_CPU_FEATURES). Measured on a
Zen 5 (the 100-building block, `pound run inputs/city_block.toml`, solver time, two runs
each): 11.26 and 11.35 s for the host (AVX-512), 10.94 and 11.15 s for "haswell"; the Zen 3
pins of all seven scenes of tests/test_bit_for_bit.py hold bit for bit on the Zen 5 with it.
On other machines (no AVX2, another architecture, another system than Linux, where the CPU's
instructions are not read here) numba compiles for the host as before.

A NUMBA_CPU_NAME, OPENBLAS_CORETYPE or NPY_DISABLE_CPU_FEATURES the user has set is left as
it is (NUMBA_CPU_NAME leaves all three). The choice must be
made before numba compiles or loads its first kernel and before OpenBLAS loads (when numpy is
first imported): `pounding_cli/__init__` makes it, which any import of pound runs first.
"""

from __future__ import annotations

import os
import platform
from collections.abc import MutableMapping
from pathlib import Path

PORTABLE_CPU = "haswell"
"""LLVM's name of the x86-64-v3 CPU that pound compiles for where the host can run it."""

X86_64_V3 = frozenset({"avx", "avx2", "bmi1", "bmi2", "f16c", "fma", "abm", "movbe"})
"""The instructions (their flags in /proc/cpuinfo; `abm` is LZCNT) that code compiled for
"haswell" may use beyond x86-64's baseline."""


NUMPY_AVX512 = {"new": "X86_V4 AVX512_ICL AVX512_SPR",
                "old": "AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL AVX512_SPR"}  # fmt: skip
"""numpy's names of its loops beyond x86-64-v3: grouped by x86-64 level since numpy 2.4
("new"), one per AVX-512 extension before ("old")."""


def runs_x86_64_v3(cpuinfo: str) -> bool:
    """Whether /proc/cpuinfo's first processor lists every x86-64-v3 instruction."""
    for line in cpuinfo.splitlines():
        if line.startswith("flags"):
            return X86_64_V3 <= set(line.partition(":")[2].split())
    return False


def pin_portable_target(environ: MutableMapping[str, str] = os.environ,
                        cpuinfo: Path = Path("/proc/cpuinfo")) -> bool:  # fmt: skip
    """Have numba compile for PORTABLE_CPU, OpenBLAS use its Haswell kernels and numpy none of
    its AVX-512 loops, where the host runs x86-64-v3 and the user has not chosen otherwise.
    True where the target is pinned."""
    if "NUMBA_CPU_NAME" in environ or platform.machine() not in ("x86_64", "AMD64"):
        return False
    try:
        if not runs_x86_64_v3(cpuinfo.read_text(encoding="utf-8", errors="replace")):
            return False
    except OSError:  # not Linux: its CPU is not read here
        return False
    environ["NUMBA_CPU_NAME"] = PORTABLE_CPU
    environ["NUMBA_CPU_FEATURES"] = ""  # the CPU's own instructions, none of the host's others
    environ.setdefault("OPENBLAS_CORETYPE", "Haswell")
    environ.setdefault("NPY_DISABLE_CPU_FEATURES", NUMPY_AVX512[_numpy_names()])
    return True


def _numpy_names() -> str:
    """Which of numpy's names of CPU features the installed numpy knows (read from its
    metadata: numpy itself must not be imported before its features are chosen)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        major, minor = (int(part) for part in version("numpy").split(".")[:2])
    except (PackageNotFoundError, ValueError):
        return "new"
    return "new" if (major, minor) >= (2, 4) else "old"


def compile_target() -> str:
    """The CPU numba generates code for in this process (its name as LLVM spells it)."""
    from numba.core import config

    if config.CPU_NAME:
        return config.CPU_NAME
    import llvmlite.binding

    return llvmlite.binding.get_host_cpu_name()
