"""Figures and tables quoted in the docs, made from the bench's result files or from a run.

docs/build.py calls :func:`figure` for every ``<!-- fig: NAME ARGS -->…<!-- /fig -->`` (a
figure inside a sentence) and ``<!-- md: NAME ARGS -->…<!-- /md -->`` (a Markdown table)
of a page. ARGS are split as a shell splits them. Timings come only from the files that
``pound bench`` writes into docs/bench/ (a measuring run, on this project's 2-core machine),
never from the build's own runs, so that the build gives the same page on every run.

    python docs/figures.py NAME ARGS        # print one
"""

from __future__ import annotations

import atexit
import json
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
"""The checkout the figures are read from (docs/build.py points it at its scratch copy)."""


class NeedsShared(Exception):
    """The figure needs a record kept in ../shared, which is absent."""


FIGURES: dict[str, Callable[..., str]] = {}


def registered(name: str):
    def wrap(fn):
        FIGURES[name] = fn
        return fn

    return wrap


def figure(name: str, *args: str) -> str:
    """The text of figure `name` (see FIGURES)."""
    if name not in FIGURES:
        raise KeyError(f"no figure {name!r} in docs/figures.py; there are: {', '.join(sorted(FIGURES))}")
    return FIGURES[name](*args)


# --- the bench's result files -----------------------------------------------------------------

SCENE = re.compile(r"^\*\*(?P<scene>[\w-]+)\*\* — (?P<text>.*)$")


@cache
def bench_file(name: str) -> dict[str, dict]:
    """docs/bench/NAME.md as {scene: {"text": the scene's line, "rows": {setting: {column: cell}}}};
    a file of one table without scene lines is the scene ""."""
    text = (ROOT / "docs" / "bench" / f"{name}.md").read_text(encoding="utf-8")
    scenes: dict[str, dict] = {}
    current = {"text": "", "rows": {}}
    header: list[str] = []
    for line in text.splitlines():
        m = SCENE.match(line)
        if m:
            current = scenes.setdefault(m.group("scene"), {"text": m.group("text"), "rows": {}})
            continue
        if not line.startswith("|"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if all(set(c) <= set("-: ") for c in cells):
            continue
        if not header or cells[0] in ("setting", "case", "buildings", "scene"):
            header = cells
            if not scenes:
                scenes[""] = current
            continue
        key = cells[0].strip("*")
        current["rows"][key] = dict(zip(header, cells, strict=False))
    return scenes


def bench_cell(file: str, scene: str, setting: str, column: str) -> str:
    try:
        return bench_file(file)[scene]["rows"][setting][column]
    except KeyError as exc:
        raise KeyError(f"docs/bench/{file}.md has no {column!r} of {setting!r} in scene {scene!r}") from exc


def bench_number(file: str, scene: str, setting: str, column: str) -> float:
    return float(bench_cell(file, scene, setting, column).replace(",", ""))


DEFAULT = "hybrid (default)"
CDM_PAPER = "cdm, Δt = 1e-5 s (paper)"
CDM_PAPER_2 = "cdm, Δt = 2e-5 s (paper)"


def percent(ratio: float) -> str:
    """A relative error as a percentage with two significant digits: 7.8e-4 -> '0.078'."""
    value = 100 * ratio
    text = f"{value:.2g}"
    return f"{value:.2e}".replace("e-0", "e-") if "e" in text else text


def seconds(value: float) -> str:
    return f"{value:.3g}"


def scene_of(name: str) -> tuple[str, str]:
    """(bench file, scene) of a scene name: paper_kobe is in kobe.md, the floors at different
    heights and their aligned twin in floors/bench.md, the others in bench.md."""
    if name in ("mismatched_floors", "aligned_floors"):
        return "floors/bench", name
    return ("kobe", name) if name == "paper_kobe" else ("bench", name)


@registered("solver")
def solver_time(scene: str, setting: str = DEFAULT) -> str:
    """Solver time (s) of a setting in a bench scene."""
    return seconds(bench_number(*scene_of(scene), setting, "solver (s)"))


@registered("error")
def error_percent(scene: str, setting: str = DEFAULT, column: str = "peak deflection error") -> str:
    """An error column of a bench row, as a percentage."""
    return percent(bench_number(*scene_of(scene), setting, column))


@registered("speedup")
def speedup(scene: str, against: str = CDM_PAPER) -> str:
    """How many times faster the default is than `against` (the CDM at the paper's 10 µs)."""
    file, name = scene_of(scene)
    ratio = bench_number(file, name, against, "solver (s)") / bench_number(file, name, DEFAULT, "solver (s)")
    return f"{ratio:.2g}" if ratio < 10 else f"{ratio:.0f}"


@registered("bench-steps")
def bench_steps(scene: str, setting: str = DEFAULT, column: str = "steps") -> str:
    return bench_cell(*scene_of(scene), setting, column)


SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def sci(value: float, digits: int = 2) -> str:
    """7.8e-04 -> '7.8 × 10⁻⁴' (the prose's form); 0 -> '0'."""
    if value == 0:
        return "0"
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    exponent = str(int(exponent))
    return mantissa if exponent == "0" else f"{mantissa} × 10{exponent.translate(SUPERSCRIPT)}"


@registered("err")
def err_sci(scene: str, setting: str = DEFAULT, column: str = "peak deflection error") -> str:
    """An error column of a bench row in the prose's form, 2.6 × 10⁻⁷."""
    return sci(bench_number(*scene_of(scene), setting, column))


@registered("max-default-error")
def max_default_error(column: str = "peak deflection error", *excluded: str) -> str:
    """The largest error of the default over the scenes of bench.md (but `excluded`)."""
    scenes = [s for s in bench_file("bench") if s not in excluded]
    return sci(max(bench_number("bench", s, DEFAULT, column) for s in scenes), 1)


def _scene_figure(scene: str, pattern: str) -> float:
    text = bench_file(scene_of(scene)[0])[scene_of(scene)[1]]["text"]
    return float(re.search(pattern, text).group(1))


@registered("halving")
def halving(scene: str) -> str:
    """How far the scene's reference moves when its step is halved (peak deflections)."""
    return sci(_scene_figure(scene, r"halving its Δt changes peak deflections by ([0-9.e+-]+)"))


@registered("bench-include")
def bench_include(path: str) -> str:
    """A result file of docs/bench/ whole (a table)."""
    return (ROOT / "docs" / "bench" / path).read_text(encoding="utf-8").strip()


@registered("auto-contact-step-us")
def auto_contact_step_us(model: str) -> str:
    """The automatic contact step before it is shortened to divide the substep:
    0.00625 · 2/ω_contact of the likely contacts, µs."""
    a = describe(model)["analysis"]
    return f"{a['dt_auto_fraction'] * a['contact_step_limit_s'] * 1e6:.3g}"


@registered("scaling-range")
def scaling_range(column: str) -> str:
    """The smallest and largest of a column of docs/bench/scaling.md: '0.024–0.029'."""
    values = [float(r[column]) for r in bench_file("scaling")[""]["rows"].values()]
    return f"{min(values):g}–{max(values):g}"


@registered("scaling")
def scaling_cell(buildings: str, column: str) -> str:
    return bench_cell("scaling", "", buildings, column)


@registered("front")
def front() -> str:
    """In how many scenes (bench.md and kobe.md) the default is on the front: 'all eight'."""
    scenes = [(f, s) for f in ("bench", "kobe") for s in bench_file(f)]
    on = sum(bench_cell(f, s, DEFAULT, "front") == "●" for f, s in scenes)
    words = {8: "eight", 7: "seven", 6: "six", 9: "nine"}
    return f"all {words.get(on, on)}" if on == len(scenes) else f"{on} of the {len(scenes)}"


@registered("steps-more")
def steps_more(scene: str, setting: str, than: str = DEFAULT) -> str:
    """How many more steps `setting` takes than `than` in a bench scene."""
    file, name = scene_of(scene)
    more = bench_number(file, name, setting, "steps") - bench_number(file, name, than, "steps")
    return f"{int(more):,}"


@registered("stab-sci")
def stability_sci(case: str, column: str = "energy balance") -> str:
    return sci(float(bench_cell("stability", "", case, column)))


@registered("stab-max-balance")
def stability_max_balance(*excluded: str) -> str:
    """The largest energy balance error of the stress cases that complete, but those named
    and the CDM's steps near its limit."""
    rows = bench_file("stability")[""]["rows"]
    values = [float(r["energy balance"]) for case, r in rows.items()
              if r["outcome"] == "complete" and not case.startswith("CDM at") and case not in excluded]  # fmt: skip
    return sci(max(values), 1)


@registered("kobe-sens")
def kobe_sensitivity(row: str, column: str, table: str = "0") -> str:
    """A cell of docs/bench/kobe-sensitivity.md (docs/kobe_sensitivity.py): table 0 is the
    errors at each contact step, table 1 the default's errors in full."""
    text = (ROOT / "docs" / "bench" / "kobe-sensitivity.md").read_text(encoding="utf-8")
    tables = [t for t in re.split(r"\n\s*\n", text) if t.lstrip().startswith("|")]
    lines = [ln for ln in tables[int(table)].strip().splitlines() if not set(ln) <= set("|-: ")]
    header = [c.strip() for c in lines[0].strip().strip("|").split("|")]
    for line in lines[1:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] == row:
            return cells[header.index(column)].removesuffix(" %")
    raise KeyError(f"docs/bench/kobe-sensitivity.md has no row {row!r}")


SCENE_LABELS = {
    "linear": "linear: the paper's buildings apart, 34 s",
    "paper_pounding": "paper_pounding: 5 cm gap, Ridgecrest × 1.5, 20 s",
    "corner": "corner: eccentric building turned 2°",
    "row_of_5": "row_of_5: five buildings",
    "stiff_contact": "stiff_contact: k_N, k_T × 100",
    "inelastic": "inelastic: the paper's buildings, 81 yielding columns, Ridgecrest × 1.5, 16 s",
    "isolated": "isolated: 9 lead-rubber bearings, moat 18 cm away, neighbour 8 cm away, 14 s",
    "paper_kobe": "paper_kobe: the paper's example, Kobe JMA 150 s",
}


@registered("bench-solver-table")
def solver_table() -> str:
    """docs/bench.md's table of solver times: the default against the CDM at the paper's steps."""
    lines = ["| scene | hybrid (default) | CDM, paper's Δt = 10⁻⁵ s | speed-up | CDM, paper's Δt = 2 × 10⁻⁵ s |",
             "| --- | ---: | ---: | ---: | ---: |"]  # fmt: skip
    for scene, label in SCENE_LABELS.items():
        file, name = scene_of(scene)
        cells = [solver_time(scene), seconds(bench_number(file, name, CDM_PAPER, "solver (s)")),
                 f"{speedup(scene)}×", seconds(bench_number(file, name, CDM_PAPER_2, "solver (s)"))]  # fmt: skip
        if scene == "paper_kobe":
            label, cells = f"**{label}**", [f"**{c}**" for c in cells]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


@registered("stability-table")
def stability_table() -> str:
    """docs/bench/stability.md without its run-time column (a timing of one run)."""
    text = (ROOT / "docs" / "bench" / "stability.md").read_text(encoding="utf-8")
    out = []
    for line in text.strip().splitlines():
        cells = line.strip().strip("|").split("|")
        del cells[3]
        out.append("|" + "|".join(cells) + "|")
    return "\n".join(out)


@registered("stability")
def stability_cell(case: str, column: str) -> str:
    return bench_cell("stability", "", case, column)


@registered("bench-scene")
def bench_scene(path: str, scene: str) -> str:
    """One scene's section (its line and table) of a bench result file, e.g. quick/bench.md."""
    lines = (ROOT / "docs" / "bench" / path).read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"**{scene}**"))
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("**")), len(lines))
    return "\n".join(lines[start:end]).strip()


@registered("storey-fe-table")
def storey_fe_table() -> str:
    """pound's slab–storey pounding against the finite-element frame (tests/test_storey_fe.py),
    as a markdown table: run both, here."""
    import tempfile

    sys.path.insert(0, str(ROOT / "tests"))
    from test_storey_fe import table

    with tempfile.TemporaryDirectory() as folder:
        return table(Path(folder))


@registered("local-modes-fe-table")
def local_modes_fe_table() -> str:
    """pound's struck columns with their own mass against the finite-element frame with
    distributed column mass (tests/test_local_modes_fe.py), as a markdown table: run both, here."""
    import tempfile

    sys.path.insert(0, str(ROOT / "tests"))
    from test_local_modes_fe import table

    with tempfile.TemporaryDirectory() as folder:
        return table(Path(folder))


@registered("local-modes-elements-table")
def local_modes_elements_table() -> str:
    """pound with 12 local modes against the frame meshed with 16, 32 and 64 elements
    (tests/test_local_modes_fe.py: element_table), run here."""
    import tempfile

    sys.path.insert(0, str(ROOT / "tests"))
    from test_local_modes_fe import element_table

    with tempfile.TemporaryDirectory() as folder:
        return element_table(Path(folder))


@registered("column-mass-study")
def column_mass_study() -> str:
    """The struck column's own mass: the reduced models' largest errors against the FE frame
    with distributed column mass (tests/fe_study.py, T3's summary), run here."""
    sys.path.insert(0, str(ROOT / "tests"))
    from fe_study import worst_errors

    return worst_errors()


@registered("sweep-timing")
def sweep_timing(jobs: str, column: str) -> str:
    """A cell of docs/bench/sweep.md (docs/sweep_timing.py): the row of `jobs` local jobs."""
    return bench_cell("sweep", "", jobs, column)


@registered("sweep-speedup")
def sweep_speedup() -> str:
    text = (ROOT / "docs" / "bench" / "sweep.md").read_text(encoding="utf-8")
    return re.search(r"two jobs: ([0-9.]+)×", text).group(1)


@registered("quick-bench-time")
def quick_bench_time() -> str:
    """The wall time of `pound bench --quick`, as docs/bench/quick/bench.md records it."""
    text = (ROOT / "docs" / "bench" / "quick" / "bench.md").read_text(encoding="utf-8")
    m = re.search(r"took (\d+ min \d+ s|\d+ s) of wall time", text)
    if not m:
        raise KeyError("docs/bench/quick/bench.md does not record its wall time")
    return m.group(1)


# --- from the code ----------------------------------------------------------------------------


@registered("schema-files")
def schema_files() -> str:
    """The files `pound schema` writes, as a Markdown list of names."""
    from pounding_cli.schema import schema_files as files

    names = list(files())
    return ", ".join(f"`{n}`" for n in names[:-1]) + f" and `{names[-1]}`"


@registered("schema-count")
def schema_count() -> str:
    from pounding_cli.schema import schema_files as files

    words = {5: "five", 6: "six", 7: "seven", 8: "eight", 9: "nine"}
    n = len(files())
    return words.get(n, str(n))


# --- from a run -------------------------------------------------------------------------------


_RUNS: dict[str, Path] = {}


@cache
def run_json(model: str) -> dict:
    """`pound run MODEL --json` of a shipped model (its file kept for :func:`run_file`)."""
    import tempfile

    path = ROOT / model
    if "shared/records" in _record_text(path) and not (ROOT.parent / "shared").is_dir():
        raise NeedsShared(f"{model} reads a record kept in ../shared, which is absent")
    folder = Path(tempfile.mkdtemp(prefix="pound-figures-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    output = folder / (path.stem + ".h5")
    out = subprocess.run([sys.executable, "-m", "pounding_cli", "run", str(path), "-o", str(output), "--json"],
                         capture_output=True, text=True, check=True).stdout  # fmt: skip
    _RUNS[model] = output
    return json.loads(out)


def run_file(model: str) -> Path:
    """The result file of :func:`run_json`'s run of MODEL."""
    run_json(model)
    return _RUNS[model]


def _record_text(model: Path) -> str:
    """A model's or record definition's text, with that of the definition a model names."""
    if model.suffix not in (".toml", ".json"):
        return ""
    text = model.read_text(encoding="utf-8")
    for name in re.findall(r'record\s*=\s*"([^"]+)"', text):
        definition = model.parent / name
        if definition.is_file():
            text += definition.read_text(encoding="utf-8")
    return text


@registered("run")
def run_value(model: str, key: str, fmt: str = "") -> str:
    """A key of `pound run MODEL --json` (dotted for nested keys)."""
    return _dotted(run_json(model), key, fmt)


@registered("run-cdm-ms")
def run_cdm_ms(model: str) -> str:
    """How long the hybrid's CDM stretches of a run last, in ms (CDM steps × Δt)."""
    doc = run_json(model)
    return f"{doc['cdm_steps'] * doc['dt_s'] * 1e3:.2g}"


@registered("run-impact-ms")
def run_impact_ms(model: str, which: str = "0") -> str:
    """How long impact number `which` (0-based, in the impact log) of a run lasts, in ms."""
    import h5py

    with h5py.File(run_file(model)) as f:
        events = f["impacts/events"][()]
    event = events[int(which)]
    return f"{(event['t_end'] - event['t_start']) * 1e3:.3g}"


@registered("run-int")
def run_int(model: str, key: str) -> str:
    """An integer key of `pound run MODEL --json`, with thousands separators."""
    return f"{int(run_value(model, key)):,}"


@registered("version")
def version() -> str:
    import pounding_cli

    return pounding_cli.__version__


@registered("c9-table")
def c9_table(model: str, building: str = "left", column: str = "C9") -> str:
    """The peak interstorey deflections of one column, per storey, from a run of MODEL."""
    import h5py

    with h5py.File(run_file(model)) as f:
        names = [n.decode() for n in f[f"buildings/{building}/columns"]["name"]]
        isd = f[f"buildings/{building}/peaks/interstorey_deflection"][()][names.index(column)]
    lines = ["| Storey | peak Δu_x (mm) | peak Δu_y (mm) | peak Δθ (rad) |", "| --- | --- | --- | --- |"]
    for storey, (dx, dy, dt) in enumerate(isd, start=1):
        lines.append(f"| {storey} | {dx * 1e3:.2f} | {dy * 1e3:.2f} | {dt:.3g} |")
    return "\n".join(lines)


@cache
def describe(model: str) -> dict:
    """`pound validate MODEL --json`."""
    import pounding_cli

    return pounding_cli.describe(ROOT / model)


@registered("period")
def period(model: str, building: str, mode: str) -> str:
    """The period (s) of mode `mode` (1-based) of a building, as `pound validate` prints it."""
    b = next(b for b in describe(model)["buildings"] if b["name"] == building)
    return f"{b['periods_s'][int(mode) - 1]:.4f}"


@registered("validate")
def validate_value(model: str, key: str, fmt: str = "") -> str:
    """A key of `pound validate MODEL --json` (dotted; list items by index)."""
    return _dotted(describe(model), key, fmt)


def _dotted(value, key: str, fmt: str) -> str:  # type: ignore[no-untyped-def]
    """The item of a JSON document at a dotted key (list items by index), formatted."""
    for part in key.split("."):
        value = value[int(part)] if isinstance(value, list) else value[part]
    return format(value, fmt) if fmt else str(value)


@registered("periods-table")
def periods_table(model: str, count: str = "6") -> str:
    """The first periods of each building of MODEL, each labelled (x, y, θ) by the direction
    that holds most of its participating mass (when that is above half), as `pound validate`
    prints them."""
    lines = ["| building | T₁ … T₆ (s) |", "| --- | --- |"]
    for b in describe(model)["buildings"]:
        cells = []
        for period, mass in list(zip(b["periods_s"], b["participating_mass_ratio_x_y_theta"], strict=True))[: int(count)]:
            k = max(range(3), key=lambda i: mass[i])
            cells.append(f"{period:.4f}" + (f" ({'xyθ'[k]})" if mass[k] > 0.5 else ""))
        lines.append(f"| {b['name']}, {b['storeys']} storeys | " + ", ".join(cells) + " |")
    return "\n".join(lines)


@cache
def record_json(path: str, *options: str) -> dict:
    if "shared/records" in _record_text(ROOT / path) and not (ROOT.parent / "shared").is_dir():
        raise NeedsShared(f"{path} reads a record kept in ../shared, which is absent")
    out = subprocess.run([sys.executable, "-m", "pounding_cli", "record", str(ROOT / path), "--json", *options],
                         capture_output=True, text=True,
                         check=True).stdout  # fmt: skip
    return json.loads(out)


@registered("record-table")
def record_table() -> str:
    """docs/records/README.md's table: what `pound record` prints for the shipped record and
    the paper's Kobe record (which needs ../shared)."""
    kobe = "inputs/kobe_jma.record.toml"
    if not (ROOT.parent / "shared").is_dir():
        raise NeedsShared(f"{kobe} reads the Kobe record kept in ../shared, which is absent")
    rows = [("Ridgecrest CI.CCC, HNE (90°)", "inputs/ridgecrest2019_ccc.record.toml", 0),
            ("Ridgecrest CI.CCC, HNN (360°)", "inputs/ridgecrest2019_ccc.record.toml", 1),
            ("Kobe KJMA 000 (N-S)", kobe, 0), ("Kobe KJMA 090 (E-W)", kobe, 1)]  # fmt: skip
    lines = ["| Record, component | Δt (s) | points | PGA (g) | PGV (m/s) | PGD (m) | I_A (m/s) | D5-95 (s) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]  # fmt: skip
    for label, path, k in rows:
        c = record_json(path)["components"][k]
        lines.append(f"| {label} | {c['dt_s']:g} | {c['points']} | {c['pga_g']:.4f} | {c['pgv_m_s']:.4f} | "
                     f"{c['pgd_m']:.4f} | {c['arias_intensity_m_s']:.3f} | {c['significant_duration_s']:.2f} |")  # fmt: skip
    return "\n".join(lines)


def _arias(path: str, trace: str) -> tuple[float, float]:
    """(pound's exact I_A, the trapezoid rule's I_A) of one trace of a record file, m/s."""
    import math

    import numpy as np

    from pounding_cli.records import read_accelerogram
    from pounding_cli.records.metrics import metrics

    full = ROOT / path
    if not full.exists() and "shared" in path:
        raise NeedsShared(f"{path} is kept in ../shared, which is absent")
    rec = read_accelerogram(full, trace=trace or None, units=None if full.suffix.upper() == ".AT2" else "m/s2")
    a, dt = rec.acceleration, rec.dt
    trapezoid = math.pi / (2 * 9.80665) * float(np.sum(dt * (a[:-1] ** 2 + a[1:] ** 2) / 2))
    return metrics(a, dt).arias_intensity, trapezoid


@registered("d5-95-trapezoid")
def d5_95_trapezoid(path: str, trace: str, fmt: str = ".2f") -> str:
    """D5-95 (s) of a record file's trace with the Arias build-up by the trapezoid rule,
    the 5 % and 95 % times interpolated between samples."""
    import numpy as np

    from pounding_cli.records import read_accelerogram

    full = ROOT / path
    if not full.exists() and "shared" in path:
        raise NeedsShared(f"{path} is kept in ../shared, which is absent")
    rec = read_accelerogram(full, trace=trace or None, units=None if full.suffix.upper() == ".AT2" else "m/s2")
    a, dt = rec.acceleration, rec.dt
    build_up = np.concatenate([[0.0], np.cumsum(dt * (a[:-1] ** 2 + a[1:] ** 2) / 2)])
    t = np.arange(a.size) * dt
    t5, t95 = np.interp([0.05 * build_up[-1], 0.95 * build_up[-1]], build_up, t)
    return format(t95 - t5, fmt)


@registered("arias")
def arias(path: str, trace: str, rule: str = "exact", fmt: str = ".3f") -> str:
    """The Arias intensity of a record file's trace by pound's exact rule or the trapezoid
    rule on the samples, m/s; rule "excess": how much more the trapezoid gives, in %."""
    exact, trapezoid = _arias(path, trace)
    if rule == "excess":
        return f"{100 * (trapezoid / exact - 1):{fmt}}"
    return format(exact if rule == "exact" else trapezoid, fmt)


@registered("record")
def record_value(path: str, component: str, key: str, fmt: str = ".4g") -> str:
    """A key of one component (by name or index) of `pound record PATH --json`."""
    doc = record_json(path)
    comps = doc["components"]
    comp = comps[int(component)] if component.isdigit() else next(c for c in comps if c["name"] == component)
    return format(comp[key], fmt)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: python docs/figures.py NAME [ARGS...]; names: " + ", ".join(sorted(FIGURES)))
    print(figure(sys.argv[1], *sys.argv[2:]))


EQUILIBRIUM_SCENES = {"paper_pounding": (20.0, 0.0002), "paper_inelastic": (8.0, 0.0005), "isolated_moat": (13.0, 0.0005)}
"""Scene → (duration, output interval) s: long enough to reach impacts (a moat's from 12.5 s),
stored finely enough that some samples fall inside them (tests/test_forces.py runs the same)."""


@registered("equilibrium-table")
def equilibrium_table() -> str:
    """The storeys' equilibrium at every stored sample (results/equilibrium.py) in three shipped
    scenes: the largest |V_s + Σ above (M·a + C·v − F_contact)| over the run, every building
    and storey, relative to the largest Σ above |M·a| + |M·a + C·v − F_contact| of that storey."""
    import numpy as np

    from pounding_cli import api
    from pounding_cli.assembly import assemble
    from pounding_cli.model import load_model
    from pounding_cli.results.equilibrium import worst_residual

    lines = ["| scene (duration, output interval) | storeys | stored samples, of them in contact | largest residual / scale: F_X, F_Y, T_O |",
             "| --- | --- | --- | --- |"]  # fmt: skip
    for name, (duration, interval) in EQUILIBRIUM_SCENES.items():
        loaded = load_model(ROOT / "inputs" / f"{name}.toml")
        loaded.model.analysis.duration = duration
        loaded.model.analysis.output_interval = interval
        result = api.run_model(loaded)
        worst = np.max([w.max(axis=0) for w in worst_residual(result, assemble(loaded)).values()], axis=0)
        touching = np.zeros(result.time.size, dtype=bool)
        for b in result.buildings.values():
            touching |= np.any(b.forces.floor_contact != 0, axis=(1, 2))
        storeys = sum(b.elevation.size for b in result.buildings.values())
        lines.append(f"| `{name}` ({duration:g} s, {interval * 1e3:g} ms) | {storeys} | {result.time.size:,}, "
                     f"{int(touching.sum())} | {', '.join(sci(v, 1) for v in worst)} |")  # fmt: skip
    return "\n".join(lines)
