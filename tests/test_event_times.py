"""The impact log's times are located inside the contact step (issue 28): where the outlines
meet and part, where stick gives way and where a slip ends, against closed forms and against
runs at a far smaller step. Before, each was the first step after the event: up to a whole
step late."""

from __future__ import annotations

import numpy as np
import pytest

from pounding_cli.assembly.contact import restitution_damping_ratio
from pounding_cli.solver import contact as kernel
from pounding_cli.solver import simulate

from free_bodies import free_slabs, square
from test_contact import _face_to_face, run

WALL = np.array([[2.0, -50], [3.0, -50], [3.0, 50], [2.0, 50]])
"""A fixed wall along the +x face of a 4 m slab centred at the origin."""


@pytest.mark.parametrize("dt", [2e-5, 1e-5])
def test_touch_and_parting_are_located_inside_the_step(dt):
    """Two free 4 m slabs 1 mm apart closing at 1 m/s, no dashpot: they touch at 1 ms exactly,
    and the overlap law is the linear spring k_N·L·δ, so they part half a period π/ω later. The
    CDM's own half period of that spring would be π/ω_d, ω_d = (2/Δt)·arcsin(ω·Δt/2), shorter
    by (ω·Δt)²/24 of it (1.9e-3·Δt at Δt = 2e-5 s, 222 steps per impact: beyond issue 28's
    1e-3 of a step); the step's force is the spring's average over the step's hat
    (contact.cell_correction), which removes that phase error. The touch is located to
    rounding (1e-9·Δt; measured 1e-11·Δt) and the parting within 1e-4·Δt of the closed form
    (measured 2.4e-5·Δt at 2e-5 s and 5.8e-6·Δt at 1e-5 s: the parting's kink correction and
    the rebound are of higher order; before the hat's correction it sat on the CDM's π/ω_d,
    1.9e-3·Δt early)."""
    structure, contact, velocity = _face_to_face(None, gap=1e-3, v=0.5)
    r = run(structure, contact, velocity, duration=0.012, dt=dt, stride=int(round(1e-4 / dt)))
    assert r.events.shape[0] == 1
    event = r.events[0]
    omega = np.sqrt(1e9 * 4.0 / (structure.mass[0] / 2))  # k_N·L over the reduced mass
    touch = 1e-3 / 1.0
    assert abs(event[kernel.EV_T_START] - touch) <= 1e-9 * dt
    assert abs(event[kernel.EV_T_END] - (touch + np.pi / omega)) <= 1e-4 * dt


def _pulled_along_a_wall(dt):
    """A 4 m slab pressed on WALL by the body force m·5 m/s² and pulled along it by a force
    growing at m·10 m/s³ from 0.5 s (both through the ground acceleration), with a tangential
    dashpot that settles the stick oscillation; rotation held back (J × 10⁶), so that F_N and
    the total friction force follow the loads: stick gives way where the pull reaches μ_s·F_N,
    at 0.5 + 0.8·5/10 = 0.9 s."""
    slab = square(4.0, (0.0, 0.0))
    c_t = 2 * 0.7 * np.sqrt(1e9 * 16000)
    structure, contact = free_slabs([slab], obstacles=[WALL], k_n=1e9, k_t=1e9, mu_s=0.8, mu_k=0.6,
                                    zeta=restitution_damping_ratio(0.2), c_t=c_t)  # fmt: skip
    structure.mass[2] *= 1e6
    t = np.arange(0, 1.0, 1e-3)
    ground = np.column_stack([np.full_like(t, -5.0), -10.0 * np.clip(t - 0.5, 0, None)])
    return simulate(structure, ground, 1e-3, dt, round(1e-3 / dt), round(0.95 / dt), contact=contact).events


def test_stick_gives_way_where_the_pull_reaches_static_friction():
    """One episode from the start; its t_slip within 1e-3·Δt of a run at Δt/16 (measured
    7e-8·Δt: the excess of friction over μ_s·F_N is linear in time, so linear interpolation
    between two steps places it exactly), and within 5e-2·Δt of the closed form 0.9 s (measured
    3.0e-2·Δt = 6e-7 s, 1.5e-6 of the time since the pull began, and the same at Δt/16: it
    belongs to the run's response, which the closed form idealises, not to the location)."""
    dt = 2e-5
    coarse, fine = _pulled_along_a_wall(dt), _pulled_along_a_wall(dt / 16)
    assert coarse.shape[0] == fine.shape[0] == 1
    assert coarse[0, kernel.EV_SLIPS] == 1 and np.isnan(coarse[0, kernel.EV_T_STICK])
    t_slip = coarse[0, kernel.EV_T_SLIP]
    assert abs(t_slip - fine[0, kernel.EV_T_SLIP]) <= 1e-3 * dt
    assert abs(t_slip - 0.9) <= 5e-2 * dt


def _sliding_to_a_stop(dt):
    """A 4 m slab touching WALL at rest, pressed on it by the body force m·20 m/s² and sliding
    along it at 0.6 m/s: kinetic friction μ_k·F_N = 0.6·m·20 brakes it at 12 m/s² (F_N settles on
    m·20 within 10 ms), with a tangential dashpot c_T = 10⁶ N·s/m beside the spring k_T = 10⁸ N/m:
    the slider stops where the slab's velocity has fallen to the rate at which the spring–dashpot
    pair still stretches, shortly before the slab would stop (0.05 s) with a spring alone."""
    slab = square(4.0, (0.0, 0.0))
    structure, contact = free_slabs([slab], obstacles=[WALL], k_n=1e9, k_t=1e8, mu_s=0.8, mu_k=0.6,
                                    zeta=restitution_damping_ratio(0.2), c_t=1e6)  # fmt: skip
    structure.mass[2] *= 1e6
    t = np.arange(0, 0.2, 1e-3)
    ground = np.column_stack([np.full_like(t, -20.0), np.zeros_like(t)])
    return simulate(structure, ground, 1e-3, dt, round(1e-3 / dt), round(0.08 / dt), contact=contact,
                    initial_velocity=np.array([0.0, 0.6, 0.0])).events  # fmt: skip


def _slider_stops(mass=16000.0, turn_inertia=1e6 * 16000.0 * 32.0 / 12.0, k_n=4e9, c_t=1e6, k_t=1e8, mu_k=0.6):
    """When the slider of _sliding_to_a_stop stops (s), from scipy's integration (DOP853,
    rtol 1e-12) of the slab pressed on the wall, F_N = max(0, k_N·L·δ + c·δ̇) (L = 4 m: k_n is
    k_N·L; c from restitution 0.2), braked by μ_k·F_N at the face's midpoint, 2 m from its
    centre (so that it also turns, against J = 10⁶ × its polar moment, kg·m²), and the spring
    force S of the spring–dashpot pair, Ṡ = (μ_k·F_N − S)/τ, τ = c_T/k_T: the root of the
    slider's velocity v_T + 2·θ̇ − (μ_k·F_N − S)/c_T. (Without the turn, 2·θ̇ ≈ 9e-7 m/s at the
    stop, the root moves by 3.7e-3·Δt.)"""
    from scipy.integrate import solve_ivp

    c = 2.0 * restitution_damping_ratio(0.2) * np.sqrt(k_n * mass)

    def normal(x, vx):
        return max(0.0, k_n * x + c * vx)

    def rates(t, z):
        x, vx, vy, turn, spring = z
        friction = mu_k * normal(x, vx)
        return [vx, 20.0 - normal(x, vx) / mass, -friction / mass, -2.0 * friction / turn_inertia,
                (friction - spring) * k_t / c_t]  # fmt: skip

    def slider(t, z):
        return z[2] + 2.0 * z[3] - (mu_k * normal(z[0], z[1]) - z[4]) / c_t

    slider.terminal, slider.direction = True, -1
    solution = solve_ivp(rates, (0.0, 0.08), [0.0, 0.0, 0.6, 0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
                         events=slider, max_step=1e-4)  # fmt: skip
    return float(solution.t_events[0][0])


def test_a_slip_ends_where_the_slider_stops():
    """The slab slides from the touch (t_slip = t_start) and sticks once, where scipy's
    integration of the same spring–dashpot–slider has the slider stop (_slider_stops; the slab
    itself would stop 5.8·Δt later, at 0.05 s, the time a spring alone gives): t_stick within
    1.5e-3·Δt of it (measured 1.0e-3·Δt), and at Δt/2 within 0.3 of that error (measured 0.25,
    as at Δt/4 and Δt/8: second order; a run at Δt/32 is within 1.2e-6·Δt of scipy's root)."""
    dt = 2e-5
    stop = _slider_stops()
    coarse, finer = _sliding_to_a_stop(dt), _sliding_to_a_stop(dt / 2)
    assert coarse.shape[0] == finer.shape[0] == 1
    event = coarse[0]
    assert event[kernel.EV_SLIPS] == 1 and event[kernel.EV_T_SLIP] == event[kernel.EV_T_START]
    error = abs(event[kernel.EV_T_STICK] - stop)
    assert error <= 1.5e-3 * dt
    assert abs(finer[0, kernel.EV_T_STICK] - stop) <= 0.3 * error


def _closed_form(e: float, mass: float, k: float) -> tuple[float, float]:
    """(duration s, peak force N) of a no-tension spring k (N/m) and dashpot of restitution e
    (docs/theory.md §10) between two free bodies of `mass` (kg) each closing at 1 m/s: the
    dashpot pushes for t_s (ω_d·t_s = π − atan(2ζ√(1−ζ²)/(1 − 2ζ²))) and leaves the overlap
    x(t_s), which the bodies, now free, leave at e·1 m/s; the force k·x + c·ẋ at its crest."""
    from scipy.optimize import minimize_scalar

    zeta = restitution_damping_ratio(e) if e < 1.0 else 0.0
    mu = mass / 2
    omega = np.sqrt(k / mu)
    omega_d = omega * np.sqrt(1 - zeta**2)
    c = 2 * zeta * np.sqrt(k * mu)
    t_s = (np.pi - np.arctan2(2 * zeta * np.sqrt(1 - zeta**2), 1 - 2 * zeta**2)) / omega_d

    def x(t):
        return np.exp(-zeta * omega * t) * np.sin(omega_d * t) / omega_d

    def rate(t):
        return np.exp(-zeta * omega * t) * (np.cos(omega_d * t) - zeta * omega / omega_d * np.sin(omega_d * t))

    crest = minimize_scalar(lambda t: -(k * x(t) + c * rate(t)), bounds=(0.0, t_s), method="bounded",
                            options={"xatol": 1e-15})  # fmt: skip
    return t_s + x(t_s) / e, -crest.fun


@pytest.mark.parametrize("e", [1.0, 0.8])
def test_face_to_face_impacts_converge_at_higher_order(e):
    """Issue 28's convergence study: free slabs closing at 1 m/s from 1.0137 mm (the touch off
    the grid), without a dashpot and with that of restitution 0.8, at Δt = 4e-5 … 5e-6 s (55 to
    440 steps per impact), against the closed form (_closed_form). The issue measured first
    order (the error falling 1.98× per halving); with both ends located inside their steps it
    was second order (duration 3.3e-5 … 5.2e-7 without a dashpot, fitted 2.0; with e = 0.8
    duration, peak force and rebound 3.5e-5, 4.0e-5, 8.4e-5 at 4e-5 s, fitted 2.1, 2.0, 2.0).
    The step's force is now the law's average over the step's hat (contact.cell_correction):
    - without a dashpot, the duration falls from 8.0e-8 to 2.3e-10 (fitted order 2.9), the
      peak force and the rebound from 5.2e-8 and 4.1e-8 to 1e-11 (fitted 4.0 and 4.2);
    - with e = 0.8, the peak force and the rebound from 5.3e-7 and 7.6e-7 (fitted 2.9 and 2.9);
      the duration 6.0e-6, 1.5e-8, 3.6e-7, 6.0e-9 (fitted 2.5): where the dashpot's pull ends
      the force is located by the force's straight line over the step (theory §10), whose error
      depends on where that end falls in its step.
    Asserted: fitted orders ≥ 2.7, 3.5, 3.5 without a dashpot, ≥ 2.0, 2.6, 2.6 with it, and the
    errors at the coarsest step within 2e-7, 1e-7, 1e-7 and 1e-5, 1e-6, 1.5e-6."""
    steps = (4e-5, 2e-5, 1e-5, 5e-6)
    errors = []
    for dt in steps:
        structure, contact, velocity = _face_to_face(None if e == 1.0 else e, gap=1.0137e-3, v=0.5)
        r = run(structure, contact, velocity, duration=0.012, dt=dt, stride=int(round(1e-4 / dt)))
        assert r.events.shape[0] == 1
        event = r.events[0]
        duration, peak = _closed_form(e, structure.mass[0], 1e9 * 4.0)
        v = r.velocity.reshape(r.time.size, 2, 3)
        errors.append((abs((event[kernel.EV_T_END] - event[kernel.EV_T_START]) / duration - 1),
                       abs(event[kernel.EV_PEAK_FN] / peak - 1), abs((v[-1, 1, 0] - v[-1, 0, 0]) / e - 1)))  # fmt: skip
    errors = np.array(errors)
    least = (2.7, 3.5, 3.5) if e == 1.0 else (2.0, 2.6, 2.6)
    for j in range(3):
        order = np.polyfit(np.log(steps), np.log(errors[:, j]), 1)[0]
        assert order >= least[j], (j, order, errors[:, j])
    assert np.all(errors[0] <= ([2e-7, 1e-7, 1e-7] if e == 1.0 else [1e-5, 1e-6, 1.5e-6])), errors[0]
