"""The reduced-model study for slab-to-column pounding (issue 23): prints its tables in markdown.

    python tests/fe_study.py            # every table (a few minutes on 2 busy cores)
    python tests/fe_study.py T2 T3      # some of them

The scene (the issue's shipped example, planar, printed with its derived figures at the top
of the output): the 5-storey building with 3.5 m storeys is struck in its third storey by the
roof of the paper's 3-storey building, at ξ = 0.25, 0.5, 0.75; pound's contact law for a
35 cm contact width; the neighbour sways in its first mode at 0.5 m/s; no damping.
"""

from __future__ import annotations

import sys
import time
from functools import lru_cache

import numpy as np

from fe_frame import (
    Frame,
    Impact,
    Neighbour,
    build_fe,
    build_reduced,
    clamped_beta,
    clamped_modal_data,
    point_load_flexibility,
    simulate,
)

E, NU, RHO = 21e9, 0.2, 2500.0
B_COL = 0.35
I = B_COL**4 / 12
EI = E * I
AREA = B_COL**2
RHOA = RHO * AREA
H = 3.5
K_N, WIDTH = 2.06e10, 0.35
K_C = K_N * WIDTH
V0 = 0.5
T_END = 0.35
DT = 1e-5
XIS = (0.25, 0.5, 0.75)
MESHES = (2, 4, 8, 16, 32, 64)
REF_MESH = 64
MODES = (1, 2, 3, 5, 8)
WINDOW = 1e-3


def scene(rhoA, xi, kc_factor=1.0, v0=V0):
    frame = Frame([64e3] * 5, [H] * 5, [9] * 5, E, I, rhoA)
    nb = Neighbour([128e3] * 3, [15 * 12 * EI / 3.0**3] * 3)
    return frame, nb, Impact(3, xi, K_C * kc_factor, v0=v0)


@lru_cache(maxsize=None)
def run(model, xi, rhoA=RHOA, n=0, kc_factor=1.0, other="lumped", form="cb", residual=True, extra_flex=0.0):
    """One impact: model = "fe" (n = elements per column) or a reduced variant "a", "b", "c"
    (n = local modes). Returns a dict of the measured quantities (SI) and the run time."""
    frame, nb, imp = scene(rhoA, xi, kc_factor)
    t0 = time.perf_counter()
    if model == "fe":
        m, x0, v0 = build_fe(frame, nb, imp, n, other_columns=other)
    else:
        m, x0, v0 = build_reduced(frame, nb, imp, model, n, residual=residual, form=form, extra_flex=extra_flex)
    r = simulate(m, x0, v0, T_END, DT, energy=False)
    s = r.summary()
    out = dict(s)
    out["last_end"] = r.impacts[-1].t1 if r.impacts else 0.0
    out["t_peak_dA"] = float(r.t[np.argmax(np.abs(r.series["drift_A3"]))])
    out.update(
        F_avg=r.window_peak("F", WINDOW),
        V_bot=r.peak["V_bot"], V_top=r.peak["V_top"],
        V_bot_avg=r.window_peak("V_bot", WINDOW), V_top_avg=r.window_peak("V_top", WINDOW),
        M_bot=r.peak["M_bot"], M_top=r.peak["M_top"],
        M_bot_avg=r.window_peak("M_bot", WINDOW), M_top_avg=r.window_peak("M_top", WINDOW),
        drift_A=r.peak["drift_A3"], drift_Amax=max(r.peak[f"drift_A{i}"] for i in range(1, 6)),
        drift_B=r.peak["drift_B3"],
        time=time.perf_counter() - t0,
    )  # fmt: skip
    for w in (2.5e-4, 5e-4, 2e-3, 5e-3):
        out[f"F_avg_{w * 1e3:g}"] = r.window_peak("F", w)
        out[f"V_bot_avg_{w * 1e3:g}"] = r.window_peak("V_bot", w)
        out[f"V_top_avg_{w * 1e3:g}"] = r.window_peak("V_top", w)
    out["F_avg_1"], out["V_bot_avg_1"], out["V_top_avg_1"] = out["F_avg"], out["V_bot_avg"], out["V_top_avg"]
    return out


# --- formatting ---------------------------------------------------------------------------------

COLS = [
    ("n_impacts", "impacts", 1, "d"),
    ("first_duration", "1st impact (ms)", 1e3, ".3f"),
    ("contact_time", "in contact (ms)", 1e3, ".2f"),
    ("impulse", "impulse (kN·s)", 1e-3, ".2f"),
    ("peak_F", "peak F (MN)", 1e-6, ".3f"),
    ("F_avg", "F̄ 1 ms (MN)", 1e-6, ".3f"),
    ("V_bot", "V bot (MN)", 1e-6, ".3f"),
    ("V_top", "V top (MN)", 1e-6, ".3f"),
    ("V_bot_avg", "V̄ bot 1 ms", 1e-6, ".3f"),
    ("V_top_avg", "V̄ top 1 ms", 1e-6, ".3f"),
    ("drift_A", "A storey 3 drift (mm)", 1e3, ".3f"),
    ("drift_B", "B storey 3 drift (mm)", 1e3, ".3f"),
]
ERR_KEYS = ["first_duration", "contact_time", "impulse", "peak_F", "F_avg", "V_bot", "V_top", "V_bot_avg", "V_top_avg", "drift_A", "drift_B"]


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def values(r, keys=None):
    return [format(r[k] * f, fmt) if fmt != "d" else str(r[k]) for k, _, f, fmt in COLS if keys is None or k in keys]


def err(r, ref, k):
    return (r[k] - ref[k]) / ref[k] if ref[k] else float("nan")


def pct(x):
    return f"{100 * x:+.1f} %" if abs(x) >= 1e-3 else f"{100 * x:+.2g} %"


def apct(x):
    """A magnitude (spread, |error|) as a percentage, without a sign."""
    return pct(x).lstrip("+")


def label(model, n):
    return {"a": "(a) outline", "b": "(b) + local flexibility"}.get(model, f"(c) {n} mode{'s' if n > 1 else ''}")


# --- the tables ----------------------------------------------------------------------------------


def T0():
    """The constants of the reduced model (c) for the study's column: what pound needs per mode."""
    print(f"### T0. Constants of the reduced model (c) for the study's column (h = {H} m, {B_COL * 100:g} × {B_COL * 100:g} cm, ρA = {RHOA:.2f} kg/m)\n")
    print("`fe_study.T0` (from `fe_frame.clamped_modal_data`). Mode k of the clamped–clamped column, unit mean square: modal mass m = ρAh = "
          f"{RHOA * H:.1f} kg, stiffness EI·(β_kL)⁴/h³, mass couplings to the floors below/above ρAh·α_k,b with α_k,b = ∫ψ_b·φ_k dξ (ψ = (1 − s, s)); "
          "the contact point's participation φ_k(ξ); the residual flexibility left for the series spring after n modes, as a fraction of a³b³/(3EIh³).\n")
    rows = []
    for k in range(1, 9):
        d = clamped_modal_data(k, 0.5)
        rows.append([k, f"{clamped_beta(k):.4f}", f"{EI * d['beta4'] / H**3 / 1e6:.1f}", f"{d['bb'][0]:+.4f}", f"{d['bb'][1]:+.4f}"]
                    + [f"{clamped_modal_data(k, xi)['phi_xi']:+.4f}" for xi in XIS])  # fmt: skip
    print(table(["k", "β_k·L", "k_k (MN/m)", "α_k,bottom", "α_k,top"] + [f"φ_k({xi})" for xi in XIS], rows))
    print()
    rows = []
    for n in (0, 1, 2, 3, 5, 8):
        row = [n]
        for xi in XIS:
            f0 = point_load_flexibility(EI, H, xi)
            fm = sum(clamped_modal_data(k, xi)["phi_xi"] ** 2 * H**3 / (EI * clamped_beta(k) ** 4) for k in range(1, n + 1))
            row.append(f"{(f0 - fm) / f0:.4f}")
        rows.append(row)
    print(table(["modes n"] + [f"residual / total at ξ = {xi}" for xi in XIS], rows))
    print()


def T1():
    """Massless columns: the FE (the mesh does not matter: Hermite statics is exact) against (a), (b)."""
    print("### T1. Massless columns: FE reference against the reduced models (a) and (b)\n")
    print("`fe_study.T1`: FE with 2 and 8 elements per struck column; relative differences of (a), (b) from FE-8.\n")
    rows = []
    for xi in XIS:
        ref = run("fe", xi, 0.0, 8)
        rows.append([xi, "FE, 8 elements"] + values(ref))
        r2 = run("fe", xi, 0.0, 2)
        rows.append([xi, "FE, 2 elements (difference)"] + [f"{err(r2, ref, k):.1e}" if k != "n_impacts" else str(r2[k]) for k, *_ in COLS])
        for model in ("a", "b"):
            r = run(model, xi, 0.0)
            rows.append([xi, label(model, 0)] + [(pct(err(r, ref, k)) if model == "a" else f"{err(r, ref, k):.1e}") if k != "n_impacts" else str(r[k]) for k, *_ in COLS])
    print(table(["ξ", "model"] + [c[1] for c in COLS], rows))
    print()


def T2():
    """Distributed column mass: the FE reference as the struck column's mesh is refined."""
    print(f"### T2. Distributed column mass (ρA = {RHOA:.2f} kg/m): FE convergence with elements per column\n")
    print("`fe_study.T2`; F̄, V̄: largest running average over 1 ms.\n")
    rows = []
    for xi in XIS:
        for n in MESHES:
            r = run("fe", xi, RHOA, n)
            rows.append([xi, n] + values(r))
    print(table(["ξ", "n_e"] + [c[1] for c in COLS], rows))
    print()
    print(f"Spread of each quantity over n_e = 8 … {REF_MESH} (max − min)/value at {REF_MESH}:\n")
    rows = []
    for xi in XIS:
        ref = run("fe", xi, RHOA, REF_MESH)
        rs = [run("fe", xi, RHOA, n) for n in MESHES if n >= 8]
        rows.append([xi] + [apct((max(r[k] for r in rs) - min(r[k] for r in rs)) / ref[k]) for k in ERR_KEYS])
    print(table(["ξ"] + [dict((c[0], c[1]) for c in COLS)[k] for k in ERR_KEYS], rows))
    print()


def T2b():
    """What the columns' distributed mass changes: FE 64 against the massless FE."""
    print(f"### T2b. Distributed against massless columns: FE {REF_MESH} (ρA = {RHOA:.2f} kg/m) over FE with ρA = 0\n")
    print("`fe_study.T2b`: ratios of the distributed-mass result to the massless one.\n")
    keys = ["impulse", "contact_time", "peak_F", "F_avg", "V_bot", "V_top", "V_bot_avg", "V_top_avg", "drift_A", "drift_B"]
    rows = []
    for xi in XIS:
        m, d = run("fe", xi, 0.0, 8), run("fe", xi, RHOA, REF_MESH)
        rows.append([xi, f"{m['n_impacts']} → {d['n_impacts']}"] + [f"{d[k] / m[k]:.3f}" for k in keys])
    print(table(["ξ", "impacts"] + [dict((c[0], c[1]) for c in COLS)[k] for k in keys], rows))
    print()


def T3():
    """Distributed mass: reduced models against the FE reference with REF_MESH elements."""
    print(f"### T3. Distributed column mass: reduced models against the FE reference ({REF_MESH} elements)\n")
    print("`fe_study.T3`: relative error of each reduced model; (c) n: Craig–Bampton with n clamped–clamped modes and the residual flexibility.\n")
    rows = []
    for xi in XIS:
        ref = run("fe", xi, RHOA, REF_MESH)
        rows.append([xi, f"FE {REF_MESH} (values)", ref["n_impacts"]] + values(ref, ERR_KEYS))
        for model, n in [("a", 0), ("b", 0)] + [("c", k) for k in MODES]:
            r = run(model, xi, RHOA, n)
            rows.append([xi, label(model, n), r["n_impacts"]] + [pct(err(r, ref, k)) for k in ERR_KEYS])
    print(table(["ξ", "model", "impacts"] + [dict((c[0], c[1]) for c in COLS)[k] for k in ERR_KEYS], rows))
    print()
    print("Largest |error| over ξ = 0.25, 0.5, 0.75:\n")
    print(worst_errors())
    print()


def worst_errors() -> str:
    """T3's summary as a markdown table: each reduced model's largest |error| over ξ = 0.25,
    0.5, 0.75 against the FE frame with distributed column mass (docs/validation.md shows it)."""
    rows = []
    for model, n in [("a", 0), ("b", 0)] + [("c", k) for k in MODES]:
        e = [max(abs(err(run(model, xi, RHOA, n), run("fe", xi, RHOA, REF_MESH), k)) for xi in XIS) for k in ERR_KEYS]
        rows.append([label(model, n)] + [apct(x) for x in e])
    return table(["model"] + [dict((c[0], c[1]) for c in COLS)[k] for k in ERR_KEYS], rows)


def T3b():
    """End moments: the reduced model's Galerkin end moments against the FE's element end moments."""
    print(f"### T3b. The struck column's end moments: reduced models against FE {REF_MESH}\n")
    print("`fe_study.T3b`: peaks and largest 1 ms running averages of the moments the column applies to the floors below (bot) and above (top); values of FE, relative errors of the reduced models.\n")
    keys = ["M_bot", "M_top", "M_bot_avg", "M_top_avg"]
    heads = ["M bot (MN·m)", "M top (MN·m)", "M̄ bot 1 ms", "M̄ top 1 ms"]
    rows = []
    for xi in XIS:
        ref = run("fe", xi, RHOA, REF_MESH)
        rows.append([xi, f"FE {REF_MESH} (values)"] + [f"{ref[k] / 1e6:.3f}" for k in keys])
        for model, n in [("b", 0)] + [("c", k) for k in (3, 5, 8)]:
            r = run(model, xi, RHOA, n)
            rows.append([xi, label(model, n)] + [pct(err(r, ref, k)) for k in keys])
        spread = [(max(run("fe", xi, RHOA, n)[k] for n in MESHES if n >= 8) - min(run("fe", xi, RHOA, n)[k] for n in MESHES if n >= 8)) / ref[k] for k in keys]
        rows.append([xi, "FE spread 8–64"] + [apct(x) for x in spread])
    print(table(["ξ", "model"] + heads, rows))
    print()


def T3c():
    """The residual flexibility: (c) with and without it."""
    print(f"### T3c. Craig–Bampton without the residual flexibility, against FE {REF_MESH}\n")
    print("`fe_study.T3c`: relative errors of (c) n when the truncated modes' static flexibility is dropped (contact spring on the modal expansion directly), next to (c) n with it (T3).\n")
    keys = ["impulse", "peak_F", "F_avg", "V_bot_avg", "V_top_avg", "drift_A"]
    rows = []
    for xi in (0.25, 0.5):
        ref = run("fe", xi, RHOA, REF_MESH)
        for n in (1, 3, 5, 8):
            for resid in (True, False):
                r = run("c", xi, RHOA, n, residual=resid)
                rows.append([xi, n, "with" if resid else "without", r["n_impacts"]] + [pct(err(r, ref, k)) for k in keys])
    print(table(["ξ", "modes", "residual", "impacts"] + [dict((c[0], c[1]) for c in COLS)[k] for k in keys], rows))
    print()


def T4():
    """Which averaging window: FE spread with the mesh and reduced-model error, per window."""
    print("### T4. Running-average window for the force and the column shear\n")
    print(f"`fe_study.T4`: for each window, the FE's spread over n_e = 8 … {REF_MESH} and the largest |error| of (c) against FE {REF_MESH}, over ξ = 0.25, 0.5, 0.75 (V̄: the larger of the two ends).\n")
    rows = []
    for w in ("0.25", "0.5", "1", "2", "5", "peak"):
        kF = "peak_F" if w == "peak" else f"F_avg_{w}"
        kV = ("V_bot", "V_top") if w == "peak" else (f"V_bot_avg_{w}", f"V_top_avg_{w}")
        row = [w if w == "peak" else f"{w} ms"]
        for keys in ((kF,), kV):
            spread = 0.0
            for xi in XIS:
                ref = run("fe", xi, RHOA, REF_MESH)
                rs = [run("fe", xi, RHOA, n) for n in MESHES if n >= 8]
                for k in keys:
                    spread = max(spread, (max(r[k] for r in rs) - min(r[k] for r in rs)) / ref[k])
            row.append(apct(spread))
            for n in (1, 2, 3, 5, 8):
                e = max(abs(err(run("c", xi, RHOA, n), run("fe", xi, RHOA, REF_MESH), k)) for xi in XIS for k in keys)
                row.append(apct(e))
        rows.append(row)
    print(table(["window", "F̄: FE spread"] + [f"F̄: (c) {n}" for n in (1, 2, 3, 5, 8)] + ["V̄: FE spread"] + [f"V̄: (c) {n}" for n in (1, 2, 3, 5, 8)], rows))
    print()


def T5():
    """Contact stiffness: does the FE converge when the contact is stiffer?"""
    print("### T5. A stiffer contact (k_c × 10, × 100), ξ = 0.5: FE convergence and the reduced model\n")
    print("`fe_study.T5`. k_c × 10 is k_N over a 3.5 m contact width (a slab edge along a wall or a deep spandrel), × 100 a penalty stiffness far above pound's law.\n")
    rows = []
    keys = ["impulse", "peak_F", "F_avg", "F_avg_2", "V_bot", "V_bot_avg", "V_bot_avg_2", "drift_A"]
    for f, meshes in ((1.0, (4, 8, 16, 32)), (10.0, (4, 8, 16, 32)), (100.0, (4, 8, 16, 32))):
        for n in meshes:
            r = run("fe", 0.5, RHOA, n, kc_factor=f)
            rows.append([f"× {f:g}", f"FE {n}", r["n_impacts"]] + [f"{r[k] * (1e3 if k == 'drift_A' else 1e-3 if k == 'impulse' else 1e-6):.3f}" for k in keys])
        for n in (3, 5, 8):
            r = run("c", 0.5, RHOA, n, kc_factor=f)
            rows.append([f"× {f:g}", f"(c) {n}", r["n_impacts"]] + [f"{r[k] * (1e3 if k == 'drift_A' else 1e-3 if k == 'impulse' else 1e-6):.3f}" for k in keys])
    print(table(["k_c", "model", "impacts", "impulse (kN·s)", "peak F (MN)", "F̄ 1 ms (MN)", "F̄ 2 ms (MN)", "V bot (MN)", "V̄ bot 1 ms", "V̄ bot 2 ms", "A storey 3 drift (mm)"], rows))
    print()
    print("How many local modes, against the contact's own frequency ω_c = √(k_c/ρAh) (the contact spring on one modal mass): the FE's spread over 8–32 elements and the errors of (c) n against FE 32, for the 1 ms averages.\n")
    rows = []
    w1 = np.sqrt(EI / (RHOA * H**4))
    for f in (1.0, 10.0, 100.0):
        wc = np.sqrt(K_C * f / (RHOA * H))
        n_rule = sum(1 for k in range(1, 40) if clamped_beta(k) ** 2 * w1 <= 2 * wc)
        fe = [run("fe", 0.5, RHOA, n, kc_factor=f) for n in (8, 16, 32)]
        ref = fe[-1]
        row = [f"× {f:g}", f"{wc:.0f}", n_rule]
        for k in ("F_avg", "V_bot_avg"):
            row.append(apct((max(r[k] for r in fe) - min(r[k] for r in fe)) / ref[k]))
            row += [pct(err(run("c", 0.5, RHOA, n, kc_factor=f), ref, k)) for n in (3, 5, 8)]
        rows.append(row)
    print(table(["k_c", "ω_c (rad/s)", "modes with ω_k ≤ 2ω_c", "F̄: FE spread", "F̄: (c) 3", "F̄: (c) 5", "F̄: (c) 8", "V̄ bot: FE spread", "V̄ bot: (c) 3", "V̄ bot: (c) 5", "V̄ bot: (c) 8"], rows))
    print()


def T6():
    """Modelling choices: the other columns' mass, the sprung and lumped forms of (c)."""
    print("### T6. Modelling choices that the comparison holds fixed\n")
    print("`fe_study.T6`: relative differences. FE 16 with the other columns (8 in the struck storey, 9 in the others) as explicit beams against the same columns condensed with the consistent mass of the storey shapes (\"guyan\": their local dynamics only), and that against their mass lumped half to each floor (the comparison's choice: the mass distribution only). (c) with 3 modes in sprung-mass coordinates (an exact change of variables) and with the floor mass block then lumped by rows (a diagonal mass matrix), against (c) 3 in Craig–Bampton form.\n")
    rows = []
    for xi in XIS:
        lumped, guyan, beam = (run("fe", xi, RHOA, 16, other=o) for o in ("lumped", "guyan", "beam"))
        rows.append([xi, "FE: other columns as beams vs guyan"] + [pct(err(beam, guyan, k)) for k in ERR_KEYS])
        rows.append([xi, "FE: guyan vs lumped"] + [pct(err(guyan, lumped, k)) for k in ERR_KEYS])
    for xi in XIS:
        a = run("c", xi, RHOA, 3)
        for form in ("sprung", "lumped"):
            b = run("c", xi, RHOA, 3, form=form)
            rows.append([xi, f"(c) 3, {form}"] + [f"{err(b, a, k):.1e}" if form == "sprung" else pct(err(b, a, k)) for k in ERR_KEYS])
    print(table(["ξ", "variant"] + [dict((c[0], c[1]) for c in COLS)[k] for k in ERR_KEYS], rows))
    print()


def timoshenko_ratio(k, h=H, kappa=5 / 6):
    """Frequency of the k-th clamped–clamped E–B mode's wavenumber β = β_k/h on a Timoshenko
    beam (the dispersion relation of an infinite beam: EIβ⁴ − ρAω² − ρI(1 + E/κG)β²ω² +
    (ρ²I/κG)ω⁴ = 0, lower root), divided by the E–B frequency."""
    G = E / (2 * (1 + NU))
    beta = clamped_beta(k) / h
    a4 = RHO**2 * I / (kappa * G)
    a2 = -(RHO * AREA + RHO * I * (1 + E / (kappa * G)) * beta**2)
    a0 = EI * beta**4
    w2 = (-a2 - np.sqrt(a2 * a2 - 4 * a4 * a0)) / (2 * a4)
    return np.sqrt(w2) / np.sqrt(a0 / (RHO * AREA))


def T7():
    """Limits: shear deformation, and what a real column could take."""
    print("### T7. Limits of the Euler–Bernoulli idealisation\n")
    G = E / (2 * (1 + NU))
    kGA = 5 / 6 * G * AREA
    print(f"`fe_study.T7`. Shear deformation (κ = 5/6, G = E/2(1+ν) = {G / 1e9:.2f} GPa): extra local flexibility of the point load, a·b/(κGA·h), against the bending a³b³/(3EIh³), and the storey's φ = 12EI/(κGAh²) = {12 * EI / (kGA * H**2):.3f}.\n")
    rows = []
    for xi in XIS:
        a, b = xi * H, (1 - xi) * H
        shear = a * b / (kGA * H)
        bend = point_load_flexibility(EI, H, xi)
        m = run("b", xi, 0.0)
        ms = run("b", xi, 0.0, extra_flex=shear)
        mc = run("c", xi, RHOA, 3)
        mcs = run("c", xi, RHOA, 3, extra_flex=shear)
        rows.append([xi, pct(shear / bend), pct(err(ms, m, "peak_F")), pct(err(ms, m, "V_bot")), pct(err(ms, m, "first_duration")),
                     pct(err(mcs, mc, "F_avg")), pct(err(mcs, mc, "V_bot_avg"))])  # fmt: skip
    print(table(["ξ", "shear / bending local flexibility", "massless (b): peak F", "peak V bot", "duration", "(c) 3: F̄ 1 ms (residual only)", "V̄ bot 1 ms"], rows))
    print()
    print("Local modes: E–B frequency of the clamped–clamped column modes and the Timoshenko frequency at the same wavenumber.\n")
    rows = []
    wEB1 = np.sqrt(EI / (RHOA * H**4))
    for k in range(1, 9):
        w = clamped_beta(k) ** 2 * wEB1
        rows.append([k, f"{clamped_beta(k):.4f}", f"{w:.0f}", f"{w / (2 * np.pi):.0f}", f"{2 * np.pi / w * 1e3:.2f}", f"{timoshenko_ratio(k):.3f}"])
    print(table(["mode k", "β_k·L", "ω_k (rad/s)", "f_k (Hz)", "period (ms)", "Timoshenko / E–B"], rows))
    print()
    fc, b_mm, d_mm = 25.0, 350.0, 310.0
    Vc = 0.17 * np.sqrt(fc) * b_mm * d_mm  # N (ACI 318 concrete contribution, MPa and mm)
    print(f"Column demand per unit approach speed (the model is linear; gap 0): F̄ and V̄ over 1 ms from FE {REF_MESH}, and the speed at which V̄ reaches an assumed shear strength, here only the concrete contribution of ACI 318 for f′c = {fc:g} MPa, b = {b_mm:g} mm, d = {d_mm:g} mm: V_c = 0.17·√f′c·b·d = {Vc / 1e3:.0f} kN (stirrups would add to it).\n")
    rows = []
    for xi in XIS:
        r = run("fe", xi, RHOA, REF_MESH)
        vmax = max(r["V_bot_avg"], r["V_top_avg"])
        rows.append([xi, f"{r['F_avg'] / V0 / 1e6:.2f}", f"{vmax / V0 / 1e6:.2f}", f"{Vc / (vmax / V0):.3f}"])
    print(table(["ξ", "F̄ per m/s (MN·s/m)", "max V̄ per m/s (MN·s/m)", "speed at V̄ = V_c (m/s)"], rows))
    print()


def T8():
    """Cost: run times and event counts of the reference and the reduced models."""
    print("### T8. Cost of the runs above (wall time on this machine, 0.35 s simulated)\n")
    print("`fe_study.T8` (from the cache of the runs above; times are noisy on a shared machine).\n")
    rows = []
    for xi in XIS:
        for key in [("fe", n) for n in MESHES] + [("b", 0)] + [("c", k) for k in MODES]:
            r = run(key[0], xi, RHOA, key[1])
            rows.append([xi, f"FE {key[1]}" if key[0] == "fe" else label(*key), r["n_impacts"], f"{r['last_end'] * 1e3:.1f}", f"{r['t_peak_dA'] * 1e3:.1f}", f"{r['time']:.2f}"])
    print(table(["ξ", "model", "impacts", "last impact ends (ms)", "A storey 3 drift peaks at (ms)", "time (s)"], rows))
    print()
    print(f"The next impact episode: FE 16 run on to 0.6 s; the first impact that starts after {T_END} s.\n")
    rows = []
    for xi in XIS:
        frame, nb, imp = scene(RHOA, xi)
        m, x0, v0 = build_fe(frame, nb, imp, 16)
        r = simulate(m, x0, v0, 0.6, 1e-4, energy=False)
        later = [p.t0 for p in r.impacts if p.t0 > T_END]
        rows.append([xi, f"{later[0] * 1e3:.1f}" if later else "none"])
    print(table(["ξ", "next impact starts (ms)"], rows))
    print()


ALL = {"T0": T0, "T1": T1, "T2": T2, "T2b": T2b, "T3": T3, "T3b": T3b, "T3c": T3c, "T4": T4, "T5": T5, "T6": T6, "T7": T7, "T8": T8}


def scene_text():
    """The scene, with every derived figure computed here."""
    frame, nb, imp = scene(RHOA, 0.5)
    z_roof = 3 * 3.0
    z0, z1 = 2 * H, 3 * H
    return (
        f"The struck building A has {len(frame.masses)} storeys of {H} m, {frame.masses[0] / 1e3:g} t floors and {frame.n_columns[0]} columns of "
        f"{B_COL * 100:g} × {B_COL * 100:g} cm per storey (E = {E / 1e9:g} GPa, ρ = {RHO:g} kg/m³, so ρA = {RHOA:.2f} kg/m and EI = {EI / 1e6:.2f} MN·m²). "
        f"The neighbour B is the paper's right building: {len(nb.masses)} storeys of 3.0 m, {nb.masses[0] / 1e3:g} t floors, 15 columns of "
        f"{B_COL * 100:g} × {B_COL * 100:g} cm, all taken square in this planar model (storey stiffness {nb.stiffness[0] / 1e6:.1f} MN/m). "
        f"B's roof ({z_roof:g} m) strikes A's storey {imp.storey} ({z0:g}–{z1:g} m) at ξ = {(z_roof - z0) / H:.3f} in the issue's example; "
        f"the study sets ξ = {', '.join(f'{x:g}' for x in XIS)}. "
        f"Contact k_c = k_N·L = {K_N:.3g} N/m² × {WIDTH} m = {K_C:.3g} N/m, no dashpot, no friction, gap 0. "
        f"B sways in its first mode with its roof at v0 = {V0} m/s towards A, and A is at rest. There is no damping. "
        f"{T_END} s are simulated, sampled every {DT * 1e6:g} µs. T8 shows that this holds one impact episode and the struck storey's drift peak. "
        "The other columns of the struck storey and the columns of the other storeys are lumped (12EI/h³ each, half their mass to each end floor) "
        "in both the FE reference and the reduced models, so the comparison isolates the struck column (T6 shows what that choice moves)."
    )


def main(argv):
    names = argv or list(ALL)
    print(scene_text())
    print()
    for name in names:
        t0 = time.perf_counter()
        ALL[name]()
        print(f"<!-- {name}: {time.perf_counter() - t0:.0f} s -->\n", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
