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


def test_groups_whose_results_would_not_fit_are_refused_before_they_run(tmp_path):
    """The estimate of the largest group's histories (the resource limits' rule) against
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
    assert "analysis.output_interval: the results of the largest of its 2 independent groups (4 buildings) would hold about" in done.stderr
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


def _same_files(a, b) -> None:
    """Every group, dataset and attribute of two HDF5 files equal (NaN equal to NaN), groups
    in the same order."""
    import h5py

    def attrs(obj):
        return {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in obj.attrs.items()
                if k not in ("DIMENSION_LIST", "REFERENCE_LIST")}  # fmt: skip

    def walk(x, y, where):
        assert attrs(x) == attrs(y), where
        if isinstance(x, h5py.Dataset):
            u, v = x[()], y[()]
            for field in u.dtype.names or (None,):
                p, q = (u, v) if field is None else (u[field], v[field])
                if p.dtype == object:
                    assert p.tolist() == q.tolist(), (where, field)
                else:
                    np.testing.assert_array_equal(p, q, err_msg=f"{where} {field}")
            return
        assert list(x) == list(y), where
        for key in x:
            walk(x[key], y[key], f"{where}/{key}")

    with h5py.File(a) as f, h5py.File(b) as g:
        walk(f, g, "")


def test_the_file_written_group_by_group_is_the_file_of_the_merged_result(tmp_path):
    """The grouped run writes each group's buildings as the group ends, keeping only peaks,
    impact log, sparse contact columns and energies (results/grouped_file.py). Its file, with
    the groups ending in reverse order, against write_hdf5 of the merged result held whole:
    every dataset and attribute equal, bit for bit (the same values go through the same
    writer), buildings in the model's order; the result returned holds no history samples."""
    from dataclasses import replace

    from pounding_cli.assembly import assemble, ground_motion
    from pounding_cli.city.groups import merge, run_groups
    from pounding_cli.city.reach import scene_reach
    from pounding_cli.model import load_model, read_document
    from pounding_cli.results import write_hdf5
    from pounding_cli.results.grouped_file import grouped_file

    doc = city_document(district_buildings(Block(rows=2, cols=2), 3, 1), "three blocks",
                        record_dir=str(REPO / "inputs" / "records"), duration=12.0)  # fmt: skip
    doc["excitation"]["scale"] = 2.0
    model = tmp_path / "three_blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    loaded = load_model(model)
    system, ground = assemble(loaded), ground_motion(loaded)
    reach, near = scene_reach(loaded.model, system.buildings, ground.acceleration, ground.dt)
    groups = components(len(system.buildings), near)
    assert len(groups) == 3
    names = [b.name for b in system.buildings]
    whole = []

    def backwards(tasks):  # the last group ends first
        for key, fn, args in reversed(tasks):
            yield key, True, fn(*args)

    def keep(result):
        whole.append(result)
        return stream.add(result)

    with grouped_file(tmp_path / "streamed.h5", names) as stream:
        results, found = run_groups(read_document(model), str(model), groups, reach.distance, backwards, keep=keep)
        merged = merge(results, names, "{}", "sha", found)
        stream.finish(merged)
    assert sum(r.contact.impact_count for r in whole) > 0
    assert all(b.displacement.shape[0] == 0 for b in merged.buildings.values())
    full = {name: b for r in whole for name, b in r.buildings.items()}
    write_hdf5(replace(merged, buildings={name: full[name] for name in names}), tmp_path / "whole.h5")
    _same_files(tmp_path / "streamed.h5", tmp_path / "whole.h5")


def test_a_sigterm_while_groups_are_written_stops_at_once_with_nothing_written(tmp_path):
    """Signals are deferred only while a group's part of the file is written
    (atomic.atomic_stream): a SIGTERM once the first group is in the temporary file (each
    write slowed by 20 ms, so that writing spans the signal) ends `pound run --jobs 1` with
    exit 1, "interrupted", and neither the file nor its temporary is left."""
    import os
    import signal
    import time

    doc = city_document(district_buildings(Block(rows=2, cols=2), 3, 1), "three blocks",
                        record_dir=str(REPO / "inputs" / "records"), duration=12.0)  # fmt: skip
    model = tmp_path / "three_blocks.toml"
    model.write_text(tomli_w.dumps(doc))
    out = tmp_path / "out" / "groups.h5"
    out.parent.mkdir()
    run = subprocess.Popen([sys.executable, "-m", "pounding_cli", "run", str(model), "-o", str(out), "--jobs", "1"],
                           stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True,
                           env={**os.environ, "POUND_TEST_SLOW_WRITES": "0.02"})  # fmt: skip
    deadline = time.time() + 120
    while not any(p.name.endswith(".tmp") for p in out.parent.iterdir()) and run.poll() is None and time.time() < deadline:
        time.sleep(0.005)
    assert run.poll() is None, "the run ended before its file was begun"
    time.sleep(0.3)
    run.send_signal(signal.SIGTERM)
    _, stderr = run.communicate(timeout=120)
    assert run.returncode == 1 and stderr.strip().splitlines()[-1] == "interrupted", stderr
    assert "Traceback" not in stderr and list(out.parent.iterdir()) == []


def test_a_district_of_more_than_a_thousand_buildings_is_a_valid_model(tmp_path):
    """A district of thousands runs as its independent groups (10,000 measured: issue 30's
    note); the model took at most 1,000 buildings. 1,001 validate now."""
    from pounding_cli.model import validate_model

    buildings = district_buildings(Block(rows=10, cols=10), 11, 1)[:1001]
    doc = city_document(buildings, "1001 buildings", record_dir=str(REPO / "inputs" / "records"))
    assert len(validate_model(doc, tmp_path / "district.toml").model.buildings) == 1001
