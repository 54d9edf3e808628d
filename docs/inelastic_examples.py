"""Run the shipped inelastic and isolated examples and write docs/inelastic.md with its figures.

    python docs/inelastic_examples.py [--jobs 2] [--out DIR]

Runs inputs/paper_inelastic.toml (the paper's buildings, every column yielding) beside
inputs/paper_pounding.toml (the same, linear), and the sweep inputs/isolated_moat.sweep.toml
(a base-isolated building at several moat gaps) through `pound sweep`'s machinery into DIR
(default: a temporary folder). The figures (isolator and column hysteresis loops, energy) go to
docs/images/inelastic-*.png, and what each shows (docs/make_report_images.py's signature) to
docs/images/inelastic-images.json, which `python docs/build.py --check` compares. Nothing is
tuned: the page reports what the runs give, and no timing (those are the bench's:
docs/bench.md), so that it is the same on every run.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import json
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "inelastic.md"
IMAGES = ROOT / "docs" / "images"
SIGNATURES = IMAGES / "inelastic-images.json"
SIGNED: dict[str, dict] = {}
"""What each image written shows (image name -> signature), for SIGNATURES."""


def save(fig, path: Path) -> None:
    """Write a figure, and keep its signature (docs/make_report_images.py) for SIGNATURES."""
    from make_report_images import save_signed  # docs/, the script's folder, is on sys.path

    save_signed(fig, path, SIGNED)


def loops_figure(runs: dict[str, object], building: str, member: str, path: Path) -> None:
    """Force against deflection of one member along local x and y, one line per run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), layout="constrained")
    for label, run in runs.items():
        y = run.buildings[building].yielding
        k = [str(n) for n in y.members["name"]].index(member)
        for a, ax in enumerate(axes):
            ax.plot(1e3 * y.deflection[:, k, a], 1e-3 * y.force[:, k, a], lw=0.7, label=label)
    fy = 1e-3 * y.members["yield_force"][k]
    for a, ax in enumerate(axes):
        for sign in (1, -1):
            ax.axhline(sign * fy[a], color="0.6", lw=0.6, ls="--")
        ax.set_xlabel(f"deflection along local {'xy'[a]} (mm)")
        ax.set_ylabel(f"force along local {'xy'[a]} (kN)")
        ax.set_title(f"{building} {member}, local {'xy'[a]} (dashed: ±F_y)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    save(fig, path)


def energy_figure(run: object, title: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 3.6), layout="constrained")
    names = ["kinetic", "strain", "damping", "hysteretic", "contact"]
    ax.stackplot(run.time, *[1e-3 * run.energy_column(n) for n in names], labels=names, alpha=0.8)
    ax.plot(run.time, 1e-3 * run.energy_column("input"), color="k", lw=0.8, label="input")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (kJ)")
    ax.set_title(title)
    ax.legend(loc="upper left", fontsize=8)
    save(fig, path)


def member_rows(run: object, building: str) -> dict[str, float]:
    y = run.buildings[building].yielding
    cols = y.members["kind"] == "column"
    iso = y.members["kind"] == "isolator"
    out = {}
    if cols.any():
        duct = y.ductility[cols]
        out["max_ductility"] = float(duct.max())
        out["yielded"] = int((duct.max(axis=1) > 1).sum())
        out["members"] = int(cols.sum())
        out["residual_mm"] = float(1e3 * np.hypot(*y.residual_deflection[cols].T).max())  # resultant
        out["residual_axis_mm"] = float(1e3 * np.abs(y.residual_deflection[cols]).max())  # one local axis
    if iso.any():
        out["iso_disp_mm"] = float(1e3 * y.peak[iso, 2].max())
        out["iso_force_kN"] = float(1e-3 * y.peak[iso, 5].max())
        out["iso_residual_mm"] = float(1e3 * np.hypot(*y.residual_deflection[iso].T).max())
    return out


def drift_mm(run: object, building: str, first_storey: int = 0) -> float:
    """Largest peak interstorey deflection (x or y) over the building's columns, mm."""
    d = run.buildings[building].interstorey_deflection[:, first_storey:, :2]
    return float(1e3 * np.nanmax(d))


def isolated_mode_damping() -> dict[str, float]:
    """The isolated building of inputs/isolated_moat.toml with its bearings on K2: the period of
    its first (isolated) mode and of its fourth (the superstructure's, on the bearings), and
    their damping ratios φᵀCφ/(2ω) from pound's C and from the former Rayleigh damping of the
    whole building on K1 (modes 1 and 3), as tests/test_isolation_damping.py computes them."""
    import scipy.linalg

    from pounding_cli import load_model
    from pounding_cli.api import prepare
    from pounding_cli.assembly.modal import rayleigh_coefficients
    from pounding_cli.solver.integrate import damping_blocks

    scene = prepare(load_model(ROOT / "inputs" / "isolated_moat.toml"))
    b = scene.system.buildings[0]
    c = damping_blocks(scene.system)[0]
    k2 = b.stiffness.copy()
    k2[:3, :3] -= 0.9 * b.storey_k[0][3:, 3:]  # K2 = 0.1·K1
    omega2, phi = scipy.linalg.eigh(k2, np.diag(b.mass))
    omega = np.sqrt(omega2)
    w = b.modes.omega
    a0, a1 = rayleigh_coefficients(w[0], w[2], 0.05, 0.05)
    c_old = a0 * np.diag(b.mass) + a1 * b.stiffness

    def ratio(cc: np.ndarray, n: int) -> float:
        return float(phi[:, n] @ cc @ phi[:, n] / (2 * omega[n]))

    return {"period": float(2 * np.pi / omega[0]), "new": ratio(c, 0), "old": ratio(c_old, 0),
            "period_super": float(2 * np.pi / omega[3]), "new_super": ratio(c, 3)}  # fmt: skip


def energy_shares(run: object) -> dict[str, float]:
    e_in = run.energy_column("input")[-1]
    return {n: float(run.energy_column(n)[-1] / e_in) for n in ("damping", "hysteretic", "contact")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    from pounding_cli import read_hdf5, run_model
    from pounding_cli.sweep import run_sweep

    IMAGES.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.out or Path(tmp)
        inelastic = run_model(ROOT / "inputs" / "paper_inelastic.toml")
        linear = run_model(ROOT / "inputs" / "paper_pounding.toml")
        outcome = run_sweep(ROOT / "inputs" / "isolated_moat.sweep.toml", folder / "isolated_moat", jobs=args.jobs,
                            log=lambda text: print(text, file=sys.stderr))  # fmt: skip
        cases = {row["case"]: read_hdf5(folder / "isolated_moat" / row["file"]) for row in outcome.rows}
    loops_figure({"yielding columns": inelastic}, "left", "C9", IMAGES / "inelastic-column-loop.png")
    energy_figure(inelastic, "paper_inelastic.toml: energy balance", IMAGES / "inelastic-energy.png")
    shown = {k: v for k, v in cases.items() if k in ("gap 5 cm", "gap 20 cm", "no contact (d = ∞)")}
    loops_figure(shown, "isolated", "I9", IMAGES / "inelastic-isolator-loops.png")
    energy_figure(cases["gap 10 cm"], "isolated_moat.toml (moat gap 10 cm): energy balance",
                  IMAGES / "inelastic-isolated-energy.png")  # fmt: skip
    PAGE.write_text(page(inelastic, linear, cases, outcome, args.jobs), encoding="utf-8")
    SIGNATURES.write_text(json.dumps(SIGNED, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {PAGE} and {SIGNATURES}", file=sys.stderr)


def page(inelastic, linear, cases: dict, outcome, jobs: int) -> str:
    d = isolated_mode_damping()
    m = member_rows(inelastic, "left")
    mr = member_rows(inelastic, "right")
    e = energy_shares(inelastic)
    rows = []
    for name, run in cases.items():
        r = member_rows(run, "isolated")
        events = run.contact.events
        moat = events[[str(b).startswith("isolated.moat") for b in events["body_b"]]] if events.size else events
        neighbour = events[[str(b) == "neighbour" for b in events["body_b"]]] if events.size else events
        rows.append(
            f"| {name} | {r['iso_disp_mm']:.1f} | {r['iso_force_kN']:.1f} | {r['iso_residual_mm']:.1f} | "
            f"{len(moat)} | {1e-3 * float(moat['peak_normal_force'].max(initial=0)):.0f} | {len(neighbour)} | "
            f"{drift_mm(run, 'isolated', 1):.2f} | {drift_mm(run, 'neighbour'):.2f} | "
            f"{100 * energy_shares(run)['hysteretic']:.0f} % | {run.balance_error_ratio:.1e} |"
        )
    table = "\n".join(rows)
    return f"""<!-- Generated whole by docs/inelastic_examples.py; do not edit by hand. Rebuild with
python docs/build.py inelastic, check with python docs/build.py --check. -->
# Inelastic columns and seismic isolation: the shipped examples

Generated by `python docs/inelastic_examples.py` (through `python docs/build.py`, which CI
checks) from the shipped examples (the public-domain 2019 Ridgecrest CI.CCC record, PGA
0.53 g / 0.47 g); nothing is tuned. Solver times are the bench's ([bench.md](bench.md)): its
scene `inelastic` is the yielding model below at 1.5 × the record, `isolated` a building like
the isolated one below, its moat 18 cm away. The model fields are in
the [user guide](user-guide.md#inelastic-columns-hysteresis), the equations in
[theory §12](theory.md#12-yielding-members-inelastic-columns-and-seismic-isolation), the checks in
the [validation report](validation.md#yielding-members).

## The paper's buildings with yielding columns

`inputs/paper_inelastic.toml` is `inputs/paper_pounding.toml` (the paper's two buildings, 5 cm
apart) with every column yielding at 1 cm of interstorey deflection and hardening at 5 % of
its elastic stiffness, on an elliptical yield surface.

| | linear (`paper_pounding.toml`) | yielding (`paper_inelastic.toml`) |
| --- | ---: | ---: |
| impacts | {linear.contact.impact_count} | {inelastic.contact.impact_count} |
| peak impact force (MN) | {linear.contact.peak_force / 1e6:.2f} | {inelastic.contact.peak_force / 1e6:.2f} |
| left: largest peak interstorey deflection (mm) | {drift_mm(linear, 'left'):.1f} | {drift_mm(inelastic, 'left'):.1f} |
| right: largest peak interstorey deflection (mm) | {drift_mm(linear, 'right'):.1f} | {drift_mm(inelastic, 'right'):.1f} |
| left: columns that yielded / largest ductility | – | {m['yielded']} of {m['members']} / {m['max_ductility']:.2f} |
| right: columns that yielded / largest ductility | – | {mr['yielded']} of {mr['members']} / {mr['max_ductility']:.2f} |
| left / right: largest residual column deflection, resultant (mm) | – | {m['residual_mm']:.2f} / {mr['residual_mm']:.2f} |
| energy dissipated: damping / hysteresis / contact | {100 * energy_shares(linear)['damping']:.0f} % / – / {100 * energy_shares(linear)['contact']:.1f} % | {100 * e['damping']:.0f} % / {100 * e['hysteretic']:.0f} % / {100 * e['contact']:.1f} % |
| energy balance error (of the input) | {linear.balance_error_ratio:.1e} | {inelastic.balance_error_ratio:.1e} |

Ductility is a member's peak deflection over its yield deflection along one of its local axes
(above 1: it yielded); the residual deflection is where the column comes to rest once the
motion dies away, given here as the resultant √(δ_x² + δ_y²) of its two local axes, as
`pound run`'s summary (`largest residual |δ|`) and the sweep's `max_residual_deflection_m[B]`
give it. Along a single local axis the largest is {m['residual_axis_mm']:.2f} mm (left) and
{mr['residual_axis_mm']:.2f} mm (right); `/buildings/<b>/peaks/residual_deflection` holds both axes.

![Column C9 of the left building: force against deflection](images/inelastic-column-loop.png)

![Energy balance of the yielding example](images/inelastic-energy.png)

## A base-isolated building against its moat wall

`inputs/isolated_moat.toml`: a 4-storey building (the paper's left building) on a base slab
0.5 m above the ground, carried by nine lead-rubber bearings (K1 = 2.25 MN/m, K2 = 0.225 MN/m,
Q = 17.5 kN: an isolated period of about 2.5 s, Q = 5 % of the weight), inside a moat wall;
its floors are level with those of a fixed-base 3-storey neighbour 8 cm away (the wall lies below the neighbour's first floor: only bodies at one level meet).
`inputs/isolated_moat.sweep.toml` runs it at moat gaps of 5 to 40 cm and without contact.

Its 5 % Rayleigh damping is the superstructure's, fitted to the superstructure's modes on a
fixed base and acting on its deformation only; the isolation system is damped by the bearings'
hysteresis (no viscous `isolation.damping_ratio`), the standard practice for base-isolated
buildings ([theory §12](theory.md#damping-of-an-isolated-building); Ryan & Polanco 2008).
The isolated mode ({d['period']:.2f} s with the bearings on K2) thus gets {100 * d['new']:.3f} % of
critical from viscous damping, where Rayleigh damping of the whole building on the bearings'
initial stiffness gave it {100 * d['old']:.1f} %; the superstructure's mode on the bearings
({d['period_super']:.2f} s) gets {100 * d['new_super']:.1f} %.

Isolator columns: peak resultant displacement, peak resultant force and residual displacement
of the worst bearing; moat impacts and their peak force; impacts with the neighbour; the
largest superstructure drift (storeys above the isolation storey) and the neighbour's; the
share of the input energy the bearings dissipated.

| case | isolator disp. (mm) | isolator force (kN) | residual (mm) | moat impacts | peak moat force (kN) | neighbour impacts | superstructure drift (mm) | neighbour drift (mm) | hysteretic | balance error |
| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |
{table}

The sweep's {len(outcome.rows)} cases are one `pound sweep inputs/isolated_moat.sweep.toml`.

![Isolator I9: force against displacement at three moat gaps](images/inelastic-isolator-loops.png)

![Energy balance of the isolated building, moat gap 10 cm](images/inelastic-isolated-energy.png)

{findings(cases)}

`pound report` on any of these files prints the yielding members and draws the loops
(`--plots`).
"""


def findings(cases: dict) -> str:
    """What the moat sweep shows, in numbers from the runs."""

    def hits(run, prefix: str) -> int:
        return sum(str(b).startswith(prefix) for b in run.contact.events["body_b"]) if run.contact.events.size else 0

    free = cases["no contact (d = ∞)"]
    narrow, wide = cases["gap 5 cm"], cases["gap 40 cm"]
    return (
        f"With a 5 cm moat the base slab hit the wall {hits(narrow, 'isolated.moat')} times: the bearings' "
        f"loops are cut off at the wall (peak displacement {member_rows(narrow, 'isolated')['iso_disp_mm']:.0f} mm "
        f"against {member_rows(free, 'isolated')['iso_disp_mm']:.0f} mm free) and the impacts drive the "
        f"superstructure's drift from {drift_mm(free, 'isolated', 1):.1f} mm to {drift_mm(narrow, 'isolated', 1):.1f} mm. "
        f"With a 40 cm moat the slab never reaches the wall, but the floors, free to move with the bearings, "
        f"hit the neighbour {hits(wide, 'neighbour')} times across its 8 cm joint (superstructure drift "
        f"{drift_mm(wide, 'isolated', 1):.1f} mm): the moat gap and the joint to a neighbour must be chosen together."
        + "".join(
            f" With a {name.removeprefix('gap ')} moat it hits both in one run: the wall {hits(run, 'isolated.moat')} "
            f"times and the neighbour {hits(run, 'neighbour')} times."
            for name, run in cases.items()
            if hits(run, "isolated.moat") and hits(run, "neighbour")
        )
    )


if __name__ == "__main__":
    main()
