"""The moat wall of a base-isolated building with its own gap and impact parameters (issue 6).

Its stiffness, friction and dashpots (restitution or coefficients) replace [contact]'s for
the base slab against the wall, resolved by the same code as an obstacle's
(`ImpactOverrides.applied_to`); `pound validate` shows them per pair. Checked here:

* resolution: what the moat gives replaces [contact]'s, the rest is [contact]'s; a
  restitution replaces a [contact] dashpot coefficient and the other way round;
* onset: the base slab of a one-storey isolated building, shaken along x by a ground pulse
  while its bearings stay elastic and undamped, touches the wall at the first step after
  its displacement reaches the gap. The time it does is found from an independent exact
  solution of the 2-DOF equations (tests/exact.py, the matrix exponential) before any
  contact;
* the moat's own k_N is the one used: F_N = k_N·A_c at every stored sample in contact, read
  from the HDF5 contact histories, with A_c = (u_b − gap)·6 m (the slab's edge against the
  wall's straight face);
* one run in which the isolated building hits its moat wall and a neighbour: both pairs are
  in the impact log, each with its own k_N.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from exact import exact_response
from pounding_cli import describe, read_hdf5, run_model
from pounding_cli.api import prepare
from pounding_cli.assembly.contact import restitution_damping_ratio
from pounding_cli.cli import app
from pounding_cli.model import Contact, validate_model
from pounding_cli.model.inelastic import Moat

SIZE = 6.0  # m, square slabs
MASS_PER_AREA = 1000.0  # kg/m²: 36 t per slab
K1, K2 = 1.8e6, 1.8e5  # N/m per bearing, four bearings
YIELD = 0.5  # m: the bearings stay elastic in these scenes
E_CONCRETE = 21e9
SECTION = 0.35
HEIGHT = 3.0
GAP = 0.05  # m, moat
K_MOAT = 5e8  # N/m², the moat's own; [contact]'s is "auto" (2.06e10 N/m² for this concrete)
RECORD_DT = 0.01
PULSE = 3.0  # m/s², ground acceleration of the pulse (towards −X, so the building moves to +x)


def pulse(duration: float = 0.6) -> np.ndarray:
    """Ground acceleration along X: −PULSE for `duration`, then 0, sampled every RECORD_DT."""
    t = np.arange(0.0, 4.0 + 1e-9, RECORD_DT)
    return np.where(t < duration - 1e-9, -PULSE, 0.0)


def isolated(name: str = "iso", origin: tuple[float, float] = (0.0, 0.0), moat: dict | None = None) -> dict:
    square = [[0, 0], [SIZE, 0], [SIZE, SIZE], [0, SIZE]]
    iso = {"height": 0.5, "slab": square, "mass_per_area": MASS_PER_AREA,
           "isolator_grid": {"x": [0, SIZE], "y": [0, SIZE], "bearing": "lrb"}}  # fmt: skip
    if moat is not None:
        iso["moat"] = moat
    return {
        "name": name,
        "origin": list(origin),
        "damping": {"ratios": [0.0, 0.0], "modes": [1, 3]},
        "isolation": iso,
        "floors": [{"height": HEIGHT, "slab": square, "mass_per_area": MASS_PER_AREA,
                    "column_grid": {"x": [0, SIZE], "y": [0, SIZE], "section": [SECTION, SECTION],
                                    "material": "concrete"}}],  # fmt: skip
    }


def model_doc(buildings: list[dict], duration: float = 2.0, contact: dict | None = None) -> dict:
    return {
        "materials": {"concrete": {"elastic_modulus": E_CONCRETE, "poisson_ratio": 0.2}},
        "bearings": {"lrb": {"initial_stiffness": K1, "post_yield_stiffness": K2, "yield_displacement": YIELD}},
        "buildings": buildings,
        "excitation": {"angle": 0.0, "components": ["L"],
                       "record": {"L": {"file": "pulse.txt", "units": "m/s2", "dt": RECORD_DT, "format": "text"}}},
        "analysis": {"duration": duration, "output_interval": 0.001},
        "contact": contact or {},
    }  # fmt: skip


def write(tmp_path, doc: dict, record: np.ndarray) -> object:
    np.savetxt(tmp_path / "pulse.txt", record)
    return validate_model(doc, tmp_path / "model.toml")


# --- resolution -------------------------------------------------------------------------


def test_moat_parameters_replace_contacts_where_given():
    contact = Contact(k_normal=2e10, friction_static=0.8, friction_kinetic=0.6, damping_normal=1e6,
                      damping_tangential=2e5)  # fmt: skip
    moat = Moat(gap=GAP, material="concrete", k_normal=K_MOAT, restitution=0.5, friction_static=0.3)
    s = moat.applied_to(contact)
    assert (s.k_normal, s.k_tangential) == (K_MOAT, "auto")
    assert (s.restitution, s.damping_normal) == (0.5, None)  # the moat's dashpot replaces [contact]'s
    assert s.damping_tangential == 2e5
    assert (s.friction_static, s.friction_kinetic) == (0.3, 0.3)  # [contact]'s μ_k capped at the moat's μ_s
    assert Moat(gap=GAP, material="concrete").applied_to(contact) is contact
    back = Moat(gap=GAP, material="concrete", damping_normal=3e5).applied_to(Contact(restitution=0.7))
    assert (back.restitution, back.damping_normal) == (None, 3e5)
    with pytest.raises(ValueError, match="either 'restitution' or 'damping_normal'"):
        Moat(gap=GAP, material="concrete", restitution=0.5, damping_normal=1e5)
    with pytest.raises(ValueError, match=r"friction_kinetic \(0.5\) exceeds friction_static \(0.3\)"):
        Moat(gap=GAP, material="concrete", friction_static=0.3, friction_kinetic=0.5)


def test_pair_arrays_and_validate_show_the_moats_own_parameters(tmp_path):
    moat = {"gap": GAP, "material": "concrete", "k_normal": K_MOAT, "k_tangential": 3e8, "restitution": 0.5,
            "damping_tangential": 1e5, "friction_static": 0.4, "friction_kinetic": 0.3}  # fmt: skip
    neighbour = isolated("neighbour", (SIZE + 2 * GAP + 2.0 + 0.03, 0.0))  # beyond the moat's 1 m wall
    del neighbour["isolation"]
    neighbour["floors"][0]["height"] = HEIGHT + 0.5
    doc = model_doc([isolated(moat=moat), neighbour], contact={"damping_normal": 2e6})
    loaded = write(tmp_path, doc, pulse())
    c = prepare(loaded).contact
    names = [(p.body_a, p.body_b) for p in c.pairs]
    assert names == [("iso", "neighbour")] + [("iso", f"iso.moat{k}") for k in (1, 2, 3, 4)]
    moat_pairs = slice(1, 5)
    zeta = restitution_damping_ratio(0.5)
    np.testing.assert_array_equal(c.pair_kn[moat_pairs], K_MOAT)
    np.testing.assert_array_equal(c.pair_kt[moat_pairs], 3e8)
    np.testing.assert_array_equal(c.pair_mu_s[moat_pairs], 0.4)
    np.testing.assert_array_equal(c.pair_mu_k[moat_pairs], 0.3)
    np.testing.assert_array_equal(c.pair_zeta[moat_pairs], zeta)
    np.testing.assert_array_equal(c.pair_cn[moat_pairs], 0.0)  # the restitution replaced [contact]'s c_N
    np.testing.assert_array_equal(c.pair_ct[moat_pairs], 1e5)
    # the floors' pair keeps [contact]'s: auto stiffness, default friction, its c_N
    assert c.pair_kn[0] == pytest.approx(2.064e10, rel=1e-3)
    assert (c.pair_mu_s[0], c.pair_mu_k[0], c.pair_zeta[0], c.pair_cn[0], c.pair_ct[0]) == (0.8, 0.6, 0.0, 2e6, 0.0)
    # validate, --json: per pair, and the moat per building
    info = describe(loaded)
    pairs = info["contact"]["pairs"]
    assert pairs[1]["k_normal_N_per_m2"] == K_MOAT and pairs[1]["friction_static"] == 0.4
    assert pairs[1]["restitution"] == pytest.approx(0.5, abs=1e-12)
    assert pairs[1]["damping_ratio_normal"] == zeta and pairs[1]["damping_tangential_N_s_per_m"] == 1e5
    assert pairs[0]["restitution"] is None and pairs[0]["damping_normal_N_s_per_m"] == 2e6
    assert info["buildings"][0]["moat"]["gap_m"] == GAP
    assert info["buildings"][0]["moat"]["walls"] == [f"iso.moat{k}" for k in (1, 2, 3, 4)]
    assert info["buildings"][0]["moat"]["overrides"]["restitution"] == 0.5
    (tmp_path / "model.json").write_text(json.dumps(doc))
    text = " ".join(CliRunner().invoke(app, ["validate", str(tmp_path / "model.json")]).stdout.split())
    assert ("floor–iso.moat1, floor–iso.moat2, floor–iso.moat3, floor–iso.moat4: k_N = 5e+05 kN/m², k_T = "
            "3e+05 kN/m; μ_s = 0.4, μ_k = 0.3; normal dashpot for e = 0.5 (ζ = 0.2553), tangential dashpot "
            "1e+05 N·s/m") in text
    assert "floor–floor: k_N = 2.064e+07 kN/m²" in text and "normal dashpot 2e+06 N·s/m" in text


# --- onset and force ----------------------------------------------------------------------


def two_dof_free_flight(record: np.ndarray, t_end: float, h: float) -> np.ndarray:
    """(n, 2) u_b, u_1 along x every h s up to t_end, before any contact: the 2-DOF
    equations of the doubly symmetric building (no damping, elastic bearings), exactly."""
    m = MASS_PER_AREA * SIZE**2
    kc = 4 * 12 * E_CONCRETE * (SECTION**4 / 12) / HEIGHT**3
    k = np.array([[4 * K1 + kc, -kc], [-kc, kc]])
    ground = np.column_stack([record, np.zeros_like(record)])
    influence = np.array([[1.0, 0.0], [1.0, 0.0]])
    substeps = round(RECORD_DT / h)
    return exact_response(np.array([m, m]), k, np.zeros((2, 2)), influence, ground, RECORD_DT, substeps,
                          math.ceil(t_end / h) + 1)  # fmt: skip


@pytest.fixture(scope="module")
def moat_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("moat")
    moat = {"gap": GAP, "material": "concrete", "k_normal": K_MOAT}
    loaded = write(tmp, model_doc([isolated(moat=moat)], duration=1.5), pulse())
    result = run_model(loaded, output=tmp / "out.h5")
    return result, read_hdf5(tmp / "out.h5")


def test_contact_starts_when_the_slab_reaches_the_gap(moat_run):
    """The first moat impact starts where the slab reaches the wall: t_start within 1e-3·Δt
    (1.3e-7 s, the issue's tolerance for located events) of t_gap, the instant the exact
    solution reaches the gap (found to ~1e-11 s by linear interpolation between its samples
    1e-5 s apart). The hybrid propagates exactly until the CDM takes over just before the wall
    (its displacement error there is 4e-14 m, 2e-13 s at the slab's 0.22 m/s), and the touch is
    located inside the step on the straight path between two steps. Measured: |t_start − t_gap|
    = 1.0e-5·Δt (before issue 28 it was the first step after, 0.50·Δt late)."""
    result, _ = moat_run
    assert result.complete
    events = result.contact.events
    assert events.size and all(str(b).startswith("iso.moat") for b in events["body_b"])
    first = events[np.argmin(events["t_start"])]
    assert first["body_b"] == "iso.moat2"  # the wall on the slab's +x edge (segments follow the edges)
    h = 1e-5
    exact = two_dof_free_flight(pulse(), first["t_start"] + 0.01, h)
    k = int(np.argmax(exact[:, 0] > GAP))
    assert k > 0, "the exact solution never reaches the gap"
    t_gap = (k - 1 + (GAP - exact[k - 1, 0]) / (exact[k, 0] - exact[k - 1, 0])) * h  # linear in h = 1e-5 s
    dt = result.diagnostics["dt"]
    assert abs(first["t_start"] - t_gap) <= 1e-3 * dt, ((first["t_start"] - t_gap) / dt, dt)
    # before the contact the run follows the exact solution (the bearings stayed elastic)
    b = result.buildings["iso"]
    before = result.time < t_gap - 0.002
    u_exact = np.interp(result.time[before], np.arange(exact.shape[0]) * h, exact[:, 0])
    assert np.abs(b.displacement[before, 0, 0] - u_exact).max() < 1e-9 * GAP
    assert b.yielding.ductility.max() < 1


def test_moat_force_is_its_own_k_normal_times_area(moat_run):
    """F_N = k_N·A_c with the moat's k_N, at every stored sample in contact, and A_c = 6 m ×
    (u_b − gap), the slab's edge pressed into the wall's straight inner face (1e-9 of the
    area: the clipping of outlines ~6 m across, rounding only). The stored F_N is the force at
    t_n: the law's k_N·A_c at the stored state plus half of what the step adds to apply the
    force's average over its hat (contact.cell_correction, theory §10), which runs the state
    ahead of the law by (ω·Δt)²/24 of it (ω = √(k_N·6 m/36 t) = 289 rad/s): within 1e-5 of
    k_N·A_c (measured 2.5e-6; before the hat's correction it was k_N·A_c to rounding)."""
    _, stored = moat_run
    c = stored.contact
    pair = [str(b) for b in c.pairs["body_b"]].index("iso.moat2")
    assert c.pairs["k_normal"][pair] == K_MOAT
    touching = c.area[:, pair] > 0
    assert touching.sum() > 10
    np.testing.assert_allclose(c.normal_force[touching, pair], K_MOAT * c.area[touching, pair], rtol=1e-5)
    u_b = stored.buildings["iso"].displacement[touching, 0, 0]
    np.testing.assert_allclose(c.area[touching, pair], SIZE * (u_b - GAP), rtol=1e-9)
    assert not c.area[:, [k for k in range(c.pairs.size) if k != pair]].any()  # only the +x wall


# --- the moat and a neighbour in one run ---------------------------------------------------


def test_isolated_building_hits_its_moat_and_a_neighbour_in_one_run(tmp_path):
    """The base slab hits its moat wall and the floor above it the neighbour's floor at the same
    level; both pairs are in the impact log, each with its own k_N (the moat's, [contact]'s)."""
    joint = GAP + 0.004  # m: a little wider than the moat's gap (the floor swings on after the slab stops)
    neighbour = isolated("neighbour", (SIZE + joint, 0.0))
    del neighbour["isolation"]
    neighbour["floors"][0]["height"] = HEIGHT + 0.5  # level with the isolated building's floor
    moat = {"gap": GAP, "thickness": 0.5, "material": "concrete", "k_normal": K_MOAT}
    doc = model_doc([isolated(moat=moat), neighbour], duration=1.5, contact={"k_normal": 2e9})
    result = run_model(write(tmp_path, doc, pulse()), output=tmp_path / "out.h5")
    assert result.complete
    events = read_hdf5(tmp_path / "out.h5").contact.events
    kinds = {("moat" if str(e["body_b"]).startswith("iso.moat") else str(e["body_b"])) for e in events}
    assert kinds == {"moat", "neighbour"}, events
    c = result.contact
    for body, k_n in (("iso.moat2", K_MOAT), ("neighbour", 2e9)):
        pair = [str(b) for b in c.pairs["body_b"]].index(body)
        touching = c.area[:, pair] > 0
        assert touching.any(), body
        # the stored F_N: k_N·A_c plus half the step's hat correction (test_moat_force_is_its_own_k_normal_times_area)
        np.testing.assert_allclose(c.normal_force[touching, pair], k_n * c.area[touching, pair], rtol=1e-5)
