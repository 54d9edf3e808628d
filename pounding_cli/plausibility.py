"""Plausibility warnings: values that are legal but almost certainly wrong.

A model may be valid and still describe no real building: a modulus typed in MPa where Pa
is expected (``elastic_modulus = 25000`` gives T1 = 374 s), a record's vertical component
given as L. Such values are not refused — a study may mean them — but they are said:

    from pounding_cli.api import prepare
    from pounding_cli.plausibility import notices
    for notice in notices(prepare("model.toml")):
        print(notice)              # model.toml: materials.concrete.elastic_modulus: …

Each check is a function of the prepared :class:`~pounding_cli.api.Scene` that yields
:class:`Notice` objects; :data:`CHECKS` lists them in the order they are reported. Another
module adds a check by appending one function to it. The thresholds are the constants
below; docs/user-guide.md ("Plausibility warnings") gives each one's source.

``pound validate`` and ``pound run`` print the notices (stderr, ``FILE: field: message``),
``--json`` carries them under ``warnings``, result files keep them (``/diagnostics/warnings``)
and ``--strict`` (validate, run, sweep) makes them errors, exit 2. A notice that makes the
model stiffer or lighter than intended (:attr:`Notice.shortens_step`) is also what a
refusal for too many time steps blames (limits._step_cause).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Iterator

import numpy as np

from .errors import InputError

if TYPE_CHECKING:
    from .api import Scene

G = 9.80665  # m/s², standard gravity

E_RANGE = (1e9, 1e12)
"""Static Young's modulus, Pa: structural materials lie within (timber about 10 GPa,
concrete 27–44 GPa, steel 210 GPa)."""

MASS_PER_AREA_RANGE = (100.0, 5000.0)
"""Seismic mass per floor area, kg/m² (a reinforced-concrete floor with its finishes and a
share of the live load is about 1000)."""

STOREY_HEIGHT_RANGE = (2.0, 10.0)
"""Storey height, m (floor to floor 2.7–4.5 m in most buildings; lobbies and halls more)."""

PERIOD_RANGE = (0.02, 6.0)
"""Fixed-base fundamental period T1, s (about 0.1 s per storey)."""

PGA_MAX_G = 3.0
"""Peak ground acceleration, g: recorded horizontal PGAs reach about 3 g at most."""

IMPACT_STIFFNESS_RATIO = 100.0
"""How far a hand-given impact stiffness may lie from the materials' own (eqs. 6–9)."""


@dataclass(frozen=True)
class Notice:
    """A plausibility warning: the file and the model field it concerns, and what is odd.

    `field` is a model path as errors name them (``materials.concrete.elastic_modulus``,
    ``buildings[0].floors[1].mass_per_area``). `shortens_step` marks a value that, if wrong,
    makes the model stiffer or lighter than meant, so that it shortens the stable time step:
    the input a refusal for too many steps most likely comes from."""

    file: str
    field: str
    message: str
    shortens_step: bool = False

    def __str__(self) -> str:
        return f"{self.file}: {self.field}: {self.message}"

    def as_dict(self) -> dict[str, str]:
        """{file, field, message}: the JSON form (`--json`'s `warnings`, the result file's)."""
        return {"file": self.file, "field": self.field, "message": self.message}


Check = Callable[["Scene"], Iterator[Notice]]


def notices(scene: "Scene") -> list[Notice]:
    """Every check's notices for a prepared scene, in the order of :data:`CHECKS`."""
    return [notice for check in CHECKS for notice in check(scene)]


def strict_error(found: list[Notice]) -> InputError:
    """The error `--strict` raises for plausibility warnings: one line per warning,
    ``FILE: field: message``, the last one saying why they are errors."""
    lines = [str(n) for n in found]
    lines[-1] += f" (--strict: {len(found)} plausibility warning{'s' if len(found) > 1 else ''} made errors)"
    return InputError("\n".join(lines))


def _si(value: float, unit: str) -> str:
    """'25 kPa', '1.2 GPa': a value with an SI prefix, 3 significant digits."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g} {unit}"
    k = max(-4, min(4, int(math.floor(math.log10(abs(value)) / 3))))
    return f"{value / 10 ** (3 * k):.3g} {('p', 'n', 'µ', 'm', '', 'k', 'M', 'G', 'T')[k + 4]}{unit}"


# --- the checks ---------------------------------------------------------------------------

DENSITY_RANGE = (300.0, 20000.0)
"""Mass density, kg/m³: structural materials lie within (timber 400–700, concrete 2,300–2,500,
steel 7,850)."""


def density(scene: "Scene") -> Iterator[Notice]:
    """A column material's density outside 300–20,000 kg/m³, with the unit it was most likely
    typed in (t/m³ or g/cm³; a unit weight in kN/m³). It gives the struck columns their mass."""
    lo, hi = DENSITY_RANGE
    for name, material in scene.loaded.model.materials.items():
        rho = material.density
        if rho is None or lo <= rho <= hi:
            continue
        if rho > hi:
            likely = "; check its unit (kg/m³) for an extra factor of 1000"
        elif lo <= rho * 1000 <= hi:
            likely = f"; it looks like t/m³ (g/cm³) typed as kg/m³: write density = {rho * 1000:.4g}"
        elif lo <= rho * 1000 / 9.81 <= hi:
            likely = (f"; it looks like a unit weight in kN/m³ ({rho:g} kN/m³ is {rho * 1000 / 9.81:.4g} kg/m³: "
                      f"write density = {rho * 1000 / 9.81:.4g})")  # fmt: skip
        else:
            likely = ""
        yield Notice(str(scene.loaded.source), f"materials.{name}.density", (
            f"ρ = {rho:g} kg/m³ is outside 300–20,000 kg/m³, where structural materials lie (timber 400–700, "
            f"concrete 2,300–2,500, steel 7,850){likely}"
        ))  # fmt: skip


# units a modulus is often typed in by mistake, with their size in Pa: the first that brings
# the value into E_RANGE is the likely one
_E_UNITS = (("GPa", 1e9), ("MPa", 1e6), ("kN/m² (kPa)", 1e3))


def elastic_modulus(scene: "Scene") -> Iterator[Notice]:
    """E outside 1 GPa–1 TPa, with the unit it was most likely typed in."""
    lo, hi = E_RANGE
    for name, material in scene.loaded.model.materials.items():
        e = material.elastic_modulus
        if lo <= e <= hi:
            continue
        field = f"materials.{name}.elastic_modulus"
        if e > hi:
            yield Notice(str(scene.loaded.source), field, (
                f"E = {e:.4g} Pa is above 1 TPa, stiffer than any structural material (steel 210 GPa, "
                "concrete 27–44 GPa); check its unit (Pa) for an extra factor of 1000"
            ), shortens_step=True)  # fmt: skip
            continue
        guess = next(((unit, factor) for unit, factor in _E_UNITS if lo <= e * factor <= hi), None)
        likely = (f"; it looks like {guess[0]} typed as Pa ({e:g} {guess[0].split()[0]} = {_si(e * guess[1], 'Pa')}: "
                  f"write elastic_modulus = {e * guess[1]:.4g})" if guess else "")  # fmt: skip
        yield Notice(str(scene.loaded.source), field, (
            f"E = {e:g} Pa ({_si(e, 'Pa')}) is below 1 GPa, softer than any structural material (timber about 10 GPa, "
            f"concrete 27–44 GPa, steel 210 GPa){likely}"
        ))  # fmt: skip


def floor_mass(scene: "Scene") -> Iterator[Notice]:
    """Mass per floor area outside about 100–5,000 kg/m² (each floor entry, each base slab)."""
    from .assembly.polygon import polygon_area

    lo, hi = MASS_PER_AREA_RANGE
    for b, building in enumerate(scene.loaded.model.buildings):
        slabs = [(f"buildings[{b}].floors[{f}]", floor) for f, floor in enumerate(building.floors)]
        if building.isolation is not None:
            slabs.insert(0, (f"buildings[{b}].isolation", building.isolation))
        for path, slab in slabs:
            area = polygon_area(np.asarray(slab.slab, dtype=float))
            if slab.mass_per_area is not None:
                field, per_area, given = "mass_per_area", slab.mass_per_area, f"mass_per_area = {slab.mass_per_area:g} kg/m²"
            else:
                field, per_area = "mass", slab.mass / area
                given = f"mass = {slab.mass:g} kg on {area:.4g} m², {per_area:.4g} kg/m²,"
            if lo <= per_area <= hi:
                continue
            low = per_area < lo
            yield Notice(str(scene.loaded.source), f"{path}.{field}", (
                f"{given} is {'below' if low else 'above'} the {lo:g}–{hi:,g} kg/m² of real floors (a concrete floor "
                f"with its finishes and live load is about 1000 kg/m²); check its unit "
                f"({'kg/m²' if field == 'mass_per_area' else 'kg'}{'; a tonne is 1000 kg' if low else ''})"
            ), shortens_step=low)  # fmt: skip


def storey_height(scene: "Scene") -> Iterator[Notice]:
    """A storey height outside about 2–10 m."""
    lo, hi = STOREY_HEIGHT_RANGE
    for b, building in enumerate(scene.loaded.model.buildings):
        for f, floor in enumerate(building.floors):
            if lo <= floor.height <= hi:
                continue
            low = floor.height < lo
            yield Notice(str(scene.loaded.source), f"buildings[{b}].floors[{f}].height", (
                f"a storey height of {floor.height:g} m is {'below' if low else 'above'} the {lo:g}–{hi:g} m of real "
                "storeys (2.7–4.5 m floor to floor in most buildings); check its unit (m)"
            ), shortens_step=low)  # fmt: skip


def fundamental_period(scene: "Scene") -> Iterator[Notice]:
    """A fixed-base fundamental period beyond about 6 s or below 0.02 s (an isolated
    building's: its superstructure's on a fixed base)."""
    lo, hi = PERIOD_RANGE
    for b, bld in enumerate(scene.system.buildings):
        modes = bld.rayleigh_modes if bld.isolated and bld.rayleigh_modes is not None else bld.modes
        if modes.periods.size == 0:
            continue
        t1 = float(modes.periods[0])
        if lo <= t1 <= hi or not math.isfinite(t1):
            continue
        storeys = bld.n_floors - int(bld.isolated)
        low = t1 < lo
        yield Notice(str(scene.loaded.source), f"buildings[{b}]", (
            f"the fixed-base fundamental period T1 = {t1:.3g} s is {'below' if low else 'beyond'} the "
            f"{lo:g}–{hi:g} s of real buildings (about 0.1 s per storey: {0.1 * storeys:.2g} s for {storeys}); "
            "check the units of elastic_modulus (Pa), column sections (m), storey heights (m) and masses (kg)"
        ), shortens_step=low)  # fmt: skip


def peak_ground_acceleration(scene: "Scene") -> Iterator[Notice]:
    """PGA above 3 g along either global axis, blamed on the likeliest factor: the
    excitation's scale, the record's own scale, or the units of its strongest component."""
    ground = scene.ground
    pga = float(np.max(np.abs(ground.acceleration))) / G if ground.acceleration.size else 0.0
    if not pga > PGA_MAX_G:
        return
    file, prefix = _record_origin(scene)
    excitation = scene.loaded.model.excitation
    if excitation.scale != 1.0:
        source, field, what = str(scene.loaded.source), "excitation.scale", f"excitation.scale = {excitation.scale:g}"
    elif ground.record_factor != 1.0:
        field = prefix + ("target_pga" if getattr(ground.record, "target_pga", None) is not None else "scale")
        source, what = file, f"the record's scale factor {ground.record_factor:.4g}"
    else:
        strongest = max(ground.components, key=lambda c: float(np.max(np.abs(ground.components[c].acceleration))))
        source, field, what = file, f"{prefix}{strongest}.units", f"component {strongest}"
    yield Notice(source, field, (
        f"the ground acceleration peaks at {pga:.3g} g, above the {PGA_MAX_G:g} g that the strongest records reach; "
        f"check {what}: values in m/s² read as g are 9.81 times too large, cm/s² (gal) read as m/s² 100 times"
    ))  # fmt: skip


_VERTICAL_WORDS = {"UP", "UD", "U", "V", "VER", "VERT", "VERTICAL", "Z", "DWN", "DOWN", "DN"}


def vertical_component(scene: "Scene") -> Iterator[Notice]:
    """A component used as L or T whose file marks it vertical: SEED channel ``??Z`` (every
    reader names a vertical channel so: AT2 ``UP``/``V``, COSMOS ``Up``/``Down``), an AT2
    component word or a COSMOS orientation that says so, or a dip of ±90°."""
    file, prefix = _record_origin(scene)
    record = scene.ground.record
    for name, accelerogram in scene.ground.components.items():
        header = accelerogram.header
        channel = str(header.get("channel", "") or (accelerogram.trace_id or "").rsplit(".", 1)[-1])
        words = {str(header.get(k, "")).strip().upper() for k in ("component", "orientation")}
        dip = header.get("dip")
        if not (channel[2:3] == "Z" or words & _VERTICAL_WORDS or (isinstance(dip, (int, float)) and abs(dip) == 90)):
            continue
        spec = getattr(record, name, None) if record is not None else None
        key = "trace" if spec is not None and spec.trace is not None else "file"
        marked = f"channel {channel}" if channel[2:3] == "Z" else "its header"
        yield Notice(file, f"{prefix}{name}.{key}", (
            f"component {name} is {accelerogram.trace_id or accelerogram.source}, which {marked} marks vertical; "
            "L and T are horizontal components (pound applies no vertical motion): choose a horizontal trace"
        ))  # fmt: skip


def impact_stiffness(scene: "Scene") -> Iterator[Notice]:
    """A hand-given impact stiffness (k_normal, k_tangential of [contact], an obstacle or a
    moat wall) more than 100 times above or below the materials' own (eqs. 6–9)."""
    from .assembly.contact import _body_material, impact_stiffness as from_materials

    contact, model = scene.contact, scene.loaded.model
    said: set[str] = set()
    for i, info in enumerate(contact.pairs):
        for term, (given, name, unit) in enumerate(((contact.pair_kn[i], "k_normal", "N/m²"),
                                                    (contact.pair_kt[i], "k_tangential", "N/m"))):  # fmt: skip
            field = contact.pair_fields[i][term]
            if field in said or _given(model, field) is None:
                continue
            try:
                own = from_materials(_body_material(scene.loaded, info.body_a), _body_material(scene.loaded, info.body_b))[term]
            except InputError:  # no single slab material: nothing to compare with
                continue
            ratio = float(given) / own
            if 1 / IMPACT_STIFFNESS_RATIO <= ratio <= IMPACT_STIFFNESS_RATIO:
                continue
            said.add(field)
            how = f"{_times(ratio)} times" if ratio > 1 else f"1/{_times(1 / ratio)} of"
            yield Notice(str(scene.loaded.source), field, (
                f"{name} = {float(given):.4g} {unit} is {how} the materials' own, {own:.4g} {unit} (\"auto\": "
                f"eqs. 6–9 for {info.body_a} against {info.body_b}); check its unit ({unit})"
            ), shortens_step=ratio > 1)  # fmt: skip


def unmet_neighbours(scene: "Scene") -> Iterator[Notice]:
    """Two buildings within levels.NEAR (1 m) of each other in plan that no contact candidate
    joins: their levels likely are not what was meant (assembly/levels.py)."""
    from .assembly.levels import scene_unmet_neighbours

    buildings = scene.system.buildings
    for i, j, d in scene_unmet_neighbours(scene):
        yield Notice(str(scene.loaded.source), f"buildings[{j}].base_elevation", (
            f"buildings {buildings[i].name!r} and {buildings[j].name!r} are {d:.3g} m apart in plan, but no floor of "
            "one lies at a floor or inside a storey of the other, so they cannot meet in pound; check their "
            "base_elevation and storey heights"))  # fmt: skip


def shared_struck_columns(scene: "Scene") -> Iterator[Notice]:
    """Columns of one storey in two struck bundles (two slabs strike overlapping sets of its
    columns): each bundle has local modes of its own, so those columns' mass is in both
    (assembly/local_modes.py)."""
    seen: dict[tuple[int, int, int], tuple[int, ...]] = {}
    said = set()
    system = scene.system
    for mode in system.local_modes:
        for column in mode.columns:
            key = (mode.building, mode.storey, column)
            other = seen.setdefault(key, mode.columns)
            if other != mode.columns and key not in said:
                said.add(key)
                bld = system.buildings[mode.building]
                name = bld.column_lines[bld.columns[column].line].name
                yield Notice(str(scene.loaded.source), f"buildings[{mode.building}]", (
                    f"column {name} of storey {mode.storey} of building {bld.name!r} is struck by two slabs with "
                    "different columns beside it: each set has local modes of its own, so its mass is counted in "
                    "both (theory §10, \"The struck columns' own mass\"); the impact forces and shears there are "
                    "approximate"))  # fmt: skip


def column_modes_capped(scene: "Scene") -> Iterator[Notice]:
    """column_modes = "auto" held at its cap of 16 for a struck set of columns whose contact
    would need more (local_modes.auto_modes): its first peak force and shear are then less
    accurate than the validation report's figures for the rule."""
    from .assembly.contact import _crossing_kn
    from .assembly.local_modes import AUTO_RATIO, MAX_MODES, highest_mode_ratio
    from .assembly.storey_contact import facade_stiffness

    contact = scene.loaded.model.contact
    if contact.column_modes != "auto":
        return
    buildings = scene.system.buildings
    said = set()
    for body in scene.contact.storeys:
        if body.modes != MAX_MODES:
            continue
        k_face = _crossing_kn(scene.loaded, buildings, body.crossing, contact, {}) * body.line
        k_columns = facade_stiffness(buildings[body.crossing.struck], body.columns, body.normal)
        ratio = highest_mode_ratio(MAX_MODES, k_face, k_columns) if k_face > 0 else np.inf
        key = (body.crossing.struck, body.crossing.storey, body.columns)
        if ratio < AUTO_RATIO and key not in said:
            said.add(key)
            yield Notice(str(scene.loaded.source), "contact.column_modes", (
                f"the columns struck in storey {body.crossing.storey} of building {buildings[body.crossing.struck].name!r} "
                f"would need more than {MAX_MODES} local modes for their contact (the highest reaches {ratio:.2g} times "
                f"the contact's own frequency, the rule asks {AUTO_RATIO:g}): their impacts' first peak force and "
                "shear are less accurate than the validation report's figures for the rule"))  # fmt: skip


def _times(ratio: float) -> str:
    """'1,000', '250', '3.2e+07': a ratio above 1 as a reader says it."""
    return f"{ratio:,.0f}" if 10 <= ratio < 1e6 else f"{ratio:.3g}"


def _given(model: Any, field: str) -> float | None:
    """The number a stiffness field holds, None if it is "auto" or absent."""
    root, _, name = field.rpartition(".")
    node: Any = model
    for part in root.replace("]", "").replace("[", ".").split("."):
        node = node[int(part)] if part.isdigit() else getattr(node, part)
    value = getattr(node, name, None)
    return None if value is None or value == "auto" else float(value)


def _record_origin(scene: "Scene") -> tuple[str, str]:
    """The file that holds the record's keys and the prefix of their field names: the
    record definition file and "", or the model and "excitation.record."."""
    if scene.ground.record_file is not None:
        return str(scene.ground.record_file), ""
    return str(scene.loaded.source), "excitation.record."


CHECKS: list[Check] = [
    elastic_modulus,
    density,
    floor_mass,
    storey_height,
    fundamental_period,
    peak_ground_acceleration,
    vertical_component,
    impact_stiffness,
    unmet_neighbours,
    shared_struck_columns,
    column_modes_capped,
]
"""The checks, in the order their notices are reported; append one to add a check."""
