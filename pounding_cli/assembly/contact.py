"""Contact candidates as arrays: the bodies that can touch, the pairs at one level, and the
impact parameters of each pair (paper eqs. 6–9, eq. 8 corrected).

Bodies are numbered floors first (body f is global floor f), then obstacles, then the storeys
that neighbours' slabs strike between two floors (storey_contact.py). Body A of a pair is the
floor of the building listed first (of a slab–storey pair: the slab); body B the other floor,
the obstacle or the storey. A storey body moves as virtual floor n_floors + 1 + k of the
solver (n_floors is the ground's slot): storey_below, storey_above, storey_shape and
storey_arm say how (solver/storey_bodies.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model import Contact, LoadedModel, Material
from .building import BuildingArrays
from .levels import LEVEL_TOLERANCE, StoreyCrossing, facing_crossings, moat_pits, storey_crossings
from .local_modes import NO_BODY_MODES, BodyModes, modal_mobility
from .storey_contact import StoreyBody, series_stiffness, storey_body
from ..solver.tunables import LIKELY_DEPTH, STEP_BOUND
from .polygon import polygon_centroid



def dynamic_modulus(e_static: float) -> float:
    """Dynamic modulus of concrete, eq. (7): E_dyn = 5.82·E_st^0.63 with both in GPa; Pa here."""
    return 5.82e9 * (e_static / 1e9) ** 0.63


def impact_stiffness(a: Material, b: Material) -> tuple[float, float]:
    """(k_N [N/m² of overlap area], k_T [N/m]) from two materials, eqs. (6)–(9).

    k_N = [(1−ν₁²)/E_dyn,1 + (1−ν₂²)/E_dyn,2]⁻¹ and k_T = [(2−ν₁)/G_dyn,1 + (2−ν₂)/G_dyn,2]⁻¹
    with G_dyn = E_dyn/(2(1+ν)): eq. (8) as printed has G_dyn,2 twice and 1−ν₂; this form
    reproduces the paper's k_N = 2.06×10⁷ kN/m², k_T = 4.59×10⁶ kN/m for E = 21 GPa, ν = 0.2.
    k_T, a modulus, is used as a spring stiffness in N/m, as the paper does.
    """
    ea, eb = dynamic_modulus(a.elastic_modulus), dynamic_modulus(b.elastic_modulus)
    ga, gb = ea / (2 * (1 + a.poisson_ratio)), eb / (2 * (1 + b.poisson_ratio))
    k_n = 1.0 / ((1 - a.poisson_ratio**2) / ea + (1 - b.poisson_ratio**2) / eb)
    k_t = 1.0 / ((2 - a.poisson_ratio) / ga + (2 - b.poisson_ratio) / gb)
    return k_n, k_t


def restitution_of(zeta: float) -> float:
    """Coefficient of restitution of a spring–dashpot contact that cannot pull.

    Relative motion m·x'' + c·x' + k·x = 0 from x = 0, x' = v₀, while the contact force
    k·x + c·x' is compressive; it separates when that force returns to zero, at
    ω_d·t_s = π − atan(2ζ√(1−ζ²)/(1−2ζ²)), and e = |x'(t_s)|/v₀ =
    e^(−ζω t_s)·|cos ω_d t_s − ζ/√(1−ζ²)·sin ω_d t_s| (ω_d = ω√(1−ζ²)).
    """
    if zeta <= 0.0:
        return 1.0
    s = np.sqrt(1.0 - zeta * zeta)
    phase = np.arctan2(2.0 * zeta * s, 1.0 - 2.0 * zeta * zeta)  # in (0, π) for 0 < ζ < 1
    wt = np.pi - phase  # ω_d·t_s
    return float(np.exp(-zeta * wt / s) * abs(np.cos(wt) - zeta / s * np.sin(wt)))


def restitution_damping_ratio(e: float) -> float:
    """Damping ratio ζ whose no-tension spring–dashpot contact rebounds with restitution e
    (inverse of restitution_of). The classical ζ = −ln e/√(π² + ln² e) (Anagnostopoulos
    1988) assumes the dashpot may pull until the overlap closes; a contact that cannot pull
    separates earlier and dissipates less, so it needs a larger ζ for the same e."""
    if e >= 1.0:
        return 0.0
    from scipy.optimize import brentq

    return float(brentq(lambda z: restitution_of(z) - e, 1e-12, 1.0 - 1e-9, xtol=1e-15, rtol=1e-14))


@dataclass(frozen=True)
class PairInfo:
    """Who a contact pair is, for reports and the impact log."""

    body_a: str
    floor_a: int  # 1-based floor of body A's building
    body_b: str
    floor_b: int  # 1-based floor of body B's building (for a storey: the floor above it); 0 for an obstacle
    elevation: float  # m
    storey: int = 0  # slab–storey: the 1-based storey of body B's building that A's slab strikes; else 0
    xi: float = float("nan")  # slab–storey: where along that storey's height, (z − z_below)/h

    @property
    def kind(self) -> str:
        """slab-slab, slab-storey or slab-obstacle."""
        return "slab-storey" if self.storey else "slab-slab" if self.floor_b else "slab-obstacle"


@dataclass(frozen=True)
class ContactArrays:
    """Everything the contact kernel needs, as arrays."""

    body_poly: np.ndarray  # (n_bodies, n_v_max, 2) outlines at rest, global, counter-clockwise
    body_nv: np.ndarray  # (n_bodies,) vertex count
    body_floor: np.ndarray  # (n_bodies,) global floor index, −1 for a fixed obstacle
    body_centre: np.ndarray  # (n_bodies, 2) mass centre (floors) or centroid (obstacles) at rest
    body_radius: np.ndarray  # (n_bodies,) largest distance from body_centre to a vertex, m
    pair_a: np.ndarray  # (n_pairs,) body index of A
    pair_b: np.ndarray  # (n_pairs,) body index of B
    pair_kn: np.ndarray  # N/m²
    pair_kt: np.ndarray  # N/m
    pair_mu_s: np.ndarray
    pair_mu_k: np.ndarray
    pair_cn: np.ndarray  # constant normal dashpot, N·s/m
    pair_zeta: np.ndarray  # damping ratio of the restitution dashpot (0: none)
    pair_ct: np.ndarray  # tangential dashpot, N·s/m
    pair_meff: np.ndarray  # m_A·m_B/(m_A + m_B), kg (m_A against an obstacle)
    pairs: list[PairInfo]
    omega_max: float  # rad/s, upper bound of the fastest contact vibration (0 without pairs)
    pair_mobility: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (n_pairs,) Σ(1/m + r²/J) of the two bodies, 1/kg
    omega_step: float = 0.0  # rad/s, the likely fastest contact vibration: what Δt = "auto" follows
    pair_omega: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (n_pairs,) each pair's likely ω, rad/s
    pair_fields: list[tuple[str, str]] = field(default_factory=list)  # the model fields that set each pair's (k_N, k_T)
    cause_max: tuple[int, int] = (-1, 0)  # (pair, 0: k_N·line, 1: k_T) that sets omega_max
    cause_step: tuple[int, int] = (-1, 0)  # (pair, term) that sets omega_step
    crossings: list[StoreyCrossing] = field(default_factory=list)  # slabs between a neighbour's floors (levels.py)
    storeys: list[StoreyBody] = field(default_factory=list)  # the storey bodies, in body order after the obstacles
    storey_below: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # (n_s,) global floor below, −1: ground
    storey_above: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # (n_s,) global floor above
    storey_shape: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (n_s,) s(ξ)
    storey_arm: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))  # (n_s, 2) G_above − G_below at rest, m
    body_modes: BodyModes = NO_BODY_MODES  # the struck columns' local modes that move each storey body (local_modes.py)
    reach: float = float("inf")  # m: buildings farther apart at rest have no candidates (city/reach.py)
    reach_source: str = ""  # "contact.reach", "bound" or why nothing is pruned
    near: frozenset[tuple[int, int]] | None = None  # the building pairs within reach when some were pruned, else None

    def stiffness_field(self, cause: tuple[int, int]) -> str:
        """The model field that sets the stiffness term `cause` (a cause_max or cause_step)."""
        pair, term = cause
        return self.pair_fields[pair][term] if 0 <= pair < len(self.pair_fields) else "contact.k_normal"

    @property
    def n_pairs(self) -> int:
        return self.pair_a.size


def contact_arrays(loaded: LoadedModel, buildings: list[BuildingArrays],
                   near: set[tuple[int, int]] | None = None) -> ContactArrays:  # fmt: skip
    """Candidate pairs and their parameters (no pairs when contact is disabled). `near`: the
    building pairs (i, j), i < j, within reach (city/reach.py); None: every two buildings."""
    model = loaded.model
    contact = model.contact
    polys, floors, centres, masses, inertias, owners = [], [], [], [], [], []
    start = 0
    for b, bld in enumerate(buildings):
        for f in range(bld.n_floors):
            polys.append(bld.slabs[f])
            floors.append(start + f)
            centres.append(bld.mass_centre[f])
            masses.append(bld.mass[3 * f])
            inertias.append(bld.mass[3 * f + 2])
            owners.append((b, f))
        start += bld.n_floors
    n_floors = start
    obstacles = model.all_obstacles()
    for obstacle in obstacles:
        poly = np.asarray(obstacle.polygon, dtype=float)
        polys.append(poly)
        floors.append(-1)
        centres.append(polygon_centroid(poly))
        masses.append(np.inf)
        inertias.append(np.inf)
    # the storeys that slabs strike between a neighbour's floors: bodies after the obstacles
    crossings = storey_crossings(buildings, moat_pits(model), near) if contact.enabled else []
    materials_of: dict[str, Material] = {}  # per body, found once (a building's walks every column)
    storeys = [storey_body(buildings, c, contact.column_modes, _crossing_kn(loaded, buildings, c, contact, materials_of))
               for c in crossings]  # fmt: skip
    first_floor = np.concatenate([[0], np.cumsum([b.n_floors for b in buildings])]).astype(np.int64)
    storey_bodies = len(polys)
    for k, body in enumerate(storeys):
        struck = buildings[body.crossing.struck]
        polys.append(struck.slabs[body.above])
        floors.append(n_floors + 1 + k)
        centres.append(struck.mass_centre[body.above])
        owners.append((body.crossing.struck, body.above))
    nv = np.array([p.shape[0] for p in polys], dtype=np.int64)
    body_poly = np.zeros((len(polys), int(nv.max()), 2))
    for k, p in enumerate(polys):
        body_poly[k, : p.shape[0]] = p
    centre = np.asarray(centres, dtype=float).reshape(-1, 2)
    radius = np.array([np.max(np.hypot(*(p - c).T)) for p, c in zip(polys, centre)])
    for k, body in enumerate(storeys):
        mass, inertia = _storey_inertia(buildings, first_floor, body, float(radius[storey_bodies + k]))
        masses.append(mass)
        inertias.append(inertia)

    candidates: list[tuple[int, int, PairInfo]] = []
    if contact.enabled:
        flat = [(b, f, bld) for b, bld in enumerate(buildings) for f in range(bld.n_floors)]
        for ia, ib in _level_pairs(flat) if near is None else _near_level_pairs(buildings, near):
            (_, fa, bld_a), (_, fb, bld_b) = flat[ia], flat[ib]
            info = PairInfo(bld_a.name, fa + 1, bld_b.name, fb + 1, float(bld_a.elevation[fa]))
            candidates.append((ia, ib, info))
        for o, obstacle in enumerate(obstacles):
            for ia, (ba, fa, bld_a) in enumerate(flat):
                if obstacle.spans(float(bld_a.elevation[fa]), LEVEL_TOLERANCE):
                    info = PairInfo(bld_a.name, fa + 1, obstacle.name, 0, float(bld_a.elevation[fa]))
                    _check_apart(polys[ia], polys[n_floors + o], info, _obstacle_field(model, o), loaded)
                    candidates.append((ia, n_floors + o, info))

        for k, body in enumerate(storeys):
            c = body.crossing
            info = PairInfo(buildings[c.building].name, c.floor + 1, buildings[c.struck].name, c.storey, c.elevation,
                            c.storey, c.xi)  # fmt: skip
            candidates.append((int(first_floor[c.building] + c.floor), storey_bodies + k, info))

    # each pair's settings: [contact]'s, with an obstacle's (or moat wall's) own in their place
    settings = [obstacles[j - n_floors].applied_to(contact) if n_floors <= j < storey_bodies else contact
                for _, j, _ in candidates]  # fmt: skip
    k_pairs = [_pair_stiffness(loaded, info, s, materials_of) for s, (_, _, info) in zip(settings, candidates)]
    # two slabs at neighbouring levels, each between the other's floors, strike each other's storeys at
    # one interface: each contact takes half its law (k_N, k_T and the dashpots; ζ/√2 halves 2ζ√(k_N·L·m)),
    # so that as the levels meet the two make the one slab–slab contact (docs/theory.md §10)
    shared = [False] * (len(candidates) - len(storeys)) + facing_crossings(crossings)
    k_pairs = [(k[0] / 2, k[1] / 2) if half else k for k, half in zip(k_pairs, shared)]
    # a struck storey's columns give way locally, in series with the overlap law (storey_contact.py)
    k_pairs = [series_stiffness(*k, storeys[j - storey_bodies]) if j >= storey_bodies else k
               for k, (_, j, _) in zip(k_pairs, candidates)]  # fmt: skip
    share = np.where(shared, 0.5, 1.0)
    fields = [_stiffness_fields(model, j - n_floors if j < storey_bodies else -1) for _, j, _ in candidates]
    kn = np.array([k[0] for k in k_pairs], dtype=float)
    kt = np.array([k[1] for k in k_pairs], dtype=float)
    m = np.asarray(masses)
    meff = np.array([m[i] if not np.isfinite(m[j]) else m[i] * m[j] / (m[i] + m[j]) for i, j, _ in candidates])
    zetas = {e: restitution_damping_ratio(e) for e in {s.restitution for s in settings} if e not in (None, 1.0)}
    arrays = ContactArrays(
        body_poly=body_poly,
        body_nv=nv,
        body_floor=np.asarray(floors, dtype=np.int64),
        body_centre=centre,
        body_radius=radius,
        pair_a=np.array([c[0] for c in candidates], dtype=np.int64),
        pair_b=np.array([c[1] for c in candidates], dtype=np.int64),
        pair_kn=kn,
        pair_kt=kt,
        pair_mu_s=np.array([s.friction_static for s in settings], dtype=float),
        pair_mu_k=np.array([s.friction_kinetic for s in settings], dtype=float),
        pair_cn=np.array([s.damping_normal or 0.0 for s in settings], dtype=float) * share,
        pair_zeta=np.array([zetas.get(s.restitution, 0.0) for s in settings], dtype=float) * np.sqrt(share),
        pair_ct=np.array([s.damping_tangential or 0.0 for s in settings], dtype=float) * share,
        pair_meff=meff.astype(float),
        pairs=[c[2] for c in candidates],
        omega_max=0.0,
    )
    # the contact's upper bound: the overlap grows at most as fast as L·δ, L the smaller body's
    # diameter, so the normal force stiffens at most to k_N·L (the tangential spring: k_T),
    # acting at a point of mobility at most pair_mobility; the likely bound: L from the edges'
    # angles (likely_contact_line)
    mobility = pair_mobility(arrays, m, np.asarray(inertias))
    diameters = np.array([_diameter(p) for p in polys])
    longest = np.array([min(diameters[i], diameters[j]) for i, j, _ in candidates])
    likely = np.array([likely_contact_line(polys[i], polys[j]) for i, j, _ in candidates])
    omega_max, cause_max = fastest_cause(kn, kt, longest, mobility)
    omega_likely, cause_step = fastest_cause(kn, kt, np.minimum(likely, longest), mobility)
    each = pair_omegas(kn, kt, np.minimum(likely, longest), mobility)
    if not omega_likely >= STEP_BOUND * omega_max:  # the likely contacts are far softer (or not finite)
        omega_likely, cause_step = STEP_BOUND * omega_max, cause_max
    return ContactArrays(**{**arrays.__dict__, "omega_max": omega_max, "pair_mobility": mobility,
                            "omega_step": omega_likely, "pair_omega": each, "pair_fields": fields, "cause_max": cause_max,
                            "cause_step": cause_step, "crossings": crossings, "storeys": storeys,
                            "storey_below": np.array([first_floor[b.crossing.struck] + b.below if b.below >= 0 else -1
                                                      for b in storeys], dtype=np.int64).reshape(-1),
                            "storey_above": np.array([first_floor[b.crossing.struck] + b.above for b in storeys],
                                                     dtype=np.int64).reshape(-1),
                            "storey_shape": np.array([b.shape for b in storeys], dtype=float).reshape(-1),
                            "storey_arm": np.array([b.arm for b in storeys], dtype=float).reshape(-1, 2)})  # fmt: skip


def _storey_inertia(buildings: list[BuildingArrays], first_floor: np.ndarray, body: StoreyBody,
                    radius: float) -> tuple[float, float]:  # fmt: skip
    """(m, J) of a storey body for the dashpot's effective mass and the contact step's bound:
    a force F at r from the upper floor's mass centre accelerates the outline there by
    F·[s²(1/m₁ + r²/J₁) + (1 − s)²(1/m₀ + (r + |d|)²/J₀)] at most (storey_contact.py), which
    1/m + r²/J with these equals at r = radius (the ground below: 1/m₀ = 1/J₀ = 0)."""
    struck = buildings[body.crossing.struck]
    s = body.shape
    m1, j1 = struck.mass[3 * body.above], struck.mass[3 * body.above + 2]
    inv_m, inv_j = s * s / m1, s * s / j1
    if body.below >= 0:
        m0, j0 = struck.mass[3 * body.below], struck.mass[3 * body.below + 2]
        stretch = (1.0 + float(np.hypot(*body.arm)) / radius) ** 2 if radius > 0 else 1.0
        inv_m += (1.0 - s) ** 2 / m0
        inv_j += (1.0 - s) ** 2 * stretch / j0
    inv_m += modal_mobility(body.crossing.xi, body.bundle_mass, body.modes)  # the columns' local modes
    return 1.0 / inv_m, 1.0 / inv_j


def _stiffness_fields(model, o: int) -> tuple[str, str]:
    """The fields that set a pair's (k_N, k_T): an obstacle's (or moat wall's) own where it
    gives them (o ≥ 0: the pair's obstacle in all_obstacles()), else [contact]'s, which for
    "auto" come from the materials' elastic_modulus."""
    out = []
    for name in ("k_normal", "k_tangential"):
        if o >= 0 and name in model.all_obstacles()[o].overrides():
            out.append(f"{_obstacle_root(model, o)}.{name}")
        else:
            out.append(f"contact.{name}")
    return out[0], out[1]


def _obstacle_root(model, o: int) -> str:
    """The model table of obstacle o of all_obstacles(): obstacles[i], or a moat's."""
    if o < len(model.obstacles):
        return f"obstacles[{o}]"
    o -= len(model.obstacles)
    for b, building in enumerate(model.buildings):
        iso = building.isolation
        if iso is not None and iso.moat is not None:
            if o < len(iso.slab):
                return f"buildings[{b}].isolation.moat"
            o -= len(iso.slab)
    return "obstacles"


def fastest_cause(kn: np.ndarray, kt: np.ndarray, line: np.ndarray, mobility: np.ndarray) -> tuple[float, tuple[int, int]]:
    """(ω, (pair, term)): the largest of pair_omegas and the pair and term (0: k_N·line, 1: k_T) that give it;
    (0, (−1, 0)) without pairs. A term that overflows counts as infinite."""
    if kn.size == 0:
        return 0.0, (-1, 0)
    with np.errstate(over="ignore", invalid="ignore"):
        terms = np.stack([kn * line, kt]) * mobility
    terms = np.where(np.isnan(terms), np.inf, terms)
    term, pair = np.unravel_index(int(np.argmax(terms)), terms.shape)
    return float(np.sqrt(terms[term, pair])), (int(pair), int(term))


def _level_pairs(flat: list) -> list[tuple[int, int]]:  # type: ignore[type-arg]
    """(ia, ib) of every two floors of different buildings at one level, ib of a later
    building, in the order of a loop over ia then ib: found among the floors within reach of
    each one's elevation (sorted), not by comparing every floor with every other, which for
    40 buildings of 1000 storeys made 1.6e9 comparisons."""
    z = np.array([bld.elevation[f] for _, f, bld in flat], dtype=float)
    owner = np.array([b for b, _, _ in flat], dtype=np.int64)
    order = np.argsort(z, kind="stable")
    ordered = z[order]
    out = []
    for ia in range(z.size):
        lo = np.searchsorted(ordered, z[ia] - 2 * LEVEL_TOLERANCE, side="left")
        hi = np.searchsorted(ordered, z[ia] + 2 * LEVEL_TOLERANCE, side="right")
        near = np.sort(order[lo:hi])
        near = near[(owner[near] > owner[ia]) & (np.abs(z[ia] - z[near]) < LEVEL_TOLERANCE)]
        out.extend((ia, int(ib)) for ib in near)
    return out


def _near_level_pairs(buildings: list[BuildingArrays], near: set[tuple[int, int]]) -> list[tuple[int, int]]:
    """_level_pairs restricted to the building pairs `near`, in the same order (by ia, then
    ib), found pair by pair: O(pairs within reach), not O(floors at a level)."""
    first = np.concatenate([[0], np.cumsum([b.n_floors for b in buildings])]).astype(np.int64)
    out = []
    for i, j in near:
        z_j = buildings[j].elevation
        order = np.argsort(z_j, kind="stable")
        for fa, z in enumerate(buildings[i].elevation):
            lo = np.searchsorted(z_j[order], z - LEVEL_TOLERANCE, side="left")
            hi = np.searchsorted(z_j[order], z + LEVEL_TOLERANCE, side="right")
            for fb in order[lo:hi]:
                if abs(z - z_j[fb]) < LEVEL_TOLERANCE:
                    out.append((int(first[i] + fa), int(first[j] + fb)))
    return sorted(out)


def _obstacle_field(model, o: int) -> str:
    """The model field of obstacle o of all_obstacles(): given, or a moat wall segment."""
    root = _obstacle_root(model, o)
    if root.endswith(".moat"):
        return root + ".gap"
    return root + ".polygon" if root.startswith("obstacles[") else root


def _check_apart(slab: np.ndarray, obstacle: np.ndarray, info: PairInfo, field: str, loaded: LoadedModel) -> None:
    """An obstacle must not overlap a floor at its level before the ground moves."""
    import shapely

    area = shapely.Polygon(slab).intersection(shapely.Polygon(obstacle)).area
    if area > 1e-9 * min(shapely.Polygon(slab).area, shapely.Polygon(obstacle).area):
        raise InputError(
            f"at rest, obstacle {info.body_b!r} overlaps floor {info.floor_a} of building {info.body_a!r} "
            f"at elevation {info.elevation:g} m by {area:.4g} m²; move the obstacle so that they are apart or touch",
            file=loaded.source,
            field=field,
        )


def _pair_stiffness(loaded: LoadedModel, info: PairInfo, settings: Contact,
                    materials_of: dict[str, Material] | None = None) -> tuple[float, float]:  # fmt: skip
    """(k_N, k_T) of a pair: as its contact settings give them, or "auto" from the bodies'
    materials (`materials_of` caches each body's material by name: finding a building's
    walks all its columns)."""
    kn, kt = settings.k_normal, settings.k_tangential
    if kn != "auto" and kt != "auto":
        return float(kn), float(kt)
    cache = {} if materials_of is None else materials_of
    for name in (info.body_a, info.body_b):
        if name not in cache:
            cache[name] = _body_material(loaded, name)
    auto_n, auto_t = impact_stiffness(cache[info.body_a], cache[info.body_b])
    return (auto_n if kn == "auto" else float(kn)), (auto_t if kt == "auto" else float(kt))


def _crossing_kn(loaded: LoadedModel, buildings: list[BuildingArrays], c: StoreyCrossing, contact: Contact,
                 materials_of: dict[str, Material]) -> float:  # fmt: skip
    """k_N of a slab–storey crossing's pair (N/m²), for column_modes = "auto" (0 where it needs none)."""
    if contact.column_modes != "auto" or not contact.enabled:
        return 0.0
    info = PairInfo(buildings[c.building].name, c.floor + 1, buildings[c.struck].name, c.storey, c.elevation, c.storey,
                    c.xi)  # fmt: skip
    return _pair_stiffness(loaded, info, contact, materials_of)[0]


def _body_material(loaded: LoadedModel, name: str) -> Material:
    """The material of a body for "auto" impact stiffness: a building's slab material, an
    obstacle's (or moat wall's) own."""
    model = loaded.model
    building = next((b for b in model.buildings if b.name == name), None)
    if building is None:
        obstacle = next(o for o in model.all_obstacles() if o.name == name)
        return model.materials[obstacle.material]
    slab = building.slab_material_name()
    if slab is None:
        raise InputError(
            "its columns use several materials, so the slab material for the \"auto\" impact "
            "stiffness is ambiguous; name it with slab_material",
            file=loaded.source,
            field=f"buildings[{model.buildings.index(building)}].slab_material",
        )
    return model.materials[slab]


def _diameter(poly: np.ndarray) -> float:
    return float(np.max(np.hypot(*(poly[:, None, :] - poly[None, :, :]).reshape(-1, 2).T)))


def pair_mobility(arrays: ContactArrays, mass: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """Σ(1/m + r²/J) over each pair's two bodies, 1/kg: the largest mobility a point of a
    body can have (r: the body's largest vertex distance from its mass centre; obstacles do
    not move)."""
    out = np.zeros(arrays.n_pairs)
    for p in range(arrays.n_pairs):
        for k in (int(arrays.pair_a[p]), int(arrays.pair_b[p])):
            if np.isfinite(mass[k]):
                out[p] += 1.0 / mass[k] + arrays.body_radius[k] ** 2 / inertia[k]
    return out


def pair_omegas(kn: np.ndarray, kt: np.ndarray, line: np.ndarray, mobility: np.ndarray) -> np.ndarray:
    """ω = √(max(k_N·line, k_T)·mobility) of each pair, rad/s: the fastest vibration of its
    contact with that contact line (m); a term that overflows counts as infinite."""
    with np.errstate(over="ignore", invalid="ignore"):
        omega = np.sqrt(np.maximum(kn * line, kt) * mobility)
    return np.where(np.isnan(omega), np.inf, omega)


def likely_contact_line(poly_a: np.ndarray, poly_b: np.ndarray, depth: float = LIKELY_DEPTH) -> float:
    """The longest contact line two outlines at rest can form when pressed `depth` (m) into
    each other, by the angle between their edges: two edges that face each other (outward
    normals opposed) at an angle φ overlap along at most depth/tan φ, and no longer than either
    edge; a vertex has two edges, hence the factor 2. Parallel faces give their shorter
    length (twice it, capped by the caller at the smaller diameter); a corner leading at 2°
    gives 2·depth/tan 2° = 57 mm at 1 mm. Twists during the run (milliradians) barely change
    an angle of degrees; where they could align two edges, the run measures what it met and
    repeats itself at the step that needs (observed_pair_omega)."""
    def edges(poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d = np.roll(poly, -1, axis=0) - poly
        length = np.hypot(d[:, 0], d[:, 1])
        keep = length > 0
        return length[keep], np.arctan2(d[keep, 1], d[keep, 0])

    len_a, ang_a = edges(np.asarray(poly_a, dtype=float))
    len_b, ang_b = edges(np.asarray(poly_b, dtype=float))
    # edges of counter-clockwise outlines face each other when their directions are opposed:
    # φ is the angle between edge a and edge b reversed
    phi = np.abs(np.angle(np.exp(1j * (ang_a[:, None] - ang_b[None, :] - np.pi))))
    facing = phi < np.pi / 2
    with np.errstate(divide="ignore"):
        reach = np.where(phi > 0, depth / np.tan(phi), np.inf)
    line = np.minimum(np.minimum(len_a[:, None], len_b[None, :]), reach)
    return float(2.0 * np.max(np.where(facing, line, 0.0), initial=0.0))


def observed_pair_omega(contact: ContactArrays, events: np.ndarray) -> np.ndarray:
    """(n_pairs,) the fastest contact vibration a run met at each pair, rad/s (0 where it met
    none): √(max(k_N·ℓ, k_T)·mobility) of each logged impact, ℓ its longest contact line
    (solver column EV_PEAK_LENGTH)."""
    from ..solver.layout import EV_PAIR, EV_PEAK_LENGTH

    seen = np.zeros(contact.n_pairs)
    if events.shape[0] == 0 or contact.n_pairs == 0:
        return seen
    p = events[:, EV_PAIR].astype(np.int64)
    omega = pair_omegas(contact.pair_kn[p], contact.pair_kt[p], events[:, EV_PEAK_LENGTH], contact.pair_mobility[p])
    np.maximum.at(seen, p, omega)
    return seen
