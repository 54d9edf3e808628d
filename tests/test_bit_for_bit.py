"""Restructuring the time loop changes no result, bit for bit.

The sha256 of every dataset (and every count in /diagnostics) that a few scenes write was
pinned in tests/bit_for_bit.json before the time loop was regrouped into records and phases
(issue 29), with the code of 2439a29. The scenes cover each path of the loop: the hybrid with
contact and friction and its approach levels (paper_pounding), yielding columns and the
yielding step (paper_inelastic), isolation with damping links, bearings and a moat wall
(isolated_moat), sweep and prune (row_of_5), double substeps (corner at ω·h / 2), the plain
CDM (linear at Δt × 4) and a stiff contact (stiff_contact).

Bits depend on more than pound's code: the CPU numba compiles for and OpenBLAS's kernels
(both fixed to Haswell's on x86-64-v3 machines, pounding_cli.cpu_target) and the versions of
numba, llvmlite, numpy and scipy. The pinned file records these; on another platform the comparison cannot mean anything and the test says so and
skips. To pin again, deliberately, after a change meant to move results:
`python tests/test_bit_for_bit.py --pin`.
Datasets added to the file since (issue 25: /diagnostics/warnings, the dimension scales and
their names in each group) were added to the pin with every dataset pinned before unchanged;
a dataset is hashed under each of its names (hard links). Columns added to a table (issue 23:
the storey struck and ξ in the impact log and the pairs; issue 28: the friction times and slip
count in the impact log) are hashed apart (ADDED_COLUMNS), so the table's own pin still holds.
Issue 28 moved two columns deliberately: the impact log's t_start and t_end, now located inside
their contact step (up to one step earlier). Its pin was renewed after every other column of
every scene's log was compared with f3049db's, value for value, and found equal, and every
other dataset's pin held. Issue 30 re-pinned row_of_5 alone: its buildings 1 and 5, 24 m apart,
lose their candidates (contact.reach), so its pairs, contact histories, the pair numbers of its
log and diagnostics/contact_pairs change and two reach diagnostics are added; every building,
energy and time dataset is unchanged. Merged, row_of_5's log differs from issue 30's branch in
t_start and t_end alone.
Issue 23's step per contact phase added diagnostics/step_changes (0 in every pinned scene: their
pairs' own ω lie within 2× of each other, so every phase takes the contact step) to the pins, with
every dataset pinned before unchanged.
Issue 28 re-pinned the five scenes whose results moved (all but paper_inelastic and the linear
scene under the plain CDM): the friction spring's slip is now taken at the step's midpoint (_slip_over_step),
which removed a first-order error in turning contacts. Against 1e68ac1's results the peaks
moved by at most 1.4e-9 (paper_pounding), 2.0e-9 (stiff_contact), 3.4e-8 (corner), 2.8e-7
(row_of_5) of their largest value; isolated_moat's 73 impacts by up to 0.24 % (residual
deflection) and 0.46 % (an impact's peak force), inside its error at the automatic step: its
interstorey peaks are 3.25e-3 (old) and 3.22e-3 (new) from a run at 1/64 of that step, and
5.9e-5 and 6.0e-5 at 1/16.
Issue 28 then re-pinned the same five: the hybrid's test of whether a pair can touch within its
horizon counts the pair's approach speed along the separating axis, not its speed whichever way
(contact._pair_closing_along), so the CDM hands back sooner after a rebound (CDM steps: corner
17,289 → 14,481, paper_pounding 1,350 → 840, row_of_5 68,247 → 63,756, stiff_contact 22,290 →
20,060). Against 472ca56's results the peaks moved by at most 6.4e-11 (paper_pounding), 2.5e-12
(stiff_contact), 2.2e-8 (corner), 1.1e-9 (row_of_5), 3.2e-7 (isolated_moat) of their largest
value, the impacts' peak forces by at most 4.7e-7: the hand-overs' own second-order error.
The pins were taken on a Zen 3 while numba compiled for the host ("znver3"). Since pound
compiles for "haswell" on every x86-64-v3 machine (cpu_target), the file records that CPU: all
seven scenes, run on a Zen 5 compiling for "haswell", gave every pinned digest (and 14 to 74 of
each scene's 118 to 228 datasets differed compiling for the Zen 5 itself).
Issue 30 re-pinned row_of_5 once more when buildings began to sleep through contact phases
(solver/sleep.py: 102 times, woken 9 times, sparing 173,484 of its 318,780 building-steps of
the CDM): its
sleeping buildings are now integrated exactly, so every building dataset, the energy and the
impact log moved by the CDM's truncation error on them (tests/test_sleep.py: displacements
1.8e-9 of their largest value, peaks 6.6e-9, impact forces 4e-9). Every other scene, in which
every building is needed through each contact phase, kept every pinned digest; the three new
counts (diagnostics/sleeps, wakes, slept_building_steps) were added to every scene's pin.
"""

from __future__ import annotations

import hashlib
import json
import platform
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np
import pytest

PINNED = Path(__file__).with_name("bit_for_bit.json")
REPO = Path(__file__).resolve().parents[1]
SCENES = {
    "paper_pounding": ("inputs/paper_pounding.toml", None),
    "paper_inelastic": ("inputs/paper_inelastic.toml", None),
    "isolated_moat": ("inputs/isolated_moat.toml", None),
    "row_of_5": ("bench:row_of_5", "hybrid (default)"),
    "corner, double substeps": ("bench:corner", "hybrid, ω·h / 2"),
    "linear, plain CDM": ("bench:linear", "cdm, Δt × 4"),
    "stiff_contact": ("bench:stiff_contact", "hybrid (default)"),
}
RUN_DEPENDENT = ("time", "us_per_step")  # diagnostics that are timings: not results
ADDED_COLUMNS = {"impacts/events": (("storey_b", "xi"), ("t_slip", "t_stick", "slips")),
                 "impacts/pairs": (("storey_b", "xi"),)}  # fmt: skip
"""Columns added to a table after it was pinned (issue 23: the storey struck and ξ; issue 28: the
friction times): the table is hashed without them, as pinned, and each group apart under
"<table>:<columns>"."""


def platform_key() -> dict[str, str]:
    """What besides pound's code decides the bits: "cpu" is the CPU numba compiles for
    (pounding_cli.cpu_target: "haswell" on every x86-64-v3 machine, else the host's)."""
    import llvmlite
    import numba
    import scipy

    from pounding_cli.cpu_target import compile_target

    return {
        "machine": platform.machine(),
        "cpu": compile_target(),
        "numba": numba.__version__,
        "llvmlite": llvmlite.__version__,
        "numpy": np.__version__,
        "scipy": scipy.__version__,
    }


def scene_result(name: str):
    """Run one scene as the CLI would (the bench's setting where one is named)."""
    from pounding_cli.api import execute, prepare
    from pounding_cli.bench.run import SETTINGS, scene_files, with_setting

    source, setting = SCENES[name]
    if source.startswith("bench:"):
        path = next(p for p in scene_files() if p.stem == source.split(":")[1])
    else:
        path = REPO / source
    scene = prepare(path)
    if setting is not None:
        scene = with_setting(scene, next(s for s in SETTINGS if s.name == setting))
    return execute(scene)


def digests(result) -> dict[str, str]:
    """sha256 of every dataset of the run's HDF5 file, and every diagnostic that is not a
    timing, by path."""
    from pounding_cli.results.hdf5 import write_hdf5

    out = {}
    with tempfile.TemporaryDirectory() as folder:
        path = write_hdf5(result, Path(folder) / "run.h5")
        with h5py.File(path) as f:

            def visit(name):  # every name: a dataset with several (hard links: /time, coordinates) under each
                node = f[name]
                if isinstance(node, h5py.Dataset):
                    data = node[()]
                    if name == "diagnostics/warnings":  # the model file's path depends on the checkout: not a result
                        data = data[[n for n in data.dtype.names if n != "file"]]
                    for added in ADDED_COLUMNS.get(name, ()):
                        out[f"{name}:{','.join(added)}"] = _digest(data[list(added)])
                        data = data[[n for n in data.dtype.names if n not in added]]
                    out[name] = _digest(data)

            f.visit_links(visit)
            for key, value in f["diagnostics"].attrs.items():
                if not any(word in key for word in RUN_DEPENDENT):
                    out[f"diagnostics/{key}"] = str(value)
            out["status"] = str(f.attrs["status"])
    return out


def _digest(data: np.ndarray) -> str:
    """sha256 of a dataset's values (tables with strings hold pointers: their values' repr)."""
    if data.dtype.names and not data.dtype.hasobject:  # a selection of columns: pack it
        data = np.array(data.tolist(), dtype=[(n, data.dtype[n]) for n in data.dtype.names])
    raw = repr(data.tolist()).encode() if data.dtype.hasobject else np.ascontiguousarray(data).tobytes()
    return hashlib.sha256(raw).hexdigest()


def pin() -> None:
    scenes = {n: digests(scene_result(n)) for n in SCENES}  # first: pound's import sets the CPU target numba reads
    PINNED.write_text(json.dumps({"platform": platform_key(), "scenes": scenes}, indent=1, ensure_ascii=False) + "\n",
                      encoding="utf-8")  # fmt: skip


@pytest.fixture(scope="module")
def pinned():
    data = json.loads(PINNED.read_text(encoding="utf-8"))
    here = platform_key()
    if data["platform"] != here:
        differ = {k: (data["platform"].get(k), v) for k, v in here.items() if data["platform"].get(k) != v}
        pytest.skip(f"pinned on another platform ({differ}: pinned, here): bits cannot be compared")
    return data["scenes"]


@pytest.mark.parametrize("name", list(SCENES))
def test_every_dataset_is_as_pinned(pinned, name):
    now = digests(scene_result(name))
    assert now.keys() == pinned[name].keys(), f"{name}: datasets added or gone"
    changed = sorted(k for k in now if now[k] != pinned[name][k])
    assert not changed, f"{name}: {len(changed)} of {len(now)} datasets changed: {changed}"


if __name__ == "__main__":
    if sys.argv[1:] != ["--pin"]:
        sys.exit("usage: python tests/test_bit_for_bit.py --pin")
    pin()


@pytest.mark.parametrize("integrator", ["hybrid", "cdm"])
def test_the_time_loops_calls_do_not_change_the_results(integrator):
    """The time loop runs in calls (chunks) whose length grows while they are quick
    (integrate.CHUNK_SECONDS); where they begin and end must not matter: the paper's scene
    (contact, friction, the hybrid's approach) from one-substep chunks against the default,
    bit for bit. No platform key needed: both runs are on this machine."""
    from dataclasses import fields

    from pounding_cli.api import prepare
    from pounding_cli.solver import simulate

    scene = prepare(REPO / "inputs" / "paper_pounding.toml")
    g = scene.grid
    substep = g.substep if integrator == "hybrid" else 0
    n_steps = g.n_steps if substep else 40 * g.stride  # the CDM at the contact step: 0.4 s

    def run(chunk: int):
        return simulate(scene.system, scene.ground.acceleration, scene.ground.dt, g.dt, g.stride, n_steps,
                        contact=scene.contact, substep=substep, yield_substep=g.yield_substep, chunk=chunk)  # fmt: skip

    small, default = run(1), run(20_000)
    for field in fields(small):
        a, b = getattr(small, field.name), getattr(default, field.name)
        if field.name in ("wall_time", "compile_time"):
            continue
        if isinstance(a, np.ndarray):
            assert a.tobytes() == b.tobytes(), field.name
        else:
            assert a == b, field.name
