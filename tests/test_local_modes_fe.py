"""pound's struck columns with their own mass (local modes) against the reduced model they
implement and the finite-element frame of tests/fe_frame.py (issue 23).

The scene is test_storey_fe's (a 3-storey building A, 3.5 m storeys, 9 columns 35 × 35 cm per
storey, E = 21 GPa, struck in storey 2 at ξ = 0.25, 0.5, 0.75 by the roof of a one-storey strip
B, 1 cm apart, shaken by the frame's test pulse, undamped) with A's columns of density
ρ = 2,500 kg/m³ (ρA = 306.25 kg/m, ρAh = 1,072 kg a column). pound's floor masses include the
columns' (half of each to either end floor, floor_masses()); B's columns, never struck, stay
massless. contact.column_modes = n gives the struck bundle (one column, C8) n clamped–clamped
local modes, ω_k = β_k²·√(EI/ρAh⁴) = 535, 2,890, 17,040 and 36,900 rad/s for k = 1, 3, 8, 12.
pound runs its central difference method throughout at the 2 µs contact step (the hybrid's
peaks between exact steps are refined except in the first exact step after a contact phase,
where a peak is off by O(h): 3.3e-6 of drift A₁ here at h = 1e-5 s, 3.3e-4 at the default
1e-3; the hybrid with local modes is held to the CDM in tests/test_local_modes.py).

Two checks bound pound's error against the frame:

1. pound against build_reduced(variant "c", n modes, residual flexibility, form "lumped"): the
   model pound implements, integrated in closed form. With local modes the contact chatters
   (B leans on A for 0.15–0.18 s: 30–105 undamped impacts, in which a difference grows by
   orders of magnitude), so impacts are compared one by one for the LEAD = 5 first (peak force,
   impulse, start and end) and the rest through totals (impulse, largest peak, F̄ the largest
   1 ms average of the force, the peak drifts A₁, A₂, A₃, B₁). The tolerances (IMPLEMENTATION)
   are 3–25× what pound's integrator gives on the reduced model's matrices at 2 µs (emulated:
   n = 0, 1, 3, 8 lead impacts 1.1e-7, 3.2e-6, 2.9e-5, 3.3e-4; drifts 2.3e-9, 4.3e-8, 1.8e-5,
   5.5e-3) and at least 1.8× their spread over steps of 1–2.5 µs; the CDM's phase error
   (ω·Δt)²/24, 5e-8 for mode 1 and 2.3e-4 for mode 12, seeds the chatter's growth, and with 8
   or more modes the largest peak is a draw from it (14 % between two steps), held to 25 %.
   The struck column's shear: the demand row of each impact is at the step where the bundle's
   whole end shear peaked from the impact's start to the next's (the column rings on after the
   contact), and holds the drift's part at that step and the bundle's own (its modes' restoring
   forces, the static reaction of what of the force they leave, the inertia of its mass that
   moves with the floors); against the reduced model's Galerkin end shears at that instant
   (shear_error, over the impact's force) measured ≤ 3.1e-7, 2.5e-4, 9.3e-4 for n = 1, 3, 8, and
   its peak over the same window (peak_shear_error) ≤ 4.1e-7, 1.8e-4, 3.8e-4.

2. The reduced model against the frame, its struck column in FE_ELEMENTS = 64 Hermite elements
   with consistent mass (fe_study's reference mesh; the other columns lumped as in pound),
   measured here (test_the_reduced_model_meets_the_frame_within_the_budget holds it within
   REDUCED_VS_FE, the measured figures rounded up). Largest relative error over ξ:

   | modes | first peak | largest peak | impulse | F̄ 1 ms | drifts | peak shear, first impact |
   | --- | --- | --- | --- | --- | --- | --- |
   | 0 (pound's massless columns) | 30 % | 67 % | 2.1 % | 32 % | 1.5 % | 20 % |
   | 3 | 6.5 % | 24 % | 0.96 % | 8.7 % | 0.14 % | 43 % |
   | 8 | 7.6 % | 12 % | 0.15 % | 0.57 % | 0.14 % | 6.9 % |
   | 12 | 0.35 % | 5.9 % | 0.42 % | 0.93 % | 0.19 % | 4.1 % |

   The contact here is stiff (k_c = k_N·1 m = 2.06e10 N/m, 2.9× the study's 0.35 m): the first
   impact's peak force needs the modes up to about 8 times the contact's own frequency against
   the column's mass (√(k_c/ρAh) = 4,400 rad/s): 12 modes (the default), not 8 (16 modes: first
   peak ≤ 0.18 %, peak shear ≤ 0.5 %). The chatter's largest peak does not converge with the
   frame's own mesh either (FE 16, 32, 64 differ by up to 21 % at ξ = 0.5), nor, at ξ = 0.5, the
   total impulse (0.6–0.8 %) and the drifts (0.3 %).

pound's tolerance against the frame (model_tolerance) is the sum of the two. Reference run
times (2 µs samples, one core): the reduced model 0.2–0.4 s per case, the frame 2.6–2.9 s per ξ
(cached across tests).
"""

from __future__ import annotations

import copy
from functools import lru_cache

import numpy as np
import pytest

from pounding_cli.api import run_model
from pounding_cli.model import validate_model

from fe_frame import Frame, Impact, Neighbour, Output, build_fe, build_reduced, simulate
from test_storey_fe import B_COL, B_MASS, B_SECTION, DURATION, E, GAP, H, I, K_N, PODIUM, STEP, _pound_model, pulse

RHO = 2500.0  # kg/m³
RHOA = RHO * B_COL**2  # 306.25 kg/m
COLUMNS = 9  # per storey of A
XIS = (0.25, 0.5, 0.75)
FE_ELEMENTS = 64  # the struck column's Hermite elements in the frame (fe_study's reference mesh)
OUTPUT = 1e-5  # s: pound's output interval here (5 contact steps), for F̄ and the demand's drift part
WINDOW = 1e-3  # s: F̄ is the largest average of the contact force over this window
LEAD = 5  # the leading impacts, compared one by one
DRIFTS = ("drift_A1", "drift_A2", "drift_A3", "drift_B1")

# pound against the same reduced model (build_reduced(form="lumped")): the largest relative
# errors allowed, by column_modes; "lead times", "first start" in contact steps, "shear" over
# the impact's force (see the module docstring for the measured figures behind each)
IMPLEMENTATION = {
    0: {"lead": 1e-6, "lead times": 3e-3, "first start": 1e-3, "impulse": 1e-6, "largest": 1e-6, "fbar": 1e-6, "drifts": 1e-6, "shear": 1e-6},
    1: {"lead": 3e-5, "lead times": 3e-2, "first start": 1e-3, "impulse": 1e-5, "largest": 1e-5, "fbar": 1e-5, "drifts": 1e-5, "shear": 1e-5},
    3: {"lead": 2e-4, "lead times": 0.1, "first start": 1e-3, "impulse": 1e-3, "largest": 2e-4, "fbar": 1e-3, "drifts": 5e-4, "shear": 1e-3},
    8: {"lead": 2e-3, "lead times": 1.0, "first start": 1e-3, "impulse": 2e-2, "largest": 0.25, "fbar": 3e-3, "drifts": 2e-2, "shear": 3e-3},
    12: {"lead": 2e-3, "lead times": 1.0, "first start": 1e-3, "impulse": 2e-2, "largest": 0.25, "fbar": 3e-3, "drifts": 2e-2, "shear": 3e-3},
}  # fmt: skip
# the reduced model against the frame (FE_ELEMENTS elements): measured here, rounded up
REDUCED_VS_FE = {
    3: {"first peak": 0.07, "largest": 0.25, "impulse": 0.012, "fbar": 0.095, "drifts": 2e-3, "shear": 0.45},
    8: {"first peak": 0.08, "largest": 0.13, "impulse": 2e-3, "fbar": 7e-3, "drifts": 2e-3, "shear": 0.075},
    12: {"first peak": 4e-3, "largest": 0.065, "impulse": 5e-3, "fbar": 0.01, "drifts": 2e-3, "shear": 0.045},
}  # fmt: skip
N_IMPLEMENTATION = tuple(IMPLEMENTATION)
N_FE = tuple(REDUCED_VS_FE)


def model_tolerance(n: int, key: str) -> float:
    """pound against the frame: the reduced model's own error (REDUCED_VS_FE) plus what pound
    may differ from the reduced model (IMPLEMENTATION); the first impact's peak is a lead one."""
    return REDUCED_VS_FE[n][key] + IMPLEMENTATION[n]["lead" if key == "first peak" else key]


# --- the scene ---------------------------------------------------------------------------------


def floor_masses() -> list[float]:
    """pound's floor masses of A, kg: the frame's 64 t and half of every column standing on or
    under the floor (ρAh/2 each, 9 a storey; the ground takes the foot of storey 1's), as
    build_fe(other_columns="lumped") and build_reduced lump them. pound moves what the struck
    bundle's local modes carry out of floors 1 and 2 itself."""
    half = COLUMNS * RHOA * H / 2
    return [64e3 + 2 * half, 64e3 + 2 * half, 64e3 + half]


def pound_model(folder, xi: float, modes: int) -> dict:
    """test_storey_fe's scene with A's columns of density ρ (B's columns, never struck, stay
    massless: a second material without a density), A's floors as floor_masses(), `modes`
    local modes per struck bundle, output every OUTPUT s, and the central difference method
    throughout (the module docstring)."""
    doc = _pound_model(folder, xi)
    doc["materials"]["concrete"]["density"] = RHO
    doc["materials"]["massless"] = {k: v for k, v in doc["materials"]["concrete"].items() if k != "density"}
    a, b = doc["buildings"]
    (floor,) = a["floors"]
    floor = {k: v for k, v in floor.items() if k not in ("repeat", "mass_per_area")}
    a["floors"] = [{**copy.deepcopy(floor), "mass": m} for m in floor_masses()]
    for f in b["floors"]:
        f["column_grid"]["material"] = "massless"
    doc["contact"]["column_modes"] = modes
    doc["analysis"]["output_interval"] = OUTPUT
    doc["analysis"]["integrator"] = "cdm"  # the module docstring: peaks at every step
    return doc


def scene(xi: float) -> tuple[Frame, Neighbour, Impact]:
    """The same scene for tests/fe_frame.py (test_storey_fe._frame's, with ρA)."""
    frame = Frame([64e3] * 3, [H] * 3, [COLUMNS] * 3, E, I, RHOA)
    h_b = H + xi * H - PODIUM
    nb = Neighbour([B_MASS], [4 * E * B_SECTION**4 / h_b**3])
    return frame, nb, Impact(2, xi, K_N * 1.0, gap=GAP, v0=0.0)


# --- what is compared --------------------------------------------------------------------------


def running_average_peak(t: np.ndarray, f: np.ndarray, window: float = WINDOW) -> float:
    """The largest average of f over `window` s, from uniform samples (trapezoid rule); pound's
    force history and the references' are read through this same function."""
    dt = t[1] - t[0]
    w = int(round(window / dt))
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dt)])
    return float(np.max(integral[w:] - integral[:-w]) / window)


@lru_cache(maxsize=None)
def reference(xi: float, model: str, n: int) -> dict:
    """The frame ("fe", n elements) or the reduced model ("reduced", n local modes, lumped
    form) for the scene at ξ, sampled at pound's contact step: {"impacts": (k, 4) t_start,
    t_end, peak force, impulse by t_start, "impulse", "fbar", "drifts", and over the impacts
    (±1 ms) "t", "F", "V_bot", "V_top" (end shears' magnitudes, N)}. The reduced model with 0
    modes has massless struck columns (pound's column_modes = 0): its end shears leave out the
    inertia of the storey shapes' consistent mass, ≤ 1.7 % of the force here."""
    frame, nb, imp = scene(xi)
    if model == "fe":
        m, x0, v0 = build_fe(frame, nb, imp, n)
    else:
        m, x0, v0 = build_reduced(frame, nb, imp, "c", n, residual=True, form="lumped")
        if n == 0:
            for name in ("V_bot", "V_top"):
                m.outputs[name] = Output(Dx=m.outputs[name].Dx, Fw=m.outputs[name].Fw)
    r = simulate(m, x0, v0, DURATION, STEP, ground=pulse(), energy=False)
    impacts = np.array([(p.t0, p.t1, p.peak, p.impulse) for p in r.impacts])
    stride = int(round(OUTPUT / STEP))
    near = (r.t >= impacts[0, 0] - 1e-3) & (r.t <= impacts[-1, 1] + 1e-3)
    return {"impacts": impacts, "impulse": r.impulse(), "fbar": running_average_peak(r.t[::stride], r.series["F"][::stride]),
            "drifts": {k: r.peak[k] for k in DRIFTS}, "t": r.t[near], "F": r.series["F"][near],
            "V_bot": np.abs(r.series["V_bot"][near]), "V_top": np.abs(r.series["V_top"][near])}  # fmt: skip


def pound_quantities(result) -> dict:
    """What pound's run gives, in reference()'s terms, and its demand table for the struck
    column as rows (impact, t_peak, |shear_bottom_x|, |shear_top_x|, the impact's force on the
    column: |impact_shear_bottom_x| + |impact_shear_top_x|), impacts numbered by t_start."""
    events = result.contact.events
    order = np.argsort(events["t_start"], kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    events = events[order]
    impacts = np.stack([events["t_start"], events["t_end"], events["peak_normal_force"], events["normal_impulse"]], axis=1)
    force = result.contact.normal_force.sum(axis=1)
    a, b = result.buildings["A"], result.buildings["B"]
    drifts = {"drift_A1": a.peak_displacement[0, 0], "drift_A2": np.max(a.interstorey_deflection[:, 1, 0]),
              "drift_A3": np.max(a.interstorey_deflection[:, 2, 0]), "drift_B1": b.peak_displacement[0, 0]}  # fmt: skip
    demand = result.contact.column_demand
    rows = np.array([(rank[r["event"]], r["t_peak"], abs(r["shear_bottom_x"]), abs(r["shear_top_x"]),
                      abs(r["impact_shear_bottom_x"]) + abs(r["impact_shear_top_x"])) for r in demand])  # fmt: skip
    return {"impacts": impacts, "impulse": float(events["normal_impulse"].sum()),
            "fbar": running_average_peak(result.time, force), "drifts": drifts, "rows": rows}  # fmt: skip


def implementation_errors(q: dict, ref: dict) -> dict:
    """q (pound's) against the reduced model: the LEAD first impacts one by one (peak force and
    impulse, relative; their starts and ends, in contact steps), the first start, then the
    totals: impulse, largest peak force, F̄, each peak drift (the largest relative error)."""
    a, b = q["impacts"], ref["impacts"]
    k = min(LEAD, len(b))
    assert len(a) >= k, f"{len(a)} impacts, the reference has {len(b)}"
    return {"lead": float(np.max(np.abs(a[:k, 2:] / b[:k, 2:] - 1))),
            "lead times": float(np.max(np.abs(a[:k, :2] - b[:k, :2]))) / STEP,
            "first start": abs(a[0, 0] - b[0, 0]) / STEP,
            "impulse": abs(q["impulse"] / ref["impulse"] - 1),
            "largest": abs(a[:, 2].max() / b[:, 2].max() - 1),
            "fbar": abs(q["fbar"] / ref["fbar"] - 1),
            "drifts": max(abs(q["drifts"][d] / ref["drifts"][d] - 1) for d in DRIFTS)}  # fmt: skip


def model_errors(q: dict, fe: dict) -> dict:
    """q (pound's or the reduced model's) against the frame: the first impact's peak force,
    the largest peak force, the total impulse, F̄ and the largest relative error of the peak
    drifts."""
    a, b = q["impacts"], fe["impacts"]
    return {"first peak": abs(a[0, 2] / b[0, 2] - 1), "largest": abs(a[:, 2].max() / b[:, 2].max() - 1),
            "impulse": abs(q["impulse"] / fe["impulse"] - 1), "fbar": abs(q["fbar"] / fe["fbar"] - 1),
            "drifts": max(abs(q["drifts"][d] / fe["drifts"][d] - 1) for d in DRIFTS)}  # fmt: skip


def shear_error(rows: np.ndarray, ref: dict, impacts: set[int]) -> float:
    """The largest |(|V| − |V_ref(t_peak)|)| over both ends and the rows of `impacts` (each
    must have one), over the row's impact force: the demand table's whole shear at each end
    against the reference's end shear at the same instant (linear between its samples at the
    contact step)."""
    worst, seen = 0.0, set()
    for k, t, v_bot, v_top, force in rows:
        if int(k) not in impacts:
            continue
        seen.add(int(k))
        for v, name in ((v_bot, "V_bot"), (v_top, "V_top")):
            worst = max(worst, abs(v - np.interp(t, ref["t"], ref[name])) / force)
    assert seen == impacts, f"no demand row for impacts {sorted(impacts - seen)}"
    return worst


def window_peak_shear(ref: dict, k: int) -> float:
    """The reference's largest end shear (|V_bot| or |V_top|) from the start of impact k to the
    start of the next (or the end of its samples): the impact and the column's ringing after it,
    the window over which pound keeps each impact's peak (solver/storey_bodies.track_column_shears)."""
    t0 = ref["impacts"][k, 0]
    t1 = ref["impacts"][k + 1, 0] if k + 1 < len(ref["impacts"]) else np.inf
    inside = (ref["t"] >= t0) & (ref["t"] < t1)
    return float(max(ref["V_bot"][inside].max(), ref["V_top"][inside].max()))


def peak_shear_error(rows: np.ndarray, ref: dict, k: int) -> float:
    """pound's peak end shear of impact k (the demand row's larger |shear|) against the
    reference's over the same window (window_peak_shear), relative."""
    (row,) = [r for r in rows if int(r[0]) == k]
    return abs(max(row[2], row[3]) / window_peak_shear(ref, k) - 1)


_POUND: dict = {}


def pound_case(folder, xi: float, modes: int) -> dict:
    """pound's run of the scene (its files in `folder`) as pound_quantities, with "complete",
    "storeys" and "xi" of its impacts and the demand table's "columns": one run per (ξ, modes)
    for all the tests that read it."""
    if (xi, modes) not in _POUND:
        result = run_model(validate_model(pound_model(folder, xi, modes), folder / "model.toml"), output=None)
        q = pound_quantities(result)
        events = result.contact.events
        q.update(complete=result.complete, storeys=set(events["storey_b"]), xi=np.asarray(events["xi"], dtype=float),
                 columns=set(result.contact.column_demand["column"]))  # fmt: skip
        _POUND[(xi, modes)] = q
    return _POUND[(xi, modes)]


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %" if x >= 0.01 else f"{100 * x:.2g} %"


def table(folder) -> str:
    """pound against the frame as a markdown table (docs/validation.md): per ξ and number of
    local modes (0: massless struck columns, for comparison), the frame's figures and pound's
    relative errors (model_errors; peak shear: peak_shear_error of the first impact)."""
    rows = ["| ξ | local modes | impacts (pound / frame) | frame: first peak F (kN) | largest peak F (kN) | error: first peak | largest peak | impulse | F̄ 1 ms | drifts | peak shear, first impact |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]  # fmt: skip
    for xi in XIS:
        fe = reference(xi, "fe", FE_ELEMENTS)
        for n in (0,) + N_FE:
            q = pound_case(folder, xi, n)
            e = model_errors(q, fe)
            rows.append(f"| {xi} | {n} | {len(q['impacts'])} / {len(fe['impacts'])} | {fe['impacts'][0, 2] / 1e3:.0f} | "
                        f"{fe['impacts'][:, 2].max() / 1e3:.0f} | {' | '.join(_pct(e[k]) for k in ('first peak', 'largest', 'impulse', 'fbar', 'drifts'))} | "
                        f"{_pct(peak_shear_error(q['rows'], fe, 0))} |")  # fmt: skip
    return "\n".join(rows)


def element_table(folder, modes: int = 12) -> str:
    """pound (`modes` local modes) against the frame meshed with 16, 32 and 64 Hermite elements
    in the struck column, per ξ: the relative errors of model_errors and the peak shear, as a
    markdown table (docs/validation.md): what of the error is the frame's own mesh."""
    rows = ["| ξ | frame's elements | error: first peak | largest peak | impulse | F̄ 1 ms | drifts | peak shear, first impact |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |"]  # fmt: skip
    for xi in XIS:
        q = pound_case(folder, xi, modes)
        for n_e in (16, 32, 64):
            fe = reference(xi, "fe", n_e)
            e = model_errors(q, fe)
            rows.append(f"| {xi} | {n_e} | {' | '.join(_pct(e[k]) for k in ('first peak', 'largest', 'impulse', 'fbar', 'drifts'))} | "
                        f"{_pct(peak_shear_error(q['rows'], fe, 0))} |")  # fmt: skip
    return "\n".join(rows)


# --- the tests -----------------------------------------------------------------------------------


@pytest.mark.parametrize("modes", N_IMPLEMENTATION)
@pytest.mark.parametrize("xi", XIS)
def test_pound_is_the_reduced_model(tmp_path, xi: float, modes: int) -> None:
    """pound with `modes` local modes against build_reduced(variant "c", the same modes, the
    residual flexibility, form "lumped"): the same equations, so what is left is pound's
    integration (the CDM at the contact step) and what the impacts' chatter makes of it."""
    q = pound_case(tmp_path, xi, modes)
    assert q["complete"]
    assert q["storeys"] == {2} and np.allclose(q["xi"], xi, atol=1e-12)
    errors = implementation_errors(q, reference(xi, "reduced", modes))
    for name, error in errors.items():
        assert error <= IMPLEMENTATION[modes][name], (name, error)


@pytest.mark.parametrize("modes", N_IMPLEMENTATION)
@pytest.mark.parametrize("xi", XIS)
def test_the_struck_columns_shear_is_the_reduced_models(tmp_path, xi: float, modes: int) -> None:
    """The demand table's whole shear at each end of the struck column (|shear_bottom_x|,
    |shear_top_x|) for the LEAD first impacts, at the step where pound found it largest (the
    module docstring), against the reduced model's Galerkin end shears there: K·u of the
    storey, the residual spring's share of the force by the fixed-end formulas (1 − s, s), and
    the inertia of the column's own mass, ρAh times the storey shapes' consistent mass on the
    floors' absolute accelerations plus ρAh·w_k on the modes' (build_reduced's outputs "V_bot",
    "V_top"; with 0 modes the struck column is massless and the reference leaves the storey
    shapes' inertia out, ≤ 1.7 % of the force); and that peak against the reduced model's over
    the same window (the impact and the ringing after it). The massless formulas miss the
    modes' inertia by 11–95 % of the force."""
    q = pound_case(tmp_path, xi, modes)
    ref = reference(xi, "reduced", modes)
    assert q["rows"].shape[0] == len(q["impacts"]) and q["columns"] == {"C8"}  # one struck column takes every impact
    lead = set(range(min(LEAD, len(q["impacts"]))))
    assert shear_error(q["rows"], ref, lead) <= IMPLEMENTATION[modes]["shear"]
    for k in sorted(lead) if modes else ():  # massless: the row is at the force's peak (test_storey_fe)
        if k + 1 < len(ref["impacts"]):  # a whole window: up to the next impact
            assert peak_shear_error(q["rows"], ref, k) <= IMPLEMENTATION[modes]["shear"]


@pytest.mark.parametrize("modes", N_FE)
@pytest.mark.parametrize("xi", XIS)
def test_pound_meets_the_frame_with_distributed_column_mass(tmp_path, xi: float, modes: int) -> None:
    """pound against the frame whose struck column is FE_ELEMENTS Hermite elements with
    consistent mass: the first impact's peak force, the largest peak force, the total
    impulse, F̄ (1 ms) and the peak drifts, each within model_tolerance."""
    q = pound_case(tmp_path, xi, modes)
    errors = model_errors(q, reference(xi, "fe", FE_ELEMENTS))
    for name, error in errors.items():
        assert error <= model_tolerance(modes, name), (name, error)


@pytest.mark.parametrize("modes", N_FE)
@pytest.mark.parametrize("xi", XIS)
def test_the_struck_columns_shear_meets_the_frame(tmp_path, xi: float, modes: int) -> None:
    """The demand table's peak shear of the first impact (and the ringing after it) against the
    frame's largest end shear over the same window (its end elements' K_e·u_e + M_e·ü_e),
    relative, within model_tolerance(modes, "shear")."""
    q = pound_case(tmp_path, xi, modes)
    fe = reference(xi, "fe", FE_ELEMENTS)
    assert peak_shear_error(q["rows"], fe, 0) <= model_tolerance(modes, "shear")


@pytest.mark.parametrize("xi", XIS)
def test_the_reduced_model_meets_the_frame_within_the_budget(xi: float) -> None:
    """No pound here: the reduced model's errors against the frame are within REDUCED_VS_FE, the
    share of model_tolerance that is the reduced model's own, so that the two checks above
    bound pound's error against the frame."""
    fe = reference(xi, "fe", FE_ELEMENTS)
    for n in N_FE:
        ref = reference(xi, "reduced", n)
        errors = model_errors(ref, fe)
        errors["shear"] = abs(window_peak_shear(ref, 0) / window_peak_shear(fe, 0) - 1)
        for name, error in errors.items():
            assert error <= REDUCED_VS_FE[n][name], (n, name, error)
