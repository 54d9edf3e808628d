"""Independent groups (pounding_cli/city/groups.py, issue 30): the connected components of
the buildings within reach, run apart and merged into one result file."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from pounding_cli.city.block import Block, city_document, district_buildings
from pounding_cli.city.groups import components

REPO = Path(__file__).resolve().parents[1]


def _union_find(n, pairs):
    parent = list(range(n))

    def root(k):
        while parent[k] != k:
            k = parent[k]
        return k

    for i, j in pairs:
        parent[root(i)] = root(j)
    groups = {}
    for k in range(n):
        groups.setdefault(root(k), []).append(k)
    return sorted(groups.values(), key=lambda g: g[0])


def test_components_against_union_find():
    rng = np.random.default_rng(3)
    for n in (1, 2, 10, 60):
        pairs = {tuple(sorted(map(int, rng.choice(n, 2, replace=False)))) for _ in range(n // 2)} if n > 1 else set()
        assert components(n, pairs) == _union_find(n, pairs), n


@pytest.mark.slow
def test_two_blocks_run_apart_give_the_whole_runs_results(tmp_path):
    """Two 2 × 2 blocks across a 20 m street, 12 s of the record × 2: `pound run --jobs 2`
    (two groups) against the plain run of the whole scene. The groups' steps differ only where
    the whole run stepped one block by the CDM while the other was in contact, and the CDM at
    that Δt matches the exact step to rounding: peaks agree to 1e-8 of their size."""
    from pounding_cli.results import read_hdf5

    doc = city_document(district_buildings(Block(rows=2, cols=2), 2, 1), "two blocks", record_dir=str(REPO / "inputs" / "records"),
                        duration=12.0)  # fmt: skip
    doc["excitation"]["scale"] = 2.0
    model = tmp_path / "two_blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    for name, extra in (("groups.h5", ["--jobs", "2"]), ("whole.h5", [])):
        done = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(tmp_path / name), *extra],
                              capture_output=True, text=True)  # fmt: skip
        assert done.returncode == 0, done.stderr
    groups, whole = read_hdf5(tmp_path / "groups.h5"), read_hdf5(tmp_path / "whole.h5")
    assert groups.diagnostics["groups"] == 2 and "groups" not in whole.diagnostics
    assert list(groups.buildings) == list(whole.buildings)
    for name, bld in whole.buildings.items():
        peak = groups.buildings[name].peak_displacement
        assert np.allclose(peak, bld.peak_displacement, rtol=1e-8, atol=1e-12), name
    assert sorted(map(tuple, groups.contact.pairs[["body_a", "floor_a", "body_b", "floor_b"]].tolist())) == sorted(
        map(tuple, whole.contact.pairs[["body_a", "floor_a", "body_b", "floor_b"]].tolist()))
    assert groups.contact.impact_count == whole.contact.impact_count
    assert np.allclose(groups.energy, whole.energy, rtol=1e-8, atol=1e-6 * np.abs(whole.energy).max())


def test_groups_whose_merged_results_would_not_fit_are_refused_before_they_run(tmp_path):
    """The estimate of the merged histories (the resource limits' rule) against
    POUND_MAX_MEMORY_GB: exit 2 naming it and analysis.output_interval, nothing written."""
    import os

    doc = city_document(district_buildings(Block(rows=2, cols=2), 2, 1), "two blocks",
                        record_dir=str(REPO / "inputs" / "records"), duration=4.0)  # fmt: skip
    model = tmp_path / "two_blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    done = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(tmp_path / "out.h5"),
                           "--jobs", "2"], capture_output=True, text=True,
                          env={**os.environ, "POUND_MAX_MEMORY_GB": "0.001"})  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert "analysis.output_interval: the merged results of its 2 independent groups would hold about" in done.stderr
    assert "POUND_MAX_MEMORY_GB" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "out.h5").exists()


def _warning_lines(stderr: str, model: Path) -> list[str]:
    """The plausibility warnings of a run's stderr, one per line (`FILE: field: message`),
    without --strict's closing remark."""
    return [line.split(" (--strict:")[0] for line in stderr.splitlines() if line.startswith(f"{model}: ")]


def test_groups_warn_as_the_whole_run_does_and_strict_refuses_with_exit_2(tmp_path):
    """A modulus typed in MPa (a plausibility warning on the material and on every building's
    period): `pound run --jobs 2` prints the warnings the whole run prints, fields named as in
    the whole model (buildings[7], not the second group's buildings[3]), each once, in the
    same order, and its progress (--progress, not a terminal: a line per tenth) counts the two
    groups; with --strict both refuse with exit 2 and the same lines, nothing written.
    (Before, the groups' warnings were not shown, and --strict inside a worker ended the run
    with exit 1 and group-local field names.)"""
    doc = city_document(district_buildings(Block(rows=2, cols=2), 2, 1), "two blocks",
                        record_dir=str(REPO / "inputs" / "records"), duration=2.0)  # fmt: skip
    for material in doc["materials"].values():
        material["elastic_modulus"] = 21000.0
    model = tmp_path / "mpa.toml"
    model.write_text(tomli_w.dumps(doc))

    def pound(*args):
        return subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), *args], capture_output=True,
                              text=True, cwd=tmp_path)  # fmt: skip

    whole, groups = pound("-o", "whole.h5"), pound("-o", "groups.h5", "--jobs", "2", "--progress")
    assert whole.returncode == groups.returncode == 0, (whole.stderr, groups.stderr)
    assert "integrating: 50 %" in groups.stderr and "integrating: 100 %" in groups.stderr  # a group of two ended
    expected = _warning_lines(whole.stderr, model)
    assert len(expected) == 9 and expected[0].startswith(f"{model}: materials.concrete.elastic_modulus: ")
    assert f"{model}: buildings[7]: " in expected[-1]
    assert _warning_lines(groups.stderr, model) == expected
    for args in (["-o", "strict-whole.h5", "--strict"], ["-o", "strict-groups.h5", "--strict", "--jobs", "2"]):
        refused = pound(*args)
        assert refused.returncode == 2, refused.stderr
        assert _warning_lines(refused.stderr, model) == expected
        assert "--strict: 9 plausibility warnings made errors" in refused.stderr
        assert not (tmp_path / args[1]).exists()


def test_a_group_its_own_set_up_refuses_is_refused_with_exit_2(tmp_path):
    """The resource limits refuse a group in its worker (POUND_MAX_STEPS = 100, far fewer than
    its contact step needs): `pound run --jobs 2` exits 2 with the message `pound run` gives
    the whole scene, nothing written, with --strict too (the refusal is not a plausibility
    warning). (Before, the worker's InputError came back as a failed group: exit 1.)"""
    import os

    doc = city_document(district_buildings(Block(rows=2, cols=2), 2, 1), "two blocks",
                        record_dir=str(REPO / "inputs" / "records"), duration=2.0)  # fmt: skip
    model = tmp_path / "two_blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    said = []
    for name, extra in (("whole.h5", []), ("groups.h5", ["--jobs", "2"]), ("strict.h5", ["--jobs", "2", "--strict"])):
        done = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(tmp_path / name),
                               *extra], capture_output=True, text=True,
                              env={**os.environ, "POUND_MAX_STEPS": "100"})  # fmt: skip
        assert done.returncode == 2, done.stderr
        assert not (tmp_path / name).exists()
        said.append(done.stderr.strip().splitlines()[-1])
    assert said[0] == said[1] == said[2] and "(POUND_MAX_STEPS)" in said[0] and "Traceback" not in said[1]
