"""Running the benchmark: scenes × integrator settings, timed and compared with a reference."""

from __future__ import annotations

import dataclasses
import statistics
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Callable

from ..api import Scene, execute, prepare, scene_grid
from ..results import RunResult
from .metrics import Errors, compare


@dataclass(frozen=True)
class Setting:
    """One way to integrate a scene."""

    name: str
    integrator: str  # "cdm" or "hybrid"
    dt_scale: float = 1.0  # × the automatic steps (contact, yielding, structure: timestep.py)
    dt_fraction: float | None = None  # instead: Δt = dt_fraction · 2/ω_max (the smaller limit)
    dt: float | None = None  # instead: a fixed Δt, s
    sampling_scale: float = 1.0  # hybrid: × the default ω_max·h (timestep.hybrid_sampling)
    default: bool = False


SETTINGS = (
    Setting("hybrid (default)", "hybrid", default=True),
    Setting("hybrid, ω·h × 2", "hybrid", sampling_scale=2.0),
    Setting("hybrid, ω·h / 2", "hybrid", sampling_scale=0.5),
    Setting("hybrid, Δt / 2", "hybrid", dt_scale=0.5),
    Setting("hybrid, Δt × 2", "hybrid", dt_scale=2.0),
    Setting("hybrid, Δt × 4", "hybrid", dt_scale=4.0),
    Setting("cdm, Δt auto", "cdm"),
    Setting("cdm, Δt × 4", "cdm", dt_scale=4.0),
    Setting("cdm, Δt = 0.2·2/ω", "cdm", dt_fraction=0.2),
    Setting("cdm, Δt = 2e-5 s (paper)", "cdm", dt=2e-5),
    Setting("cdm, Δt = 1e-5 s (paper)", "cdm", dt=1e-5),
)
QUICK_SETTINGS = tuple(s for s in SETTINGS if s.name in ("hybrid (default)", "cdm, Δt × 4", "cdm, Δt = 2e-5 s (paper)"))


@dataclass(frozen=True)
class Row:
    """One line of the table."""

    scene: str
    setting: Setting
    steps: int
    contact_steps: int
    wall_time: float  # s, median of the repeats, time loop only
    errors: Errors


@dataclass(frozen=True)
class SceneReport:
    """A scene's reference and its rows."""

    scene: str
    reference: Setting
    reference_steps: int
    convergence: Errors  # the reference against the same at half its Δt
    rows: list[Row]
    sensitivity: Errors | None = None  # the scene under its record × (1 + PERTURBATION) against itself

    @property
    def floor(self) -> float:
        """The error below which settings cannot be told apart: the larger of the reference's
        own change when its Δt is halved and the scene's sensitivity to its input (largest
        relative change of a peak interstorey deflection)."""
        sensitivity = self.sensitivity.peak_deflection if self.sensitivity is not None else 0.0
        return max(self.convergence.peak_deflection, sensitivity)


PERTURBATION = 1e-4
"""The input change that measures how well a scene's peaks are determined at all: the record
scaled by 1 + PERTURBATION, far less than any record's calibration is known to. Impacts
amplify it: a peak that moves by more than it does is not set by the numerics."""


EXACT_REFERENCE_FACTOR = 8
"""A scene the hybrid integrates exactly (no contact, no yielding member) takes its reference
at a further 1/EXACT_REFERENCE_FACTOR of the step: there the hybrid's only error is its peaks'
interpolation, orders below the CDM's at a quarter of the structure's automatic step (1e-5
of the peaks), which would hide it. Such a scene's steps are few and cheap."""


def reference_scale(scene: Scene, reference_divisor: int) -> float:
    """The reference's step, as a fraction of the automatic one (Setting.dt_scale)."""
    exact = scene.contact.n_pairs == 0 and scene.system.members.top.size == 0
    return 1.0 / (reference_divisor * (EXACT_REFERENCE_FACTOR if exact else 1))


def scene_files() -> list[Path]:
    """The shipped benchmark scenes."""
    folder = resources.files("pounding_cli.bench") / "scenes"
    return sorted(Path(str(p)) for p in folder.iterdir() if p.name.endswith(".toml"))


def with_setting(scene: Scene, setting: Setting, duration: float | None = None) -> Scene:
    """The scene with its time grid chosen by `setting` (and its duration cut if asked)."""
    analysis = scene.loaded.model.analysis.model_copy(
        update={"integrator": setting.integrator, "dt": setting.dt if setting.dt is not None else "auto",
                "duration": duration if duration is not None else scene.loaded.model.analysis.duration}  # fmt: skip
    )
    grid, regrid = scene_grid(analysis, str(scene.loaded.source), scene.system, scene.contact, scene.ground,
                              setting.dt_fraction, setting.sampling_scale, setting.dt_scale)  # fmt: skip
    return dataclasses.replace(scene, grid=grid, regrid=regrid)


def timed(scene: Scene, repeats: int) -> tuple[RunResult, float]:
    """A run of the scene and the median solver time over `repeats` runs."""
    runs = [execute(scene) for _ in range(repeats)]
    return runs[0], statistics.median(r.diagnostics["wall_time_s"] for r in runs)


def bench(
    models: list[Path],
    settings: tuple[Setting, ...] = SETTINGS,
    repeats: int = 3,
    reference_divisor: int = 4,
    duration: float | None = None,
    log: Callable[[str], None] = lambda _: None,
) -> list[SceneReport]:
    """Benchmark every model under every setting; the reference is the CDM at its automatic
    step divided by reference_divisor (and by EXACT_REFERENCE_FACTOR where the hybrid is
    exact), checked against half that."""
    reports = []
    for path in models:
        base = prepare(path)
        name = Path(path).stem
        scale = reference_scale(base, reference_divisor)
        fine = Setting(f"cdm, Δt auto / {round(1 / scale)} (reference)", "cdm", dt_scale=scale)
        finer = dataclasses.replace(fine, dt_scale=fine.dt_scale / 2)
        log(f"{name}: reference")
        reference = execute(with_setting(base, fine, duration))
        check = execute(with_setting(base, finer, duration))
        log(f"{name}: sensitivity to the input")
        sensitivity = input_sensitivity(path, base, reference_divisor, duration)
        rows = []
        for setting in settings:
            log(f"{name}: {setting.name}")
            run, wall = timed(with_setting(base, setting, duration), repeats)
            rows.append(Row(name, setting, run.diagnostics["steps"], run.diagnostics["contact_steps"], wall,
                            compare(run, reference)))  # fmt: skip
        reports.append(SceneReport(name, fine, reference.diagnostics["steps"], compare(reference, check), rows,
                                   sensitivity))  # fmt: skip
    return reports


def input_sensitivity(path: Path, base: Scene, reference_divisor: int, duration: float | None) -> Errors:
    """How far the scene's peaks move when its record is scaled by 1 + PERTURBATION: the
    hybrid at the reference's contact step (exact between contacts, so as accurate as the
    reference where it matters, and cheap) with and without the change."""
    from ..model import read_document, validate_model

    doc = read_document(path)
    excitation = doc.setdefault("excitation", {})
    excitation["scale"] = float(excitation.get("scale", 1.0)) * (1.0 + PERTURBATION)
    shaken = prepare(validate_model(doc, path))
    setting = Setting("sensitivity", "hybrid", dt_scale=1.0 / reference_divisor)
    return compare(execute(with_setting(shaken, setting, duration)), execute(with_setting(base, setting, duration)))


def on_front(report: SceneReport) -> set[str]:
    """Settings that no other setting beats on both solver time and error (the largest of the
    peak deflection, peak force and yielding members' peak deflection errors). Two settings
    that take the same steps and give the same errors are one run (a contact step in a scene
    without contact, say): their times differ by noise alone, and neither beats the other."""
    def error(row: Row) -> float:
        return max(row.errors.peak_deflection, row.errors.peak_force, row.errors.member_deflection)

    def same_run(a: Row, b: Row) -> bool:
        return (a.setting.integrator, a.steps, a.contact_steps, a.errors) == (b.setting.integrator, b.steps,
                                                                            b.contact_steps, b.errors)  # fmt: skip

    front = set()
    for row in report.rows:
        dominated = any(
            o.wall_time <= row.wall_time and error(o) <= error(row) and (o.wall_time < row.wall_time or error(o) < error(row))
            and not same_run(o, row)
            for o in report.rows
        )
        if not dominated:
            front.add(row.setting.name)
    return front
