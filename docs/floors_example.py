"""Run the shipped floors-at-different-heights example and write docs/floors.md with its figures.

    python docs/floors_example.py

Runs inputs/mismatched_floors.toml (a 5-storey building with 3.5 m storeys beside the paper's
3-storey building with 3.0 m storeys, 5 cm apart, under the shipped Ridgecrest record) with its
output every millisecond, so that the histories resolve the impacts, and writes where the
impacts fall and the most loaded struck column's shear history against its capacity to
docs/images/floors-*.png (what each shows, docs/make_report_images.py's signature, to
docs/images/floors-images.json, which `python docs/build.py --check` compares), and the page
docs/floors.md. Nothing is tuned and no timing is quoted (those are the bench's).
"""

from __future__ import annotations

import json
import sys
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "floors.md"
IMAGES = ROOT / "docs" / "images"
SIGNATURES = IMAGES / "floors-images.json"
MODEL = ROOT / "inputs" / "mismatched_floors.toml"
OUTPUT_INTERVAL = 0.001  # s: the histories resolve impacts of 10–190 ms
SIGNED: dict[str, dict] = {}


def save(fig, path: Path) -> None:
    """Write a figure, and keep its signature (docs/make_report_images.py) for SIGNATURES."""
    from make_report_images import save_signed  # docs/, the script's folder, is on sys.path

    save_signed(fig, path, SIGNED)


def run():
    """(scene, result) of the example with its output every OUTPUT_INTERVAL."""
    from pounding_cli.api import execute, prepare
    from pounding_cli.model import validate_model

    doc = tomllib.loads(MODEL.read_text(encoding="utf-8"))
    doc["analysis"]["output_interval"] = OUTPUT_INTERVAL
    scene = prepare(validate_model(doc, MODEL))
    return scene, execute(scene)


def where_figure(scene, result, path: Path) -> None:
    """Elevation: both buildings' levels side by side, each impact drawn at its slab's elevation
    on the struck side, labelled with the storey and ξ; right: the impacts against time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.6), layout="constrained", width_ratios=(1, 1.6))
    buildings = scene.system.buildings
    for k, b in enumerate(buildings):
        x0 = 0.0 if k == 0 else 1.2
        for z0, z1 in zip(b.levels[:-1], b.levels[1:]):
            ax.add_patch(plt.Rectangle((x0, z0), 1.0, z1 - z0, fill=False, lw=0.8))
        ax.text(x0 + 0.5, b.levels[-1] + 0.3, b.name, ha="center", fontsize="small")
    events = result.contact.events
    names = [b.name for b in buildings]
    for (body_b, storey, xi, z), count in _struck(events).items():
        x = 0.0 if names.index(body_b) == 0 else 1.2
        edge = x + 1.0 if x == 0.0 else x
        ax.annotate(f"storey {storey}, ξ = {xi:.2f} ({count}×)", xy=(edge, z), xytext=(edge + (0.25 if x else -0.25), z),
                    ha="left" if x else "right", va="center", fontsize="x-small",
                    arrowprops=dict(arrowstyle="->", lw=0.8))  # fmt: skip
    ax.set_xlim(-1.6, 3.8)
    ax.set_ylim(0, max(b.levels[-1] for b in buildings) + 1.0)
    ax.set_xticks([])
    ax.set_ylabel("elevation (m)")
    ax.set_title("where the slabs strike", fontsize="small")
    for body_b in sorted(set(str(b) for b in events["body_b"])):
        mine = events[events["body_b"] == body_b]
        bx.scatter(mine["t_peak"], mine["elevation"], s=20 + 200 * mine["peak_normal_force"] / events["peak_normal_force"].max(),
                   label=f"into {body_b}", alpha=0.7)  # fmt: skip
    bx.set_xlabel("time (s)")
    bx.set_ylabel("elevation of the striking slab (m)")
    bx.set_title("impacts (marker area ∝ peak force)", fontsize="small")
    bx.legend(fontsize="small")
    save(fig, path)


def _struck(events) -> dict[tuple[str, int, float, float], int]:
    """(struck building, storey, ξ, elevation) → impacts."""
    out: dict[tuple[str, int, float, float], int] = {}
    for e in events:
        key = (str(e["body_b"]), int(e["storey_b"]), float(e["xi"]), float(e["elevation"]))
        out[key] = out.get(key, 0) + 1
    return out


def shear_figure(scene, result, row, path: Path) -> None:
    """The shear of the most loaded struck column (the row of /impacts/column_demand with the
    largest ratio) at its foot and top along its local x, from the stored histories, against
    its capacity, with the logged impacts' values at their peaks."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pounding_cli.results.column_demand import struck_column_shears

    body, column = _body_and_column(scene, row)
    pair = scene.contact.pairs.index(next(p for p in scene.contact.pairs if p.storey and p.body_b == row["building"]
                                          and p.storey == row["storey"] and abs(p.xi - row["xi"]) < 1e-12))  # fmt: skip
    c = result.contact
    inward = -body.normal  # the force on the struck building: along the inward normal, friction along the façade
    force = np.outer(c.normal_force[:, pair], inward) + np.outer(c.tangential_force[:, pair], [-inward[1], inward[0]])
    motion = np.concatenate([b.displacement for b in result.buildings.values()], axis=1)
    shears = struck_column_shears(scene.system, body, column, result.time, force, result.time, motion)
    window = (result.time > row["t_peak"] - 1.5) & (result.time < row["t_peak"] + 1.5)
    fig, ax = plt.subplots(figsize=(10, 4.2), layout="constrained")
    t = result.time[window]
    ax.plot(t, 1e-3 * shears["bottom"][window, 0], lw=0.8, label="at its foot")
    ax.plot(t, 1e-3 * shears["top"][window, 0], lw=0.8, label="at its top")
    demand = c.column_demand[(c.column_demand["building"] == row["building"]) & (c.column_demand["column"] == row["column"])
                             & (c.column_demand["storey"] == row["storey"])]  # fmt: skip
    for name, marker in (("shear_bottom_x", "o"), ("shear_top_x", "s")):
        ax.plot(demand["t_peak"], 1e-3 * demand[name], marker, ms=4, mfc="none", color="k", lw=0)
    cap = 1e-3 * row["capacity_x"]
    ax.axhline(cap, color="tab:red", lw=0.8, ls="--", label=f"shear_capacity ±{cap:.0f} kN")
    ax.axhline(-cap, color="tab:red", lw=0.8, ls="--")
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("time (s)")
    ax.set_ylabel("shear along local x (kN)")
    ax.set_title(f"{row['building']} {row['column']}, storey {row['storey']}, struck at ξ = {row['xi']:.2f}: "
                 f"shear from the stored histories (every {1e3 * OUTPUT_INTERVAL:g} ms), ○ □ at each impact's peak",
                 fontsize="small")  # fmt: skip
    ax.legend(fontsize="small")
    save(fig, path)


def _body_and_column(scene, row):
    """The storey body and the column index (into its building's columns) of a demand row."""
    contact = scene.contact
    for body in contact.storeys:
        struck = scene.system.buildings[body.crossing.struck]
        if struck.name == row["building"] and body.crossing.storey == row["storey"]:
            for i in body.columns:
                if struck.column_lines[struck.columns[i].line].name == row["column"]:
                    return body, i
    raise LookupError(row)


def page(scene, result) -> str:
    events = result.contact.events
    demand = result.contact.column_demand
    struck_rows = "\n".join(
        f"| {body_b} | {storey} | {xi:.3f} | {z:g} | {count} |" for (body_b, storey, xi, z), count in sorted(_struck(events).items())
    )  # fmt: skip
    worst = []
    for building in sorted(set(str(b) for b in demand["building"])):
        mine = demand[demand["building"] == building]
        per_column = {}
        for r in mine:
            key = (str(r["column"]), int(r["storey"]))
            shear = max(abs(r["shear_bottom_x"]), abs(r["shear_top_x"]), abs(r["shear_bottom_y"]), abs(r["shear_top_y"]))
            impact = max(abs(r["impact_shear_bottom_x"]), abs(r["impact_shear_top_x"]))
            old = per_column.get(key, (0.0, 0.0, 0.0, np.nan))
            per_column[key] = (max(old[0], shear), max(old[1], impact), max(old[2], r["impact_moment_bottom"], r["impact_moment_top"]),
                               float(np.fmax(old[3], r["ratio"])))  # fmt: skip
        for (column, storey), (shear, impact, moment, ratio) in sorted(per_column.items()):
            text = "– (no capacity given)" if np.isnan(ratio) else f"{ratio:.2f}" + (" **≥ 1**" if ratio >= 1 else "")
            worst.append(f"| {building} | {column} | {storey} | {impact / 1e3:.0f} | {moment / 1e3:.0f} | {shear / 1e3:.0f} | "
                         f"{text} |")  # fmt: skip
    demand_rows = "\n".join(worst)
    return f"""<!-- Generated whole by docs/floors_example.py; do not edit by hand. Rebuild with
python docs/build.py floors, check with python docs/build.py --check. -->
# Floors at different heights: the shipped example

Generated by `python docs/floors_example.py` (through `python docs/build.py`, which CI checks)
from `inputs/mismatched_floors.toml`: a 5-storey building with 3.5 m storeys (`tall`, 30 × 30 cm
columns) beside the paper's 3-storey building with 3.0 m storeys (`low`), 5 cm apart, under the
shipped 2019 Ridgecrest CI.CCC record (PGA 0.53 g / 0.47 g), with its output every
{1e3 * OUTPUT_INTERVAL:g} ms so that the histories resolve the impacts. No floors share a level: every
contact is a slab striking a storey of its neighbour between two floors. The model is in
[theory §10](theory.md) ("Floors at different heights"), the fields in the
[user guide](user-guide.md), the checks against a finite-element frame in the
[validation report](validation.md).

## Where the impacts fall

{events.size} impacts, peak normal force {result.contact.peak_force / 1e3:.0f} kN; energy balance error
{result.balance_error_ratio:.1e} of the input.

| struck building | storey | ξ | elevation of the striking slab (m) | impacts |
| --- | ---: | ---: | ---: | ---: |
{struck_rows}

![Where the slabs strike](images/floors-where.png)

## What they put into the struck columns

The struck columns share each impact's force by their stiffness; each, clamped at both floors,
carries its share at ξ·h. Per struck column, over the run: the largest shear of an impact's own
(along the façade's normal, local x here), the largest end moment it puts in, the largest whole
shear (with the storey's drift) and the largest demand/capacity ratio against its
`shear_capacity` where the model gives one (the tall building's, an indicative 150 kN):

| building | column | storey | impact shear (kN) | impact moment (kN·m) | whole shear (kN) | demand/capacity |
| --- | --- | ---: | ---: | ---: | ---: | ---: |
{demand_rows}

![The most loaded struck column's shear against its capacity](images/floors-shear.png)

The example's columns have no `density`, so they are massless here: with one (`materials.<name>.density`,
kg/m³) their local modes split each impact into shorter ones and raise the peak force and the
columns' shear (theory §10, "The struck columns' own mass"). A ratio above 1 means the
column fails in shear before the impact's force is reached, and what follows (local failure) is
beyond a shear-type model: the figures are demands, not the response.
"""


def main() -> None:
    IMAGES.mkdir(exist_ok=True)
    scene, result = run()
    demand = result.contact.column_demand
    worst = demand[int(np.nanargmax(demand["ratio"]))]
    where_figure(scene, result, IMAGES / "floors-where.png")
    shear_figure(scene, result, worst, IMAGES / "floors-shear.png")
    PAGE.write_text(page(scene, result), encoding="utf-8")
    SIGNATURES.write_text(json.dumps(SIGNED, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {PAGE} and {SIGNATURES}", file=sys.stderr)


if __name__ == "__main__":
    main()
