"""pound fixes the CPU its code is generated for (pounding_cli.cpu_target), so that a run gives
the same bits on every x86-64-v3 machine. That the bits are then the pinned ones is
tests/test_bit_for_bit.py's; here: which machines are pinned, that a user's choice wins, and
that this process and a `pound` process really compile for the pinned CPU."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from pounding_cli import cpu_target
from pounding_cli.cpu_target import PORTABLE_CPU, X86_64_V3, compile_target, pin_portable_target, runs_x86_64_v3

ZEN3_FLAGS = ("fpu vme de pse tsc msr pae mce cx8 apic sep mtrr pge mca cmov pat pse36 clflush mmx fxsr sse sse2 ht "
              "syscall nx mmxext fxsr_opt pdpe1gb rdtscp lm constant_tsc rep_good nopl nonstop_tsc cpuid extd_apicid "
              "aperfmperf rapl pni pclmulqdq monitor ssse3 fma cx16 pcid sse4_1 sse4_2 x2apic movbe popcnt aes xsave "
              "avx f16c rdrand lahf_lm cmp_legacy svm extapic cr8_legacy abm sse4a misalignsse 3dnowprefetch osvw "
              "ibs skinit wdt tce topoext perfctr_core perfctr_nb bpext perfctr_llc mwaitx cpb cat_l3 cdp_l3 "
              "hw_pstate ssbd mba ibrs ibpb stibp vmmcall fsgsbase bmi1 avx2 smep bmi2 erms invpcid cqm rdt_a rdseed "
              "adx smap clflushopt clwb sha_ni xsaveopt xsavec xgetbv1 xsaves")  # fmt: skip
"""The flags line of an AMD EPYC 7763 (Zen 3), as Linux prints it."""


def cpuinfo(tmp_path: Path, flags: str) -> Path:
    path = tmp_path / "cpuinfo"
    path.write_text(f"processor\t: 0\nvendor_id\t: AuthenticAMD\nflags\t\t: {flags}\n\nprocessor\t: 1\n", encoding="utf-8")
    return path


def test_a_zen3_runs_x86_64_v3_and_a_cpu_without_avx2_does_not(tmp_path):
    assert runs_x86_64_v3(cpuinfo(tmp_path, ZEN3_FLAGS).read_text())
    for missing in sorted(X86_64_V3):  # each instruction is needed
        flags = " ".join(f for f in ZEN3_FLAGS.split() if f != missing)
        assert not runs_x86_64_v3(cpuinfo(tmp_path, flags).read_text()), missing
    assert not runs_x86_64_v3("processor : 0\n")  # no flags line: not known to run it


@pytest.fixture
def x86_64(monkeypatch):
    monkeypatch.setattr(cpu_target.platform, "machine", lambda: "x86_64")


def test_an_x86_64_v3_machine_compiles_for_haswell_with_haswells_blas_and_no_avx512_loops(tmp_path, x86_64):
    environ: dict[str, str] = {}
    assert pin_portable_target(environ, cpuinfo(tmp_path, ZEN3_FLAGS))
    assert environ["NUMBA_CPU_NAME"] == PORTABLE_CPU == "haswell"
    assert environ["NUMBA_CPU_FEATURES"] == ""  # haswell's own instructions: none of the host's AVX-512
    assert environ["OPENBLAS_CORETYPE"] == "Haswell"
    assert "AVX512" in environ["NPY_DISABLE_CPU_FEATURES"]


def test_a_users_choice_is_left_alone(tmp_path, x86_64):
    environ = {"NUMBA_CPU_NAME": "znver3"}
    assert not pin_portable_target(environ, cpuinfo(tmp_path, ZEN3_FLAGS))
    assert environ == {"NUMBA_CPU_NAME": "znver3"}  # nor BLAS nor numpy: the user compiles for the host they chose
    environ = {"OPENBLAS_CORETYPE": "Zen", "NPY_DISABLE_CPU_FEATURES": "X86_V4"}
    assert pin_portable_target(environ, cpuinfo(tmp_path, ZEN3_FLAGS))
    assert environ["OPENBLAS_CORETYPE"] == "Zen" and environ["NPY_DISABLE_CPU_FEATURES"] == "X86_V4"


def test_other_machines_compile_for_their_host(tmp_path, x86_64, monkeypatch):
    old = " ".join(f for f in ZEN3_FLAGS.split() if f != "avx2")  # a Sandy Bridge, say
    for environ, path in (({}, cpuinfo(tmp_path, old)), ({}, tmp_path / "absent")):  # no /proc/cpuinfo: not Linux
        assert not pin_portable_target(environ, path)
        assert environ == {}
    monkeypatch.setattr(cpu_target.platform, "machine", lambda: "aarch64")
    environ = {}
    assert not pin_portable_target(environ, cpuinfo(tmp_path, ZEN3_FLAGS)) and environ == {}


def test_numpys_names_for_its_avx512_loops_follow_its_version(monkeypatch):
    import importlib.metadata

    for version, names in (("2.4.6", "new"), ("2.10.0", "new"), ("2.3.5", "old"), ("1.26.4", "old"), ("3.0.0rc1", "new")):
        monkeypatch.setattr(importlib.metadata, "version", lambda _, v=version: v)
        assert cpu_target._numpy_names() == names, version


here_v3 = pytest.mark.skipif(
    cpu_target.platform.machine() != "x86_64" or not Path("/proc/cpuinfo").exists()
    or not runs_x86_64_v3(Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace"))
    or os.environ.get("NUMBA_CPU_NAME", PORTABLE_CPU) != PORTABLE_CPU,
    reason="this machine is not x86-64-v3 (or NUMBA_CPU_NAME chooses another CPU): pound compiles for its host")  # fmt: skip


@here_v3
def test_this_process_compiles_for_haswell_and_numpy_runs_no_avx512_loop():
    """The tests import pound (conftest) before numpy and numba: the pin holds in them."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    from pounding_cli.solver.jit import kernel

    @kernel
    def twice(x):
        return 2.0 * x

    assert twice(1.5) == 3.0
    assert compile_target() == "haswell"
    codegen = twice.targetctx.codegen()
    assert codegen._tm_features == ""  # the target machine numba made: haswell's instructions only
    running = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    assert not [f for f in running if "512" in f or f == "X86_V4"], running


@here_v3
def test_a_pound_process_compiles_for_haswell():
    code = ("import pounding_cli, numpy, os; from pounding_cli.cpu_target import compile_target; "
            "print(compile_target(), os.environ['OPENBLAS_CORETYPE'])")  # fmt: skip
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES", "OPENBLAS_CORETYPE")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout
    assert out.split() == ["haswell", "Haswell"]
