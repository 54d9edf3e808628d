"""The overlap-area impact model: stiffness from materials, restitution, momentum and energy
of free slabs, friction, corner impacts, and the impact log."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pounding_cli.assembly.contact import (
    impact_stiffness,
    restitution_damping_ratio,
    restitution_of,
)
from pounding_cli.model import Material
from pounding_cli.solver import contact as kernel
from pounding_cli.solver import simulate

from free_bodies import free_slabs, momenta, square


def run(structure, contact, velocity, duration, dt=2e-5, stride=10, ground=None):
    n = int(round(duration / dt / stride)) * stride
    ground = np.zeros((2, 2)) if ground is None else ground
    return simulate(structure, ground[0], ground[1], dt, stride, n, contact=contact, initial_velocity=velocity) \
        if isinstance(ground, tuple) else \
        simulate(structure, ground, 1.0, dt, stride, n, contact=contact, initial_velocity=velocity)


def test_impact_stiffness_reproduces_the_papers_values():
    """E = 21 GPa, ν = 0.2: k_N = 2.06×10⁷ kN/m², k_T = 4.59×10⁶ kN/m (paper §6, 3 digits)."""
    concrete = Material(elastic_modulus=21e9, poisson_ratio=0.2)
    k_n, k_t = impact_stiffness(concrete, concrete)
    assert f"{k_n / 1e3:.3g}" == "2.06e+07"
    assert f"{k_t / 1e3:.3g}" == "4.59e+06"


def test_restitution_damping_ratio_inverts_the_closed_form():
    for e in (0.95, 0.8, 0.65, 0.5, 0.3, 0.15):
        assert_allclose(restitution_of(restitution_damping_ratio(e)), e, rtol=1e-12)
    # light damping: the no-tension correction vanishes and the classical formula holds
    e = 0.995
    assert_allclose(restitution_damping_ratio(e), -np.log(e) / np.sqrt(np.pi**2 + np.log(e) ** 2), rtol=2e-2)


def _face_to_face(e=None, gap=1e-3, v=0.5, angle_deg=0.0, mu=(0.0, 0.0), v_slide=0.0):
    """Two 4 m slabs a gap apart face to face, B turned by angle_deg, closing at 2v (and sliding
    past each other at 2·v_slide), with the dashpot of restitution e (none if None)."""
    a = square(4.0, (0.0, 0.0))
    b = square(4.0, (4.0 + gap, 0.0), angle_deg=angle_deg)
    zeta = restitution_damping_ratio(e) if e is not None else 0.0
    structure, contact = free_slabs([a, b], k_n=1e9, mu_s=mu[0], mu_k=mu[1], zeta=zeta)
    velocity = np.array([v, v_slide, 0, -v, -v_slide, 0])
    return structure, contact, velocity


def _rebound(e, dt, gap=1e-3):
    structure, contact, velocity = _face_to_face(None if e == 1.0 else e, gap)
    r = run(structure, contact, velocity, duration=0.03, dt=dt, stride=int(round(1e-4 / dt)))
    assert r.events.shape[0] == 1, "one impact"
    v = r.velocity.reshape(r.time.size, 2, 3)
    p = momenta(structure, r.displacement.reshape(-1, 2, 3), v)
    assert_allclose(p[:, 0], 0.0, atol=1e-9 * 16000)
    assert np.abs(v[:, :, 1:]).max() < 1e-12, "a central impact moves nothing sideways"
    return v[-1, 1, 0] - v[-1, 0, 0]  # relative speed after separation; it was 1 m/s before


@pytest.mark.parametrize("e", [1.0, 0.8, 0.5])
def test_face_to_face_rebound_has_the_given_restitution(e):
    """Equal-width slabs meeting face to face: the overlap force is a linear spring k_N·L·δ,
    so the dashpot derived from e must give back e·v₀. Touches on the grid (gap 1 mm, 50
    steps of 2e-5 s) and off it (1.0137 mm, 1.0071 mm). The dashpot's force jumps to c_N·v₀ at
    the touch (weighted by s + ½ at the first step), and the force's slope jumps at the touch
    and where the force falls to zero (the kink impulses, theory §10), so the rebound converges
    at second order in Δt with an error that does not depend on where the touch falls: at
    Δt = 2e-5 s (ω·Δt = 0.014, 220 steps per contact) within (ω·Δt)²/4 = 5e-5 of e (measured
    3.5e-5, the dashpot's velocity estimate), falling by more than 12 from 2e-5 to 5e-6 s
    (second order gives 16; measured 16). Without the kink impulses the error was up to 1.2e-5
    at e = 1, its sign set by where the touch fell in its step. Without a dashpot the CDM's
    leapfrog gives the speed back exactly but for the kinks, so e = 1 is met within
    (ω·Δt)⁴ = 3.8e-8 (measured 4.7e-9). Where the touch falls no longer matters: the three
    gaps' rebounds agree within (ω·Δt)³ = 2.7e-6 (measured 9.3e-9, 5.8e-8, 2.2e-7; without
    the impulse where the dashpot's pull ends the force, 1.2e-5 at e = 0.5)."""
    gaps = (1e-3, 1.0137e-3, 1.0071e-3)
    signed = [_rebound(e, 2e-5, g) - e for g in gaps]
    coarse = [abs(x) for x in signed]
    fine = [abs(_rebound(e, 5e-6, g) - e) for g in gaps]
    assert max(coarse) < (3.8e-8 if e == 1.0 else 5e-5)
    assert max(fine) < max(coarse) / 12
    assert max(signed) - min(signed) < 2.7e-6


def test_peak_force_is_the_crest_wherever_it_falls():
    """Slabs meeting face to face without a dashpot: the force is a linear spring k_N·L·δ, so
    its crest is m_eff·ω·v₀ (m_eff = 8 t, ω = √(k_N·L/m_eff) = 707 rad/s, closing at 1 m/s),
    at t = gap/v₀ + π/(2ω). The largest sample misses it by up to (ω·Δt)²/8 = 2.5e-5 at
    Δt = 2e-5 s, by an amount set by where the crest falls in its step (measured up to 1.8e-5
    over these four gaps); the parabola through the three steps around it (contact.crest) is
    within 1e-8 wherever it falls (measured 2.7e-9, of the force at t_n the histories carry:
    the law's plus half the step's hat correction, contact.cell_correction; of the law's value
    alone, 1.8e-7). The logged time is the largest sample's, within half a step of the crest's."""
    m_eff, v0 = 8000.0, 1.0
    omega = np.sqrt(1e9 * 4.0 / m_eff)
    dt = 2e-5
    for gap in (1e-3, 1.0137e-3, 1.0071e-3, 1.0031e-3):
        structure, contact, velocity = _face_to_face(None, gap)
        r = run(structure, contact, velocity, duration=0.01, dt=dt, stride=5)
        (event,) = r.events
        assert event[kernel.EV_PEAK_FN] == pytest.approx(m_eff * omega * v0, rel=1e-8), gap
        assert abs(event[kernel.EV_T_PEAK] - (gap / v0 + np.pi / (2 * omega))) <= 0.5 * dt * (1 + 1e-3), gap


def _oblique(mu_s, mu_k):
    a = square(4.0, (0.0, 0.0))
    b = square(4.0, (4.9, 1.2), angle_deg=30.0)  # its left corner 7 cm from A's face
    structure, contact = free_slabs([a, b], k_n=1e9, k_t=1e8, mu_s=mu_s, mu_k=mu_k)
    velocity = np.array([2.0, 0.3, 0.1, -1.0, 0.0, -0.2])
    return structure, contact, velocity


@pytest.mark.parametrize("mu", [(0.0, 0.0), (0.8, 0.6)], ids=["frictionless", "friction"])
def test_oblique_impact_conserves_momentum(mu):
    """Equal and opposite forces at one point: linear momentum is conserved to rounding, and
    angular momentum too (the leapfrog's half-step momenta telescope exactly; see
    docs/theory.md). 1e-8 of the initial momentum leaves room for 10⁴ steps of rounding."""
    structure, contact, velocity = _oblique(*mu)
    r = run(structure, contact, velocity, duration=0.25)
    assert r.events.shape[0] >= 1
    p = momenta(structure, r.displacement.reshape(-1, 2, 3), r.velocity.reshape(-1, 2, 3))
    scale = np.abs(p[0]).max()
    assert_allclose(p, np.broadcast_to(p[0], p.shape), rtol=0, atol=1e-8 * scale)
    if mu[0] > 0:
        assert r.events[0, kernel.EV_SLID] == 1.0, "the corner slides along the face"


def test_frictionless_oblique_impact_without_spin_keeps_kinetic_energy():
    """Without friction and dashpots, and with the slabs' rotation held back (J × 10⁶), the
    overlap-area force is the gradient of k_N·∫A dδ (∇A ⟂ P1P2, |∇A| = |P1P2|): the contact
    stores and returns energy, and kinetic energy after separation equals that before within
    0.1 % (the CDM's error here is ~1e-5)."""
    structure, contact, velocity = _oblique(0.0, 0.0)
    structure.mass[2::3] *= 1e6
    velocity[2::3] = 0.0
    r = run(structure, contact, velocity, duration=0.25)
    assert r.events.shape[0] == 1 and np.isfinite(r.events[0, kernel.EV_T_END])
    e_k = r.energy[:, 1]
    assert_allclose(e_k[-1], e_k[0], rtol=1e-3)
    assert np.abs(r.energy[:, 6]).max() < 1e-3 * e_k[0], "energy balance"


def test_frictionless_spinning_corner_impact_keeps_kinetic_energy():
    """With rotation free (the slabs turn by up to 0.03 rad each while in contact), without
    friction or dashpots, the slabs leave with the kinetic energy they brought: the issue asks
    0.1 %; the kernel moves the outlines rigidly, so the overlap-area force at the centroid is
    conservative for this corner-into-face contact (tests/test_contact_work.py, theory §10),
    and what remains is the CDM's error, which falls with Δt at second order (measured 1.9e-9
    at 2e-5 s, 1.2e-10 at 5e-6 s: the kinks summed at the tips make each step's force the
    cell's average, no longer the gradient of a potential sampled at t_n, which gave 1.4e-11
    and 1.2e-13); 1e-8 is five times the larger. The energy balance closes to 1e-6."""
    for dt in (2e-5, 5e-6):
        structure, contact, velocity = _oblique(0.0, 0.0)
        r = run(structure, contact, velocity, duration=0.25, dt=dt, stride=int(round(2e-4 / dt)))
        assert r.events.shape[0] == 1 and np.isfinite(r.events[0, kernel.EV_T_END])
        e_k = r.energy[:, 1]
        assert abs(e_k[-1] / e_k[0] - 1.0) < 1e-8, dt
        assert np.abs(r.energy[:, 6]).max() < 1e-6 * e_k[0], "energy balance"
        assert np.abs(r.displacement.reshape(-1, 2, 3)[:, :, 2]).max() > 0.01, "the slabs turn"


def corner_friction_errors(mu_s, mu_k, steps=(2e-5, 5e-6)):
    """The spinning corner impact (_oblique) with friction: at each step in `steps`, the
    slabs' largest velocity error over 0.2 s (sampled every ms), m/s, against a run at
    2e-5/256 s (its own error, at second order, ~1e-11 m/s). The velocity after the impact
    alone is a poor measure: the error built up in contact partly cancels as the contact ends,
    by an amount that jumps with the step."""
    reference = None
    errors = []
    for dt in (2e-5 / 256, *steps):
        structure, contact, velocity = _oblique(mu_s, mu_k)
        r = run(structure, contact, velocity, duration=0.2, dt=dt, stride=int(round(1e-3 / dt)))
        assert r.events.shape[0] == 1 and r.events[0, kernel.EV_SLID] == 1.0, "one episode, which slips"
        if reference is None:
            reference = r.velocity
            continue
        errors.append(np.abs(r.velocity - reference).max())
    return errors


@pytest.mark.parametrize("mu", [(0.6, 0.6), (0.8, 0.6)], ids=["mu_s=mu_k", "mu_s>mu_k"])
def test_oblique_corner_friction_converges_at_second_order(mu):
    """The spinning corner impact with friction, at Δt = 2e-5 and 5e-6 s: it slips from the
    touch, sticks while F_T turns over, and slips again as F_N falls. The stuck spring sums
    each step's slip; taken with the action point, mass centres and tangent at t_n instead of
    the step's midpoint it erred by O(Δt²) a step, first order in all (1.9e-6 → 4.7e-7 m/s over
    4× the step, order 1.0). With the midpoint slip: 4.6e-7 → 2.9e-8 m/s, order 2.00 for both
    friction laws (`python docs/measure_validation.py corner-friction`). 1.8 rules first order
    out with room for the episode's events inside the step."""
    errors = corner_friction_errors(*mu)
    order = np.log2(errors[0] / errors[1]) / 2.0
    assert order >= 1.8, errors


def test_corner_first_impact_turns_the_slab_the_right_way():
    """A slab turned 10° moving +x hits a wall with its lowest-right corner first: the push
    −F_x at that corner, below the centre, turns the slab clockwise (θ' < 0)."""
    slab = square(4.0, (0.0, 0.0), angle_deg=10.0)
    lead = slab[np.argmax(slab[:, 0])]
    wall = np.array([[lead[0] + 1e-3, -10], [lead[0] + 1.0, -10], [lead[0] + 1.0, 10], [lead[0] + 1e-3, 10]])
    structure, contact = free_slabs([slab], obstacles=[wall], k_n=1e9)
    r = run(structure, contact, np.array([1.0, 0.0, 0.0]), duration=0.05)
    assert r.events.shape[0] >= 1
    assert lead[1] < 0
    assert r.velocity[-1, 2] < 0, "clockwise"
    assert r.velocity[-1, 0] < 0, "bounced back"
    # the action point of the peak is at the corner, on the wall face (the overlap triangle's
    # centroid lies a third of the penetration inside the wall)
    assert_allclose(r.events[0, kernel.EV_X], lead[0] + 1e-3, atol=1e-2)
    assert_allclose(r.events[0, kernel.EV_Y], lead[1], atol=0.05)


STICK_SLIP = (5.0, 10.0, 0.8, 0.6, 0.5)
"""g₀ (m/s²), pull rate r (m/s³), μ_s, μ_k, the pull's start (s) of _stick_slip."""


def _stick_slip():
    """(response, structure): a 4 m slab pressed on a wall by the body force m·g₀ and pulled
    along it by a force growing at m·r from t_pull (both through the ground acceleration)."""
    g0, rate, mu_s, mu_k, t_pull = STICK_SLIP
    slab = square(4.0, (0.0, 0.0))
    wall = np.array([[2.0, -50], [3.0, -50], [3.0, 50], [2.0, 50]])
    c_t = 2 * 0.7 * np.sqrt(1e9 * 16000)  # tangential dashpot: settles the stick oscillation
    structure, contact = free_slabs([slab], obstacles=[wall], k_n=1e9, k_t=1e9, mu_s=mu_s, mu_k=mu_k,
                                    zeta=restitution_damping_ratio(0.2), c_t=c_t)  # fmt: skip
    dt_g = 1e-3
    t = np.arange(0, 1.3, dt_g)
    ground = np.column_stack([np.full_like(t, -g0), -rate * np.clip(t - t_pull, 0, None)])
    return simulate(structure, ground, dt_g, 2e-5, 50, 65_000, contact=contact), structure


def test_stick_then_slip_at_static_then_kinetic_friction():
    """A slab pressed on a wall by a steady body force m·g₀ (through the ground acceleration)
    is pulled along the wall by a force growing at m·r: it sticks (friction carries the
    pull, below μ_s·F_N), slips when the pull reaches μ_s·m·g₀, then slides at
    F_T = μ_k·F_N, and the contact absorbs the work of friction.

    Friction acts at the wall face, off the slab's centre, so its couple rocks the slab a
    little and moves the overlap's centroid: F_T follows the pull within 1 % while sticking,
    and F_N varies while sliding — the checks use the forces the run reports."""
    g0, rate, mu_s, mu_k, t_pull = STICK_SLIP
    r, structure = _stick_slip()
    fn, ft = r.contact[:, 0, kernel.NOW_FN], r.contact[:, 0, kernel.NOW_FT]
    m = structure.mass[0]
    settled = (r.time > 0.3) & (r.time < t_pull)
    assert_allclose(fn[settled], m * g0, rtol=1e-3)
    t_slip = t_pull + mu_s * g0 / rate
    sticking = (r.time > t_pull + 0.08) & (r.time < t_slip - 0.02)
    # on the wall (body B) friction acts along +t = +y, as the pull does on the slab
    assert_allclose(ft[sticking], m * rate * (r.time[sticking] - t_pull), rtol=1e-2)
    assert (np.abs(ft[sticking]) < mu_s * fn[sticking]).all()
    assert np.abs(r.displacement[sticking, 1]).max() < 1e-3, "no sliding while sticking"
    # slip starts within one output interval of where the pull reaches μ_s·F_N
    moving = r.time[(r.time > t_pull) & (np.abs(r.velocity[:, 1]) > 1e-2)]
    assert abs(moving[0] - t_slip) < 0.015
    sliding = r.time > t_slip + 0.01
    assert_allclose(np.abs(ft[sliding]) / fn[sliding], mu_k, rtol=1e-9)
    # what friction dissipates while sliding, ∫ F_T·v_y dt, is what the contact absorbs
    i0 = np.searchsorted(r.time, t_slip + 0.01)
    power = ft[i0:] * r.velocity[i0:, 1]
    work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(r.time[i0:])))
    e_contact = r.energy[:, 5]
    assert_allclose(e_contact[-1] - e_contact[i0], work, rtol=1e-2)
    assert np.abs(r.energy[:, 6]).max() < 1e-3 * e_contact[-1], "energy balance"


def _shaken_along_a_wall(dt, c_t=0.0):
    """A 4 m slab pressed on a wall by the body force m·20 m/s² and shaken along it by
    25 m/s²·sin(2π·5 Hz·t) (μ_s·20 = 16 < 25 and μ_k·20 = 12: it sticks and slips in turn),
    for 0.5 s at step dt, output every 1 ms, with a tangential dashpot c_t (N·s/m). Rotation
    held back (J × 10⁶)."""
    slab = square(4.0, (0.0, 0.0))
    wall = np.array([[2.0, -50], [3.0, -50], [3.0, 50], [2.0, 50]])
    structure, contact = free_slabs([slab], obstacles=[wall], k_n=1e9, k_t=1e8, mu_s=0.8, mu_k=0.6, zeta=0.2,
                                    c_t=c_t)  # fmt: skip
    structure.mass[2] *= 1e6
    t = np.arange(0, 0.501, 1e-3)
    ground = np.column_stack([np.full_like(t, -20.0), -25.0 * np.sin(2 * np.pi * 5 * t)])
    return simulate(structure, ground, 1e-3, dt, round(1e-3 / dt), round(0.5 / dt), contact=contact)


@pytest.mark.parametrize("c_t", [0.0, 5e4, 5e5, 2e6])
def test_stick_slip_converges_at_second_order(c_t):
    """Where stick gives way, F_T drops from μ_s·F_N to μ_k·F_N inside a step; the kernel
    gives that step's force the impulse of the drop where it happened (_kinetic_shortfall).
    Switching at the step's end instead misplaces an impulse (μ_s − μ_k)·F_N·Δt at every
    break-away, a first-order error. Against a run at Δt/128, the sliding displacement's
    largest error from Δt = 1e-4 to 6.25e-6 s, without a tangential dashpot and with one
    beside the spring, 2 %, 20 % and 79 % of the critical 2√(k_T·m) (docs/theory.md, "The
    tangential dashpot": the spring relaxes while the contact slips, exactly over the part of
    the step the slip took): it falls by more than 32 over the four halvings, twice what first
    order gives (16; second gives 256: measured 250, 270, 100, 460, the third at the reference's
    own error, 4e-9 m, from 1.25e-5 s on; with the drop at the step's end, order 1.4 and 30×
    larger errors), and is within 2e-5 of the 5 cm amplitude at the coarsest step (measured
    4.5e-7, 7.8e-7, 4.5e-7, 6.4e-7 m: 0.9–1.6e-5 of it; 2.2e-6 m
    without a dashpot and up to 2.6e-6 m with one before the step's force became the hat's
    average, contact.cell_correction). Without a dashpot, the fitted order ≥ 1.8 (measured
    2.0); with one, the finer errors reach the reference's own (4e-9 m) and a fit means less."""
    reference = _shaken_along_a_wall(1e-4 / 128, c_t)
    fn, ft = (reference.contact[:, 0, k] for k in (kernel.NOW_FN, kernel.NOW_FT))
    slipping = np.isclose(np.abs(ft), 0.6 * fn, rtol=1e-9) & (fn > 0)
    assert np.count_nonzero(slipping[1:] & ~slipping[:-1]) >= 4, "several break-aways"
    amplitude = np.abs(reference.displacement[:, 1]).max()
    steps = 1e-4 / 2.0 ** np.arange(5)
    errors = [np.abs(_shaken_along_a_wall(dt, c_t).displacement[:, 1] - reference.displacement[:, 1]).max()
              for dt in steps]  # fmt: skip
    assert errors[0] > 32 * errors[-1], errors
    if c_t == 0.0:
        order = np.polyfit(np.log(steps), np.log(errors), 1)[0]
        assert order >= 1.8, f"order {order:.2f}, errors {errors}"
    assert errors[0] < 2e-5 * amplitude


def test_impact_log_keeps_the_contact_force_at_the_peak():
    """The oblique corner impact with friction (it slides), output at every step: each logged
    episode's F_T at the peak is the F_T of the contact histories at t_peak, bit for bit (the
    same number, stored twice), within Coulomb's bound |F_T| ≤ μ_s·F_N; its peak F_N is the
    crest of the parabola through the histories' F_N at t_peak and the steps either side (to
    rounding, 1e-12), at or above the sample there; and its normal is the
    one shapely gives for the displaced outlines at that step — perpendicular to the line
    through the points where they cross — to 1e-9 (the clipping and shapely's intersection
    agree to rounding of coordinates of order 10 m)."""
    from pounding_cli.report.plan import contact_normal

    mu_s, mu_k = 0.8, 0.6
    structure, contact, velocity = _oblique(mu_s, mu_k)
    r = run(structure, contact, velocity, duration=0.25, stride=1)
    assert r.events.shape[0] >= 1
    slabs = contact.body_poly[:2]
    centres = structure.floor_centre
    for event in r.events:
        k = int(np.flatnonzero(r.time == event[kernel.EV_T_PEAK])[0])
        f_n, f_t = r.contact[k, 0, kernel.NOW_FN], r.contact[k, 0, kernel.NOW_FT]
        assert event[kernel.EV_FT_PEAK] == f_t
        f0, f2 = r.contact[k - 1, 0, kernel.NOW_FN], r.contact[k + 1, 0, kernel.NOW_FN]
        parabola = np.polyfit([-1.0, 0.0, 1.0], [f0, f_n, f2], 2)
        top = np.polyval(parabola, -parabola[1] / (2 * parabola[0])) if f0 > 0 and f2 > 0 else f_n
        assert event[kernel.EV_PEAK_FN] == pytest.approx(top, rel=1e-12) and event[kernel.EV_PEAK_FN] >= f_n
        assert abs(f_t) <= mu_s * f_n
        u = r.displacement[k].reshape(2, 3)
        turn = [np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]) for t in u[:, 2]]
        moved = [centres[i] + u[i, :2] + (p - centres[i]) @ turn[i].T for i, p in enumerate(slabs)]  # rigidly
        assert_allclose([event[kernel.EV_NX], event[kernel.EV_NY]], contact_normal(*moved), atol=1e-9)
    peak = r.events[np.argmax(r.events[:, kernel.EV_PEAK_FN])]
    assert r.events[0, kernel.EV_SLID] == 1.0 and abs(peak[kernel.EV_FT_PEAK]) > 0.05 * peak[kernel.EV_PEAK_FN], \
        "friction carries a real share of the force at the peak"


def test_tangential_state_resets_between_contact_episodes():
    """A slab held against a wall by a steady body force, sliding along it: it bounces, flies
    and lands again, so the one pair has several episodes. Each ends sliding, its friction
    spring at μ_k·F_N of the last step (kN); each new episode must start from F_T = 0, so its
    first step carries exactly the spring's increment over the part of the step spent in
    contact, s·k_T·Δu_T (B, the wall, is fixed: Δu_T = −(slab's slip at the action point) =
    −(Δu_y + Δθ·(c_x − G_x)); s = penetration now / (gap a step ago + penetration now), both
    measured from the slab's foremost corner), to rounding (1e-9), not the last episode's force
    on top of it. Rotation held back (J × 10⁶) keeps the action point on the wall face."""
    r, episodes = _bouncing_along_a_wall()
    assert len(episodes) >= 2 and r.events.shape[0] == len(episodes) + 1, "episodes of one pair"
    assert (r.events[:, kernel.EV_SLID] == 1).all()
    for leftover, fn_end, first, increment, fn_first in episodes:
        assert_allclose(abs(leftover), 0.6 * fn_end, rtol=1e-9)  # sliding to the end
        assert abs(leftover) > 1e3, "the last episode ends with a friction force of kN"
        assert_allclose(first, increment, rtol=1e-9)
        assert abs(first) < 0.8 * fn_first, "it sticks in its first step"


def _bouncing_along_a_wall(k_t=1e8):
    """(response, one row per episode after the first: F_T and F_N at the last step of the
    episode before, F_T at its own first step, the spring's increment s·k_T·Δu_T of that step,
    F_N then), N, for test_tangential_state_resets_between_contact_episodes."""
    slab = square(4.0, (0.0, 0.0))
    face = 2.002  # the wall's face, m
    wall = np.array([[face, -50], [3.0, -50], [3.0, 50], [face, 50]])
    structure, contact = free_slabs([slab], obstacles=[wall], k_n=1e9, k_t=k_t, mu_s=0.8, mu_k=0.6)
    structure.mass[2] *= 1e6
    t = np.arange(0, 0.2, 1e-3)
    ground = np.column_stack([np.full_like(t, -20.0), np.zeros_like(t)])  # pushes the slab (+x) to the wall
    r = simulate(structure, ground, 1e-3, 2e-5, 1, 8000, contact=contact, initial_velocity=np.array([0.5, 0.3, 0.0]))
    fn, ft, cx = (r.contact[:, 0, k] for k in (kernel.NOW_FN, kernel.NOW_FT, kernel.NOW_X))
    on = r.contact[:, 0, kernel.NOW_AREA] > 0
    first = np.flatnonzero(on[1:] & ~on[:-1]) + 1
    last = np.flatnonzero(~on[1:] & on[:-1])
    u = r.displacement
    reach = u[:, 0] + 2.0 * np.cos(u[:, 2]) + 2.0 * np.abs(np.sin(u[:, 2]))  # the slab's largest x, m
    rows = []
    for end, start in zip(last, first[1:]):
        g_x = structure.floor_centre[0, 0] + u[start, 0]
        slip = (u[start, 1] - u[start - 1, 1]) + (u[start, 2] - u[start - 1, 2]) * (cx[start] - g_x)
        depth, gap = reach[start] - face, face - reach[start - 1]
        rows.append((ft[end], fn[end], ft[start], k_t * slip * depth / (gap + depth), fn[start]))
    return r, rows


def _turned_rebound(angle_deg, dt, gap=1e-3, mu=(0.0, 0.0), v_slide=0.0):
    """Velocities (2, 3) after the slabs of _face_to_face meet, without a dashpot."""
    structure, contact, velocity = _face_to_face(None, gap, angle_deg=angle_deg, mu=mu, v_slide=v_slide)
    r = run(structure, contact, velocity, duration=0.03, dt=dt, stride=max(1, int(round(1e-4 / dt))))
    assert r.events.shape[0] == 1, "one impact"
    return r.velocity[-1].reshape(2, 3)


GAPS = (1e-3, 1.0137e-3, 1.0071e-3, 1.0033e-3)  # touches on the grid of 2e-5 s and off it


@pytest.mark.parametrize("angle", [5e-5, 3e-4], ids=["L·θ = 0.17 of a step's closing", "L·θ = 1.0 of it"])
def test_faces_turned_slightly_rebound_wherever_the_touch_falls(angle):
    """Faces meeting turned by θ ≈ 1–5 µrad (the Kobe example's): the depth tapers along the
    4 m line by L·θ, here 0.17 and 1.0 times the 2e-5 m a step of 2e-5 s closes, so the line
    touches and parts within one or two steps, and the taper's couple k_N·L³·θ/12 switches on
    and off with it. The kinks are integrated point by point along the line (theory §10): at
    ω·Δt = 0.014 the rebound speed is within (ω·Δt)⁴ = 4e-8 of a run at 2.5e-8 s (measured
    3e-9; taking the line as one kink of slope k_N·L₀ it was up to 4e-6, its sign following
    where the touch fell) and the spin the impact gives within (ω·Δt)² = 2e-4 of itself
    (measured 1.6e-5; with the couple a whole cell on or off, up to 2.8e-3)."""
    ref = _turned_rebound(angle, 2.5e-8)
    spin = abs(ref[1, 2] - ref[0, 2])
    assert spin > 1e-4, "the taper's couple turns the slabs"
    for gap in GAPS:
        got = _turned_rebound(angle, 2e-5, gap)
        rebound = (got[1, 0] - got[0, 0]) - (ref[1, 0] - ref[0, 0])
        assert abs(rebound) < 4e-8, gap
        assert abs((got[1, 2] - got[0, 2]) - (ref[1, 2] - ref[0, 2])) < 2e-4 * spin, gap


def test_sliding_faces_take_the_friction_impulse_wherever_the_touch_falls():
    """Faces meeting parallel while sliding past each other (2 × 0.05 m/s; μ_s = 0.8,
    μ_k = 0.6, k_T = 1e8 N/m): the contact sticks, and within its last step or two the stick
    gives way and the friction fades with the normal force. The jump to μ_k·F_N is sized with
    F_N where it happened and the friction's end is integrated with the normal force's, so
    the sideways speed the impact takes off (Δv = 5.6e-3 m/s) is within (ω·Δt)²·Δv = 1.1e-6
    m/s of a run at 2.5e-8 s, wherever the touch falls (measured 3.7e-8; with the jump sized
    at the step's end and the end left to the cells, up to 4.3e-6)."""
    mu = (0.8, 0.6)
    ref = _turned_rebound(0.0, 2.5e-8, mu=mu, v_slide=0.05)
    taken = 0.05 - ref[0, 1]
    assert 4e-3 < taken < 8e-3
    for gap in GAPS:
        got = _turned_rebound(0.0, 2e-5, gap, mu=mu, v_slide=0.05)
        assert abs(got[0, 1] - ref[0, 1]) < 2e-4 * taken, gap
