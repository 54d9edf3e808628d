"""Resource limits (pounding_cli/limits.py): models that would need more time, memory or disk
than is sensible are refused up front with the estimate, the limit and the field that causes
it; the limits are read from the environment; the disk estimate matches real files."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from typer.testing import CliRunner

import pounding_cli as pound
from pounding_cli import api, limits
from pounding_cli.cli import app
from pounding_cli.errors import InputError
from pounding_cli.model.load import read_document, validate_model

from conftest import INPUTS, example_doc, load_doc


def refusal(doc, **env) -> str:
    """The message of the InputError that `pound validate` raises for `doc`."""
    with pytest.MonkeyPatch.context() as mp:
        for name, value in env.items():
            mp.setenv(f"POUND_{name}", str(value))
        with pytest.raises(InputError) as caught:
            pound.describe(load_doc(doc))
    return str(caught.value)


def test_too_many_storeys_is_refused_with_the_estimate():
    doc = example_doc()
    doc["buildings"][0]["floors"][0]["repeat"] = 500
    doc["buildings"][0]["floors"].append(dict(doc["buildings"][0]["floors"][0]))
    doc["buildings"][0]["floors"].append(dict(doc["buildings"][0]["floors"][0], repeat=1))
    # (6 × 1001)² × 8 bytes = 288 576 288 B = 275.2 MiB; (6 × 1000)² × 8 = 288 000 000 B = 274.7 MiB
    assert refusal(doc).endswith(
        "buildings[0].floors: 1001 storeys: more than the limit of 1000 (POUND_MAX_STOREYS): the exact integrator "
        "holds a dense (6N)² state-transition matrix per building, 275.2 MiB for 1001 storeys against 274.7 MiB at "
        "the limit"
    )


def test_a_million_floors_in_one_entry_says_why_500_and_what_it_would_take():
    doc = example_doc()
    doc["buildings"][0]["floors"][0]["repeat"] = 10**6
    message = refusal(doc)
    # (6 × 10⁶)² × 8 bytes = 2.88e14 bytes = 2.682e5 GiB
    assert "buildings[0].floors[0].repeat: 1000000 storeys in one floor entry: at most 500, so that a slip" in message
    assert "(1000000 storeys would need 2.682e+05 GiB for the exact integrator's (6N)² matrix)" in message
    assert "up to 1000 storeys in all (POUND_MAX_STOREYS)" in message


def test_an_output_interval_of_a_nanosecond_is_blamed_on_the_output_interval():
    doc = example_doc()
    doc["analysis"]["output_interval"] = 1e-9
    message = refusal(doc)
    assert re.search(r"analysis\.output_interval: the analysis would take 3\.4e\+10 time steps \(34 s at Δt = 1e-09 s\), "
                     r"more than the limit of 2e\+08 \(POUND_MAX_STEPS\); an output interval of 1e-09 s forces the "
                     r"time step down to it \(else Δt = .* s\); check its unit \(s\)", message), message  # fmt: skip


def test_a_duration_of_a_million_seconds_is_blamed_on_the_duration():
    doc = example_doc()
    doc["analysis"]["duration"] = 1e6
    message = refusal(doc)
    assert "analysis.duration: the analysis would take" in message and "(POUND_MAX_STEPS)" in message
    assert "a duration of 1e+06 s is 2.94e+04 times the record's length; check its unit (s)" in message  # 1e6 / 34 s


def test_a_tiny_given_step_is_blamed_on_the_step():
    doc = example_doc()
    doc["analysis"]["dt"] = 1e-10
    assert "analysis.dt: the analysis would take 3.4e+11 time steps (34 s at Δt = 1e-10 s)" in refusal(doc)


def test_auto_step_too_small_names_the_stiff_building_or_the_contact():
    """A unit slip that makes Δt = "auto" tiny: the stiffest building's masses (t given as kg
    would make the structure 1000 times lighter) or the impact stiffness (in kN/m² given as
    N/m²... and then multiplied by 10⁶); the step limit is lowered for a quick check."""
    light = example_doc()
    light["contact"] = {"enabled": False}
    light["buildings"][1]["floors"][0]["mass_per_area"] = 1.0
    # the refusal names the implausible mass itself (a plausibility warning), not the whole building
    assert re.search(r"buildings\[1\]\.floors\[0\]\.mass_per_area: the analysis would take .* Δt = \"auto\" follows "
                     r"the highest natural frequency of building 'right' .*, and mass_per_area = 1 kg/m² is below",
                     refusal(light, MAX_STEPS=1e6))  # fmt: skip
    stiff = example_doc()
    stiff["buildings"][1]["origin"] = [8.05, 0.0]
    stiff["contact"] = {"k_normal": 2.06e16}
    assert "contact.k_normal: the analysis would take" in refusal(stiff, MAX_STEPS=1e6)
    plausible = example_doc()  # a plausible building beyond the limit: the building, whose inputs to check
    plausible["contact"] = {"enabled": False}
    assert re.search(r"buildings\[1\]: the analysis would take .* check the units of its column sections",
                     refusal(plausible, MAX_STEPS=1e3))  # fmt: skip


def test_the_step_limit_refuses_about_a_billion_steps_and_accepts_below_the_limit():
    """9.8 × 10⁸ steps (the audit's case) is refused; 1.9 × 10⁸ (below 2 × 10⁸) is accepted, its
    histories stored every 10 s being small."""
    scene = pound.api.prepare(load_doc(example_doc()))
    dt = scene.grid.dt
    doc = example_doc()
    doc["analysis"].update(duration=10.0 * round(9.8e8 * dt / 10.0), output_interval=10.0)  # whole outputs
    taken = re.search(r"analysis\.duration: the analysis would take (\d\.\d+)e\+08 time steps", refusal(doc))
    assert taken and float(taken[1]) == pytest.approx(9.8, abs=0.02)  # the duration rounded to whole outputs
    doc["analysis"]["duration"] = 1.9e8 * dt
    assert pound.describe(load_doc(doc))["analysis"]["steps"] <= 2e8


def test_a_result_file_beyond_the_disk_limit_gives_the_estimate():
    doc = example_doc()
    # 3 400 001 samples of 8 × (1 + 2 + 3 × 21 + 7 + 6 × 3 + 75) = 1328 bytes: 4.515e9 B = 4.205 GiB; the 75 force
    # values: 6 per storey (7) and 6 per building's base shear (2), 3 contact forces per floor (7)
    doc["analysis"]["output_interval"] = 1e-5
    message = refusal(doc, MAX_OUTPUT_GB=0.5)
    assert message.endswith(
        "analysis.output_interval: its result file would take 4.205 GiB (3.4e+06 samples every 1e-05 s × 1328 bytes: "
        "21 DOFs, 3 contact pairs, 0 yielding members, 75 force values), more than the limit of 512 MiB (POUND_MAX_OUTPUT_GB); "
        "store less often (a larger output interval) or shorten the analysis"
    )


def test_histories_beyond_the_memory_limit_name_the_duration_when_it_is_the_cause():
    doc = example_doc()
    # 100 times the record: 340 000 samples + 1 of 1328 bytes, twice in memory, plus the impact log's
    # buffer of 200 000 × 11 floats: 2 × 451.52 MB + 17.6 MB = 920.6 MB = 878 MiB
    doc["analysis"]["duration"] = 3400.0
    message = refusal(doc, MAX_MEMORY_GB=0.25, MAX_STEPS=1e10)  # (6.4e8 steps of the contact step)
    assert "analysis.duration: its time histories would hold 878 MiB" in message
    assert "more than the limit of 256 MiB (POUND_MAX_MEMORY_GB); a duration of 3400 s is 100 times" in message


def test_a_limit_that_is_not_a_number_is_named():
    with pytest.raises(InputError, match=r"^POUND_MAX_STEPS: expected a positive number, got 'lots'$"):
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv("POUND_MAX_STEPS", "lots")
            pound.describe(load_doc(example_doc()))


def test_limits_can_be_raised_and_lowered_by_the_environment(monkeypatch):
    monkeypatch.setenv("POUND_MAX_STOREYS", "3")
    with pytest.raises(InputError, match="4 storeys: more than the limit of 3"):
        pound.describe(load_doc(example_doc()))
    monkeypatch.setenv("POUND_MAX_STOREYS", "1000")
    doc = example_doc()
    doc["analysis"]["output_interval"] = 1e-7
    monkeypatch.setenv("POUND_MAX_STEPS", "1e12")  # the step limit lets it through: the disk limit does not
    assert "its result file would take 420.5 GiB" in refusal(doc)  # 3.4e8 samples × 1328 bytes


def test_column_force_histories_are_counted_and_named_when_they_are_the_cause():
    """4 values per column line and storey per sample (the paper's 9 + 15 lines over 4 and 3
    storeys: 4 × (36 + 45) = 324, 2592 bytes) beside the 1328 the run stores anyway: 3920 bytes
    × 340 001 samples = 1.241 GiB, which a 1 GiB limit refuses, naming the histories that
    1328 bytes alone (0.42 GiB) would not need."""
    doc = example_doc()
    doc["analysis"].update(output_interval=1e-4, column_force_histories=True)
    message = refusal(doc, MAX_OUTPUT_GB=1.0)
    assert "analysis.column_force_histories: its result file would take 1.241 GiB" in message
    assert "3920 bytes: 21 DOFs, 3 contact pairs, 0 yielding members, 399 force values" in message
    assert message.endswith("set column_force_histories = false (the columns' peak forces are stored regardless)")
    doc["analysis"]["column_force_histories"] = False
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("POUND_MAX_OUTPUT_GB", "1.0")
        pound.describe(load_doc(doc))  # within the limit without them


def test_single_precision_histories_halve_the_buildings_part_and_are_named_when_they_would_fit():
    """Of the 1328 bytes per sample, the buildings' histories are 138 values (3 × 21 DOFs and
    75 force values), 4 bytes each in single precision: 224 + 552 = 776 bytes. 340 001 samples
    take 0.4205 GiB in double, 0.2457 GiB in single precision: a 0.3 GiB limit refuses the
    first, naming analysis.history_precision, and passes the second. Memory is counted in
    double precision either way (the solver's histories are)."""
    doc = example_doc()
    doc["analysis"]["output_interval"] = 1e-4
    message = refusal(doc, MAX_OUTPUT_GB=0.3)
    assert "analysis.history_precision: its result file would take 430.6 MiB" in message
    assert message.endswith('set history_precision = "single" (7 significant digits; peaks, impact log and '
                            "energies stay in double precision)")  # fmt: skip
    doc["analysis"]["history_precision"] = "single"
    scene = api.prepare(load_doc(doc))
    assert api.resource_size(scene).per_sample == 776
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("POUND_MAX_OUTPUT_GB", "0.3")
        pound.describe(load_doc(doc))
    # memory: the same 2 × 1328 bytes a sample in both precisions
    assert limits.memory_bytes(api.resource_size(scene), 10) == 2 * 1328 * 10 + limits.EVENT_BUFFER_BYTES


def test_the_command_line_exits_2_with_the_message(tmp_path):
    doc = example_doc()
    doc["analysis"]["output_interval"] = 1e-9
    path = tmp_path / "model.json"
    path.write_text(json.dumps(doc))
    (tmp_path / "records").symlink_to(INPUTS / "records")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"{path}: analysis.output_interval: the analysis would take 3.4e+10 time steps")


@pytest.mark.parametrize("name, precision", [("paper_pounding", "double"), ("paper_inelastic", "double"),
                                             ("isolated_moat", "double"), ("paper_pounding", "single")])  # fmt: skip
def test_the_disk_estimate_matches_the_real_file(tmp_path, name, precision):
    """The estimate counts every time history the file holds; the rest (column and floor
    tables, peaks, modes, the impact log, attributes, HDF5's own structure) is a few tens of
    kB, so the real file is at most 1.05 times the estimate for the shipped examples (measured
    before the contact histories were stored sparsely: 1.004–1.017). The contact histories
    (6 per pair) and floor contact forces (3 per floor) are written only where they hold a
    value (results/sparse.py), so the file is at least the estimate without them. In single
    precision the buildings' histories take 4 bytes a value (the floor contact forces too in
    the estimate)."""
    doc = read_document(INPUTS / f"{name}.toml")
    doc["analysis"]["history_precision"] = precision
    scene = api.prepare(validate_model(doc, INPUTS / f"{name}.toml"))
    size = api.resource_size(scene)
    estimate = limits.history_bytes(size, scene.grid.n_outputs)
    floors = sum(b.n_floors for b in scene.system.buildings)
    sparse = (8 * 6 * size.n_pairs + size.building_item * 3 * floors) * scene.grid.n_outputs
    api.execute(scene, tmp_path / "out.h5")
    real = (tmp_path / "out.h5").stat().st_size
    assert estimate - sparse <= real <= 1.05 * estimate, (real, estimate, sparse)


# --- issue 27: limits that refuse before allocating, from the counts ------------------------


def _storeys(doc, n):
    floor = doc["buildings"][0]["floors"][0]
    doc["buildings"][0]["floors"] = [dict(floor, repeat=min(500, n - k)) for k in range(0, n, 500)]
    return doc


def test_a_thousand_storeys_is_refused_from_the_counts_before_anything_is_assembled(monkeypatch):
    """The documented storey limit (1000) passes the count; its exact integrator would then
    take 16 GiB (8·(48 + 4·2)·6004² bytes: measured 56 matrices of (6N + 4)² at 200 and 300
    storeys) and about 2 hours (3e-8·6004³ s): refused by memory on a machine of less than
    32 GiB, or by time at 1 hour, with nothing assembled: a run used to grow to 9.5 GB and
    still be setting up after 200 s."""
    import time

    doc = _storeys(example_doc(), 1000)
    monkeypatch.setattr(api, "assemble", lambda loaded: pytest.fail("assembled before the limits refused"))
    start = time.perf_counter()
    message = refusal(doc, MAX_MEMORY_GB=11.5)
    assert time.perf_counter() - start < 2.0
    assert message.endswith("buildings[0].floors: setting the analysis up would take about 15.58 GiB of memory (1000 "
                            "storeys and 9000 column instances in building 0, with the exact integrator (integrator = "
                            "\"cdm\" needs no matrix exponentials); 3 contact pairs), more than the limit of 11.5 GiB "
                            "(POUND_MAX_MEMORY_GB)"), message  # fmt: skip
    message = refusal(doc, MAX_MEMORY_GB=64, MAX_HOURS=1)
    assert "buildings[0].floors: setting the analysis up would take about 108 min" in message, message
    assert "more than the limit of 1 h (POUND_MAX_HOURS)" in message


def test_the_cdm_needs_no_exponentials():
    """integrator = "cdm" sets up dense (3N)² matrices only: a thousand storeys fit."""
    doc = _storeys(example_doc(), 1000)
    doc["analysis"]["integrator"] = "cdm"
    setup = api.setup_counts(load_doc(doc))
    assert setup.storeys == (1000, 3) and setup.columns == (9000, 45) and not setup.exact
    assert limits.setup_bytes(setup) < 2**30 and limits.setup_seconds(setup) < 10


@pytest.mark.parametrize("where", ["column_grid", "isolator_grid", "columns"])
def test_a_huge_storey_is_refused_before_any_column_is_made(where):
    """A 1000 × 1000 grid hung validation: a million Column objects, checked one by one, and
    their names compared with each other (quadratic). The count is checked first."""
    import time

    from pounding_cli.model import validate_model

    doc = example_doc()
    floor = doc["buildings"][0]["floors"][0]
    lines = [float(i) for i in range(1000)]
    if where == "column_grid":
        floor["column_grid"].update(x=lines, y=lines)
        expected = "buildings[0].floors[0].column_grid: 1000000 columns on one grid: at most 10000"
    elif where == "columns":
        floor["columns"] = [{"name": f"X{i}", "x": 1.0, "y": 1.0, "section": [0.3, 0.3], "material": "concrete"}
                            for i in range(10_001)]  # fmt: skip
        expected = "buildings[0].floors[0].columns: List should have at most 10000 items after validation"
    else:
        doc = pound.load_model(INPUTS / "isolated_moat.toml").model.model_dump(mode="json")
        doc["buildings"][0]["isolation"]["isolator_grid"].update(x=lines, y=lines)
        expected = "buildings[0].isolation: 1000000 isolators under one base slab: at most 10000"
    start = time.perf_counter()
    with pytest.raises(InputError) as caught:
        validate_model(doc, INPUTS / "huge.toml")
    assert time.perf_counter() - start < 3.0
    assert expected in str(caught.value), str(caught.value)


def test_the_time_loop_estimate_counts_columns_pairs_and_steps():
    """Past the set-up, the time loop: steps × their cost (dense step matrices, DOFs, column
    instances, pairs). A lowered POUND_MAX_HOURS refuses the paper's example, naming the
    step's cause: its Δt follows the contact."""
    setup = api.setup_counts(load_doc(example_doc()))
    assert setup.pairs == 3 and setup.columns == (36, 45)
    scene = api.prepare(load_doc(example_doc()))
    steps = scene.grid.free_steps(scene.ground.dt)
    loop = steps * limits.step_seconds(setup, 3, exact=True)
    assert loop > 0
    hours = (limits.setup_seconds(setup) + 0.5 * loop) / 3600  # the set-up passes, the loop does not
    message = refusal(example_doc(), MAX_HOURS=hours)
    assert f"the analysis would take about {limits._duration(limits.setup_seconds(setup) + loop)} (set-up" in message, message
    assert f"{steps:.3g} steps of" in message and "(POUND_MAX_HOURS)" in message


def test_level_pairs_match_every_floor_against_every_floor():
    """The candidates found by sorting elevations are those of the all-pairs loop, in its order."""
    from pounding_cli.assembly.contact import _level_pairs
    from pounding_cli.assembly.levels import LEVEL_TOLERANCE

    rng = np.random.default_rng(3)

    class B:
        def __init__(self, z):
            self.elevation = z

    for _ in range(50):
        blds = [B(np.cumsum(rng.choice([3.0, 3.0005, 3.5, 4.0], size=rng.integers(1, 12)))) for _ in range(rng.integers(1, 5))]
        flat = [(b, f, bld) for b, bld in enumerate(blds) for f in range(bld.elevation.size)]
        brute = [(ia, ib) for ia, (ba, fa, a) in enumerate(flat) for ib, (bb, fb, b) in enumerate(flat)
                 if bb > ba and abs(a.elevation[fa] - b.elevation[fb]) < LEVEL_TOLERANCE]  # fmt: skip
        assert _level_pairs(flat) == brute
