"""Quantities derived from accepted inputs stay finite and in range, or the run is refused.

Each input field is bounded by the schema, but products and ratios of several are not: a
duration of 1e306 s over a step of 2.6e-6 s is an integer count beyond float range, 5e-324 s
divides into infinity, k_N = 1e308 N/m² makes the contact's ω infinite and its step 0. The
time grid takes every count through timestep.whole()/nearest(), which hold it at MAX_COUNT
(2^62) instead of overflowing, and the step limit then refuses the run naming the field that
causes it (limits._step_cause). The cases of the issue are files in tests/invalid/
(invalid_duration_1e308.toml, ...); here, the grid itself over every combination of extremes,
and the exact integrator's bound on ρ·h for overdamped modes (rotational_inertia = 1e18).
"""

from __future__ import annotations

import itertools
import math
import subprocess
import sys

import pytest

from pounding_cli.api import prepare
from pounding_cli.assembly.timestep import time_grid
from pounding_cli.limits import MAX_COUNT
from pounding_cli.model import Analysis
from pounding_cli.solver.peaks import crest_series_order
from pounding_cli.solver.tunables import CREST_SPAN

from conftest import load_doc, model_doc, square_building

EXTREMES = [5e-324, 2.2e-308, 1e-12, 0.01, 1.0, 1e6, 1e154, 1e306, 1.7976931348623157e308]


@pytest.mark.parametrize("integrator", ["auto", "cdm"])
def test_time_grid_never_overflows(integrator: str) -> None:
    """Every combination of extreme durations, steps, output intervals and frequencies gives a
    grid of integer counts at most MAX_COUNT per factor, never an exception."""
    for duration, dt, out, omega, omega_c in itertools.product(
        [1e-3, 1.0, 1e306, 1e308], [5e-324, 1e-9, "auto"], [5e-324, 1e-9, 0.01, 10.0], EXTREMES[::2], [0.0, 1e3, 1e308, math.inf]
    ):  # fmt: skip
        if dt != "auto" and dt >= 2 / omega:
            continue  # refused as above the stability limit (InputError), not derived
        analysis = Analysis(duration=duration, dt=dt, output_interval=out, integrator=integrator)
        grid = time_grid(analysis, omega, 40.0, "m.toml", omega_c, 0.01, yielding=False)
        assert 1 <= grid.stride and 1 <= grid.n_steps and grid.n_steps % grid.stride == 0
        assert grid.n_steps <= MAX_COUNT * max(grid.stride, 1), (duration, dt, out, omega, omega_c)
        assert grid.dt > 0 and math.isfinite(grid.dt), (duration, dt, out, omega, omega_c)
        assert isinstance(grid.n_steps, int) and isinstance(grid.stride, int)


def test_saturated_counts_are_refused_naming_the_field() -> None:
    """A count held at MAX_COUNT is far beyond the step limit: the run is refused, and the
    message says "more than" rather than quoting the held count as the true one."""
    from pounding_cli.errors import InputError

    doc = model_doc(square_building(), duration=1e308)
    with pytest.raises(InputError, match=r"analysis\.duration: the analysis would take more than 4\.61e\+18 time steps"):
        prepare(load_doc(doc))


def overdamped_doc() -> dict:
    """The issue's case: a floor of rotational_inertia 1e18 kg·m² (the schema's maximum). Its
    rotational modes (one per floor: 4) have periods of days; Rayleigh damping anchored at
    modes 1 and 3 (both rotational) gives the translational modes ζ ≈ 4e4: they decay at
    ρ ≈ 2ζω, about 1e7 1/s."""
    building = square_building(storeys=4)
    building["floors"][0]["rotational_inertia"] = 1e18
    return model_doc(building, duration=0.2)


def test_overdamped_modes_bound_the_exact_step() -> None:
    """The hybrid's exact step satisfies ρ·h ≤ CREST_SPAN for the fastest decay rate ρ, not
    only ω_max·h: the solver's crest search sums a series in ρ·h (peaks.crest_series_order),
    which with ρ·h = 6.5e4 overflowed to infinity and never ended."""
    scene = prepare(load_doc(overdamped_doc()))
    rate, b, mode, zeta = scene.system.fastest_rate()
    assert zeta > 1e4 and rate > 1e4 * scene.system.omega_max, (rate, zeta)
    h = scene.grid.dt * scene.grid.substep
    assert scene.grid.fastest_rate == rate
    assert rate * h <= CREST_SPAN * (1 + 1e-12), rate * h
    assert crest_series_order(rate * h) < 100


@pytest.mark.slow
def test_overdamped_model_runs_to_the_end(tmp_path) -> None:
    """The issue's hang, end to end: `pound run` of it finishes (in seconds)."""
    import json

    path = tmp_path / "m.json"
    doc = overdamped_doc()
    doc["excitation"]["record"]["L"]["file"] = doc["excitation"]["record"]["T"]["file"] = str(
        (load_doc(doc).folder / doc["excitation"]["record"]["L"]["file"]).resolve())  # fmt: skip
    path.write_text(json.dumps(doc))
    proc = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(path), "-o", str(tmp_path / "o.h5")],
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert proc.returncode == 0, proc.stderr


def test_crest_series_order_ends_for_any_argument() -> None:
    """The solver's own guard: crest_series_order sums terms (ρh)^j/j! until they fall below
    SERIES_REMAINDER. ρh = 4 (the largest an exact step takes, CREST_SPAN) needs a few dozen
    terms; a rate that is infinite, NaN or so large that the terms would pass SERIES_MAX_ORDER
    is refused with ValueError instead of looping (rotational_inertia = 1e18 once hung here)."""
    from pounding_cli.solver.tunables import SERIES_MAX_ORDER

    assert 4 < crest_series_order(CREST_SPAN) < 40
    for rho_h in (float("inf"), float("nan"), 1e4, 6.5e4):
        with pytest.raises(ValueError, match=f"more than {SERIES_MAX_ORDER} terms"):
            crest_series_order(rho_h)
