"""What a command loads before it answers (issue 28, cold start).

numba's import and its CPU target's start-up take about 0.8 s on the reference machine before
the first cached kernel loads (docs/bench.md, "Cold start"): more than everything else
`pound validate` does. Commands that never integrate must not pay it, and a run must load the
kernels its scene needs and no others. Each check runs in a fresh interpreter, as a user's
command does; what is asserted is which modules and kernels were loaded, not a time.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from conftest import INPUTS, ROOT


def _in_fresh_process(code: str) -> str:
    result = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    return result.stdout.strip().splitlines()[-1]


def _cli_then(args: list[str], probe: str) -> str:
    """Run `pound ARGS` in a fresh interpreter, then print the value of `probe`."""
    return _in_fresh_process(
        "import sys\n"
        "from pounding_cli.cli import app\n"
        f"try:\n    app({args!r})\nexcept SystemExit as e:\n    assert e.code in (0, None), e.code\n"
        f"print({probe})\n"
    )


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("cold") / "paper_pounding.h5"
    from pounding_cli import api

    assert api.run_model(INPUTS / "paper_pounding.toml", output=path).complete
    return path


@pytest.mark.parametrize("model", ["paper_pounding.toml", "paper_inelastic.toml", "isolated_moat.toml",
                                   "mismatched_floors.toml"])  # fmt: skip
def test_validate_does_not_load_numba(model):
    assert _cli_then(["validate", str(INPUTS / model)], "'numba' in sys.modules") == "False"


def test_schema_does_not_load_numba(tmp_path):
    assert _cli_then(["schema", "--out", str(tmp_path)], "'numba' in sys.modules") == "False"


@pytest.mark.parametrize("command", [["report", "--json"], ["report"], ["export", "--csv", "{out}"]])
def test_reading_results_does_not_load_numba(result_file, tmp_path, command):
    args = [a.replace("{out}", str(tmp_path / "exported")) for a in command]
    args.insert(1, str(result_file))
    assert _cli_then(args, "'numba' in sys.modules") == "False"


def _loaded_kernels_after_run(model: str, out: str) -> list[str]:
    probe = ("json.dumps(sorted(f'{m.__name__.rsplit(\".\", 1)[-1]}.{n}' for m in list(sys.modules.values()) "
             "if getattr(m, '__name__', '').startswith('pounding_cli.') "
             "for n, f in vars(m).items() if getattr(f, 'signatures', None) and f.__module__ == m.__name__))")  # fmt: skip
    return json.loads(_in_fresh_process(
        "import sys, json\n"
        "from pounding_cli.cli import app\n"
        f"try:\n    app(['run', {model!r}, '-o', {out!r}, '--no-progress'])\nexcept SystemExit as e:\n"
        "    assert e.code in (0, None), e.code\n"
        f"print({probe})\n"
    ))  # fmt: skip


def test_an_elastic_scene_loads_the_time_loop_alone(tmp_path):
    """The elastic pounding example loads the hybrid time loop (and the crest search, compiled
    apart with its one signature so that its call sites share one compile): no yielding kernel,
    no kernel a run without yielding members does not call."""
    loaded = _loaded_kernels_after_run(str(INPUTS / "paper_pounding.toml"), str(tmp_path / "a.h5"))
    assert loaded == ["hybrid.hybrid_advance", "peaks.quintic_crests"]


def test_a_yielding_scene_loads_its_members_kernels(tmp_path):
    """The counter-check: an inelastic scene does load the members' kernels, so the check
    above would see them."""
    loaded = _loaded_kernels_after_run(str(INPUTS / "paper_inelastic.toml"), str(tmp_path / "b.h5"))
    assert "hybrid.hybrid_advance" in loaded
    assert any(name.startswith("hysteresis.") for name in loaded), loaded


_ENDING = """
import atexit, sys
class Teardown:
    def __del__(self):
        print("torn down", flush=True)
keep = Teardown()  # a module global: the interpreter's shutdown would delete it
atexit.register(lambda: print("exit handler ran", flush=True))
sys.argv = ["pound", *sys.argv[1:]]
from pounding_cli.__main__ import main
main()
print("not reached")
"""


@pytest.mark.parametrize("args, code", [(["validate", str(INPUTS / "paper_pounding.toml")], 0),
                                        (["validate", str(INPUTS / "no-such-model.toml")], 2)])  # fmt: skip
def test_a_command_ends_the_process_without_the_interpreters_shutdown(args, code):
    """Once a command has its exit code the process ends (pounding_cli.__main__.end_now): the
    code as the command gave it, the output flushed, the exit handlers run (a caller's and the
    libraries'), but no module torn down, which is what the interpreter's shutdown spends a
    third of a second of a run on (docs/bench.md, "Cold start")."""
    done = subprocess.run([sys.executable, "-c", _ENDING, *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)  # fmt: skip
    assert done.returncode == code, done.stderr
    lines = done.stdout.splitlines()
    assert lines[-1] == "exit handler ran", lines[-3:]
    assert "torn down" not in lines and "not reached" not in lines
    if code == 0:
        assert any("paper_pounding" in line or "left" in line for line in lines[:-1]), lines[:5]
    else:
        assert "no-such-model.toml" in done.stderr
