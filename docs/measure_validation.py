"""Re-measure the figures quoted in docs/validation.md and docs/theory.md.

    python docs/measure_validation.py [time-histories] [geometry] [impacts] [events] [corner-friction]

(every section without arguments; a few minutes, most of it the geometry kernel's
hypothesis examples and the Kobe example). Uses the test suite's independent references
(tests/exact.py, shapely, the exact pounding solution of tests/test_pounding.py) on the same
cases the tests run, and prints what the tests assert against their tolerances.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import pounding_cli as pound  # noqa: E402
from pounding_cli.api import execute  # noqa: E402
from pounding_cli.assembly import assemble, ground_motion  # noqa: E402
from pounding_cli.bench.run import Setting, with_setting  # noqa: E402
from pounding_cli.solver import simulate  # noqa: E402
from pounding_cli.solver.tunables import AUTO_DT_FRACTION  # noqa: E402
from test_time_history import _eccentric_case, _exact_peaks  # noqa: E402


def peak_errors(result_peaks: np.ndarray, exact: np.ndarray) -> list[float]:
    """Largest relative error per component (x, y, θ) over significant entries."""
    out = []
    for k in range(3):
        sig = exact[:, :, k] > 1e-3 * exact[:, :, k].max()
        out.append(float((np.abs(result_peaks[:, :, k] - exact[:, :, k])[sig] / exact[:, :, k][sig]).max()))
    return out


def time_histories() -> None:
    """docs/validation.md, "Time histories"; theory §9."""
    loaded = _eccentric_case()
    system = assemble(loaded)
    ground = ground_motion(loaded)
    exact, _ = _exact_peaks(system.buildings[0], ground, substeps=20)
    print("peak interstorey deflection error against the exact solution (x, y, θ):")
    scene = pound.prepare(loaded)
    settings = [Setting(f"cdm, {f:g}·2/ω_max", "cdm", dt_fraction=f) for f in (0.2, 0.1, 0.05, 0.025)]
    for setting in settings + [Setting("hybrid (the default)", "hybrid")]:
        result = execute(with_setting(scene, setting))
        errs = peak_errors(result.buildings["b"].interstorey_deflection, exact)
        default = setting.integrator == "cdm" and setting.dt_fraction == AUTO_DT_FRACTION
        mark = "  <- the CDM's default step" if default else ""
        print(f"  {setting.name}, Δt = {result.diagnostics['dt'] * 1e3:.3f} ms: "
              + ", ".join(f"{100 * e:.4f} %" for e in errs)
              + f"; energy balance {result.balance_error_ratio:.2e}{mark}")

    fine, _ = _exact_peaks(system.buildings[0], ground, substeps=200)
    result = execute(with_setting(scene, Setting("hybrid (the default)", "hybrid")))
    errs = peak_errors(result.buildings["b"].interstorey_deflection, fine)
    print("  hybrid (the default) against the exact solution sampled every 0.05 ms: "
          + ", ".join(f"{e:.2e}" for e in errs))

    _, u_exact = _exact_peaks(system.buildings[0], ground, substeps=4)
    reference = u_exact[:4001:4]
    steps, errors = [], []
    for per_output in (8, 16, 32, 64):
        r = simulate(system, ground.acceleration, ground.dt, 0.01 / per_output, per_output, per_output * 1000)
        errors.append(np.abs(r.displacement - reference).max())
        steps.append(0.01 / per_output)
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    print(f"CDM convergence: max displacement error {', '.join(f'{e:.3g}' for e in errors)} m "
          f"at Δt = 1.25, 0.625, 0.3125, 0.156 ms; slope {slope:.4f}")

    example = pound.describe(ROOT / "inputs" / "paper_wide_gap.toml")
    for b in example["buildings"]:
        print(f"{b['name']}: periods " + ", ".join(f"{t:.4f}" for t in b["periods_s"]) + " s")


def geometry() -> None:
    """docs/validation.md, "Contact geometry": every hypothesis example of
    tests/test_contact_geometry.py (the same examples: the tests' functions run unchanged,
    only check_frame is watched), the worst area and centroid errors against the reference
    check_frame uses (shapely, or exact rational arithmetic where shapely fails), and the
    normal's turn per step against its bound."""
    import shapely
    from hypothesis.statistics import collector

    import test_contact_geometry as tcg
    from pounding_cli.solver.contact_geometry import AREA, CX, CY

    worst: dict[str, list[float]] = {}
    checked = tcg.check_frame

    def watched(a, b, ref_a=None, ref_b=None, label=""):
        ok, r = checked(a, b, ref_a, ref_b, label)
        if ok:
            a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
            inter = shapely.intersection(shapely.Polygon(a), shapely.Polygon(b))
            big = max(np.abs(a).max(), np.abs(b).max())
            area, centre, perimeter = inter.area, (inter.centroid.x, inter.centroid.y), inter.length
            if not abs(r[AREA] - area) <= 1e-9 * area + 4 * tcg.EPS * big * perimeter:
                area, cx, cy, perimeter = tcg.exact_overlap(a, b)  # shapely failed: as check_frame does
                centre = (cx, cy)
            rounding = 4 * tcg.EPS * big * perimeter  # the rounding term of the tolerance
            error = abs(r[AREA] - area)
            w = worst.setdefault(label.split(",")[0], [0, 0.0, 0.0, 0.0])
            w[0] += 1
            if 1e-9 * area >= rounding:  # an overlap thick enough for 1e-9 relative to apply alone
                w[1] = max(w[1], error / area)
            w[2] = max(w[2], error / (1e-9 * area + rounding))
            size = max(np.ptp(a, axis=0).max(), np.ptp(b, axis=0).max())
            diameter = float(np.hypot(*np.subtract(*np.reshape(inter.bounds, (2, 2))))) if area else size
            allowed = 1e-9 * size + rounding * diameter / area  # check_frame's centroid tolerance
            if np.hypot(*(r[CX : CY + 1] - centre)) > allowed:  # as check_frame: exact arithmetic decides
                centre = tcg.exact_overlap(a, b)[1:3]
            w[3] = max(w[3], float(np.hypot(*(r[CX : CY + 1] - centre))) / allowed)
        return ok, r

    counts: dict[str, int] = {}

    def count(name):
        def note(stats):
            for phase in stats.values():
                if isinstance(phase, dict):
                    counts[name] = counts.get(name, 0) + sum(c["status"] == "valid" for c in phase.get("test-cases", []))
        return note

    tcg.check_frame = watched
    try:
        for name in sorted(n for n in dir(tcg) if n.startswith("test_") and hasattr(getattr(tcg, n), "hypothesis")):
            with collector.with_value(count(name)):
                getattr(tcg, name)()
    finally:
        tcg.check_frame = checked
    for name, n in counts.items():
        print(f"  {name}: {n} examples")
    print(f"hypothesis examples: {sum(counts.values())} in all, every one passing")
    print("overlaps found (both ways round where a test swaps), worst area error relative to the area where")
    print("1e-9·A exceeds the rounding term, worst error as a fraction of the tolerance, worst centroid error as a")
    print("fraction of its tolerance:")
    for label, (n, relative, of_tolerance, centroid) in worst.items():
        print(f"  {label}: {n} overlaps; area {relative:.2g} relative, {of_tolerance:.2g} of the tolerance; "
              f"centroid {centroid:.2g} of the tolerance")
    thick = max(w[1] for w in worst.values())
    print(f"worst relative area error over all families: {thick:.2g}; as a fraction of the tolerance: "
          f"{max(w[2] for w in worst.values()):.2g}")
    for angle in (3.0, 8.0, 30.0):
        rows = [row for row in tcg.drive(angle) if row[5]]
        ratio = max(tcg.angle_between(n0, n1) / (2 * step / (min(l0, l1) * np.sin(np.radians(angle))))
                    for (_, _, n0, l0, _, _), (_, _, n1, l1, step, _) in zip(rows, rows[1:]))  # fmt: skip
        print(f"normal turn per step at {angle:g}°: largest {ratio:.2f} of the bound 2Δs/(|P1P2| sin φ)")
    rows = [row for row in tcg.drive(45.0) if row[5]]
    ratio = max(tcg.angle_between(n0, n1) / (2 * step / (min(l0, l1) * np.sin(np.pi / 4)))
                for (_, _, n0, l0, _, _), (_, _, n1, l1, step, _) in zip(rows, rows[1:]))  # fmt: skip
    print(f"normal turn per step at 45° (four crossings): largest {ratio:.2f} of the two-crossing bound (allowed: 4)")


def impacts() -> None:
    """docs/validation.md, "Impact model"; theory §10 ("Is the contact conservative?")."""
    import tempfile

    import test_contact as tc
    import test_contact_work as tw
    import test_pounding as tp
    import test_pounding_cli as tpc
    from conftest import INPUTS, SHARED, load_doc
    from pounding_cli.assembly.contact import impact_stiffness, restitution_damping_ratio, restitution_of
    from pounding_cli.model import Material, read_document, validate_model
    from pounding_cli.solver import contact as kernel
    from free_bodies import contact_force, momenta

    concrete = Material(elastic_modulus=21e9, poisson_ratio=0.2)
    k_n, k_t = impact_stiffness(concrete, concrete)
    print(f"impact stiffness: k_N = {k_n / 1e3:.3g} kN/m², k_T = {k_t / 1e3:.3g} kN/m")
    es = (0.95, 0.8, 0.65, 0.5, 0.3, 0.15)
    print("restitution → damping ratio → restitution: worst "
          f"{max(abs(restitution_of(restitution_damping_ratio(e)) - e) / e for e in es):.1g} relative")

    for e in (1.0, 0.8, 0.5):
        gaps = (1e-3, 1.0137e-3, 1.0071e-3)
        coarse = max(abs(tc._rebound(e, 2e-5, g) - e) for g in gaps)
        fine = max(abs(tc._rebound(e, 5e-6, g) - e) for g in gaps)
        print(f"free slabs face to face, e = {e:g}, three gaps: rebound within {coarse:.1e} of v0 at 2e-5 s, "
              f"{fine:.1e} at 5e-6 s (falls by {coarse / fine:.1f})")
    with tempfile.TemporaryDirectory() as tmp:
        for e in (0.8, 0.5):
            folder = Path(tmp) / f"e{e:g}"
            folder.mkdir()
            measured, duration, _ = tpc._rebound(folder, {"restitution": e})
            expected = tpc._episode_time(restitution_damping_ratio(e), e)
            print(f"model file, floor against a wall, restitution = {e:g}: rebound {measured:.5f} "
                  f"({measured / e - 1:+.1e}); episode {1e3 * duration:.5f} ms, closed form {1e3 * expected:.5f} ms "
                  f"({(duration - expected) / tpc.DT:+.3f} steps)")

    for mu in ((0.0, 0.0), (0.8, 0.6)):
        structure, contact, velocity = tc._oblique(*mu)
        r = tc.run(structure, contact, velocity, duration=0.25)
        p = momenta(structure, r.displacement.reshape(-1, 2, 3), r.velocity.reshape(-1, 2, 3))
        drift = np.abs(p - p[0]).max() / np.abs(p[0]).max()
        print(f"oblique corner impact, μ = {mu[0]:g}/{mu[1]:g}: momenta conserved to {drift:.1e} of the initial")
    structure, contact, velocity = tc._oblique(0.0, 0.0)
    structure.mass[2::3] *= 1e6
    velocity[2::3] = 0.0
    r = tc.run(structure, contact, velocity, duration=0.25)
    e_k = r.energy[:, 1]
    print(f"the same, frictionless, rotation held back: kinetic energy {e_k[-1] / e_k[0] - 1:+.1e}, "
          f"balance {np.abs(r.energy[:, 6]).max() / e_k[0]:.1e}")
    gains = []
    for dt in (2e-5, 5e-6):
        structure, contact, velocity = tc._oblique(0.0, 0.0)
        r = tc.run(structure, contact, velocity, duration=0.25, dt=dt, stride=int(round(2e-4 / dt)))
        e_k = r.energy[:, 1]
        gains.append(e_k[-1] / e_k[0] - 1)
        print(f"the same, free to spin, Δt = {dt:g} s: kinetic energy {100 * gains[-1]:+.3f} %, "
              f"balance {np.abs(r.energy[:, 6]).max() / e_k[0]:.1e}")
    print(f"  gain at Δt and Δt/4 differ by {abs(gains[0] - gains[1]):.1e}")

    for scene in (tw._corner_into_face, tw._narrow_face):
        structure, contact, q = scene()
        forces = tw._kernel(structure, contact)
        work, side = tw._loop_work(forces, q - [0, 0, 0, 0.002, 0.002, 0], 3, 4, 0.004)
        print(f"curl of the kernel's forces, {scene.__name__[1:]} at θ = 0: {tw._curl(forces, q)[0]:.1e} of ∂Q; "
              f"4 mm loop in (x, y): {abs(work) / side:.1e} of a side's work")
    structure, contact, q0 = tw._corner_into_face()
    exact = tw.TurnedExactly(structure, contact)
    for theta in (0.01, 0.02, 0.1):
        q = q0.copy()
        q[2], q[5] = theta, -theta
        tw._press(lambda x: contact_force(structure, contact, x)[1][0, kernel.NOW_DEPTH], q, 0.01)
        small = tw._curl(tw._kernel(structure, contact), q)[0]
        q = q0.copy()
        q[2], q[5] = theta, -theta
        tw._press(exact.depth, q, 0.01)
        print(f"corner into a face turned ±{theta:g} rad: curl {small:.3g} (small-rotation outlines), "
              f"{tw._curl(exact, q)[0]:.1e} (exactly turned)")
    for scene in (tw._corners_in_each_other, tw._faces_offset):
        structure, contact, q = scene()
        forces = tw._kernel(structure, contact)
        work, side = tw._loop_work(forces, q, 3, 4, 0.004)
        print(f"{scene.__name__[1:]}: curl {tw._curl(forces, q)[0]:.2g} of ∂Q; 4 mm loop in (x, y) does "
              f"{abs(work) / side:.1e} of a side's work")
    structure, contact, velocity = tc._oblique(0.0, 0.0)
    r = tc.run(structure, contact, velocity, duration=0.25, dt=2e-5, stride=1)
    e_k = r.energy[:, 1]
    on = np.flatnonzero(r.contact[:, 0, kernel.NOW_AREA] > 0)
    u = r.displacement
    exact = tw.TurnedExactly(structure, contact)
    path = range(on[0] - 100, on[-1] + 100)
    work_kernel = sum(contact_force(structure, contact, u[n])[0] @ (u[n + 1] - u[n - 1]) / 2 for n in path)
    work_exact = sum(exact(u[n]) @ (u[n + 1] - u[n - 1]) / 2 for n in path)
    print(f"spinning corner impact, along its path: kinetic energy {(e_k[-1] - e_k[0]) / e_k[0]:+.4e}, work of the "
          f"kernel's forces {work_kernel / e_k[0]:+.4e}, of the law on exactly turned outlines "
          f"{work_exact / e_k[0]:+.1e}; largest turn {np.abs(u[on][:, [2, 5]]).max():.3f} rad")

    slab = tc.square(4.0, (0.0, 0.0), angle_deg=10.0)
    lead = slab[np.argmax(slab[:, 0])]
    wall = np.array([[lead[0] + 1e-3, -10], [lead[0] + 1.0, -10], [lead[0] + 1.0, 10], [lead[0] + 1e-3, 10]])
    structure, contact = tc.free_slabs([slab], obstacles=[wall], k_n=1e9)
    r = tc.run(structure, contact, np.array([1.0, 0.0, 0.0]), duration=0.05)
    print(f"corner-first impact on a wall: θ' = {r.velocity[-1, 2]:+.3g} rad/s, v_x = {r.velocity[-1, 0]:+.3g} m/s; "
          f"action point at the peak {1e3 * (r.events[0, kernel.EV_X] - lead[0] - 1e-3):+.1f} mm from the wall face, "
          f"{1e3 * (r.events[0, kernel.EV_Y] - lead[1]):+.1f} mm along it from the corner")

    g0, rate, mu_s, mu_k, t_pull = tc.STICK_SLIP
    r, structure = tc._stick_slip()
    fn, ft = r.contact[:, 0, kernel.NOW_FN], r.contact[:, 0, kernel.NOW_FT]
    m = structure.mass[0]
    t_slip = t_pull + mu_s * g0 / rate
    sticking = (r.time > t_pull + 0.08) & (r.time < t_slip - 0.02)
    pull = m * rate * (r.time[sticking] - t_pull)
    moving = r.time[(r.time > t_pull) & (np.abs(r.velocity[:, 1]) > 1e-2)]
    sliding = r.time > t_slip + 0.01
    i0 = np.searchsorted(r.time, t_slip + 0.01)
    power = ft[i0:] * r.velocity[i0:, 1]
    work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(r.time[i0:])))
    absorbed = r.energy[-1, 5] - r.energy[i0, 5]
    print(f"stick-slip: F_T = pull within {np.abs(ft[sticking] / pull - 1).max():.1e} while sticking "
          f"(|F_T| ≤ {np.abs(ft[sticking] / (mu_s * fn[sticking])).max():.2f}·μ_s·F_N); slip {1e3 * (moving[0] - t_slip):+.1f} ms "
          f"from pull = μ_s·F_N; sliding |F_T|/F_N = μ_k within {np.abs(np.abs(ft[sliding]) / fn[sliding] / mu_k - 1).max():.1e}; "
          f"contact energy = friction work within {abs(absorbed / work - 1):.1e}")
    r, episodes = tc._bouncing_along_a_wall()
    print(f"tangential reset: {len(episodes) + 1} episodes; each ends sliding with |F_T| = "
          f"{min(abs(e[0]) for e in episodes) / 1e3:.1f}–{max(abs(e[0]) for e in episodes) / 1e3:.1f} kN, and the next "
          f"starts at k_T·Δu_T of its first step within {max(abs(e[2] / e[3] - 1) for e in episodes):.1e} "
          f"({min(abs(e[2]) for e in episodes):.0f}–{max(abs(e[2]) for e in episodes):.0f} N)")

    for integrator in ("cdm", "hybrid"):
        doc = tp._face_to_face_doc()
        doc["analysis"]["integrator"] = integrator
        loaded = load_doc(doc)
        result = pound.run_model(loaded)
        k_contact = result.contact.pairs["k_normal"][0] * 8.0
        t, y, starts, peak_force = tp._cached_reference(loaded, k_contact)
        events = result.contact.events
        d = result.diagnostics
        print(f"face to face, {integrator} (Δt = {d['dt']:.3g} s): {len(events)} impacts, reference {len(starts)}; "
              f"start times within {np.abs(events['t_start'] - starts).max() / d['dt']:.2g}·Δt; peak forces within "
              f"{np.abs(events['peak_normal_force'] / peak_force - 1).max():.1e}")
        for name, column in (("left", 0), ("right", 1)):
            exact = np.abs(y[:, column]).max()
            line = f"  {name}: peak displacement {result.buildings[name].peak_displacement[0, 0] / exact - 1:+.2e}"
            if integrator == "hybrid":
                from scipy.interpolate import CubicSpline

                h = d["substep"]
                sampled = np.abs(CubicSpline(t, y[:, column])(np.arange(0.0, t[-1], h))).max()
                line += f" (the reference sampled every h = {1e3 * h:.3g} ms: {sampled / exact - 1:+.2e})"
            print(line)

    a = tp.square_building("a", eccentricity=(0.4, 0.3), storeys=2)
    b = tp.square_building("b", origin=(8.005, 0.5), eccentricity=(-0.2, 0.0), section=(0.45, 0.45), storeys=2)
    doc = tp.model_doc(a, b, components=["L"], duration=16.0)
    r1, r2 = pound.run_model(load_doc(doc)), pound.run_model(load_doc(tp._mirrored(doc)))
    worst = 0.0
    for name in ("a", "b"):
        u1, u2 = r1.buildings[name].displacement, r2.buildings[name].displacement
        scale = np.abs(u1[:, :, :2]).max()
        worst = max(worst, np.abs(u2 * [-1, 1, -1] - u1)[:, :, :2].max() / scale,
                    np.abs(u2[:, :, 2] + u1[:, :, 2]).max() * 8 / scale)  # fmt: skip
    print(f"mirrored scene: {r1.contact.impact_count} = {r2.contact.impact_count} impacts; histories mirror to "
          f"{worst:.1e} of the peak")

    for name in ("paper_wide_gap", "paper_pounding", "paper_kobe"):
        path = INPUTS / f"{name}.toml"
        if "shared/records" in path.read_text() and not SHARED.exists():
            print(f"{name}: skipped (its record in ../shared is absent)")
            continue
        line = []
        for integrator in ("hybrid", "cdm"):
            doc = read_document(path)
            doc.setdefault("analysis", {})["integrator"] = integrator
            r = pound.run_model(validate_model(doc, path))
            line.append(f"{integrator} {r.balance_error_ratio:.2g}")
        print(f"{name}: energy balance error {', '.join(line)} of the input ({r.contact.impact_count} impacts)")


def event_times() -> None:
    """docs/validation.md, "Impact model": the impact log's times located inside the step
    (theory §10, "Events inside the step"), as tests/test_event_times.py checks them."""
    import test_event_times as te
    from pounding_cli.solver import contact as kernel

    for dt in (2e-5, 1e-5):
        structure, contact, velocity = te._face_to_face(None, gap=1e-3, v=0.5)
        event = te.run(structure, contact, velocity, duration=0.012, dt=dt, stride=int(round(1e-4 / dt))).events[0]
        omega = np.sqrt(1e9 * 4.0 / (structure.mass[0] / 2))
        omega_cdm = 2.0 / dt * np.arcsin(omega * dt / 2)
        print(f"face to face, Δt = {dt:g} s: t_start − 1 ms = {(event[kernel.EV_T_START] - 1e-3) / dt:+.1e}·Δt; "
              f"t_end − (1 ms + π/ω_d) = {(event[kernel.EV_T_END] - 1e-3 - np.pi / omega_cdm) / dt:+.1e}·Δt, "
              f"− (1 ms + π/ω) = {(event[kernel.EV_T_END] - 1e-3 - np.pi / omega) / dt:+.1e}·Δt")
    dt = 2e-5
    coarse, fine = te._pulled_along_a_wall(dt), te._pulled_along_a_wall(dt / 16)
    print(f"pulled along a wall: t_slip − run at Δt/16 = {(coarse[0, kernel.EV_T_SLIP] - fine[0, kernel.EV_T_SLIP]) / dt:+.1e}·Δt, "
          f"− 0.9 s = {(coarse[0, kernel.EV_T_SLIP] - 0.9) / dt:+.1e}·Δt")
    coarse, fine = te._sliding_to_a_stop(dt), te._sliding_to_a_stop(dt / 32)
    print(f"sliding to a stop: t_stick − run at Δt/32 = {(coarse[0, kernel.EV_T_STICK] - fine[0, kernel.EV_T_STICK]) / dt:+.1e}·Δt, "
          f"− 0.05 s = {(coarse[0, kernel.EV_T_STICK] - 0.05) / dt:+.1e}·Δt")


def corner_friction() -> None:
    """docs/validation.md, "Impact model": the spinning corner impact with friction converging
    (theory §10, "The slip at the step's midpoint"), as tests/test_contact.py runs it."""
    from test_contact import corner_friction_errors

    steps = (2e-5, 1e-5, 5e-6, 2.5e-6)
    for mu in ((0.6, 0.6), (0.8, 0.6)):
        errors = corner_friction_errors(*mu, steps)
        orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
        print(f"corner with friction μ_s = {mu[0]}, μ_k = {mu[1]}: largest velocity errors "
              f"{', '.join(f'{e:.2g}' for e in errors)} m/s at Δt = {', '.join(f'{s:g}' for s in steps)} s "
              f"(orders {', '.join(f'{o:.2f}' for o in orders)})")


SECTIONS = {"time-histories": time_histories, "geometry": geometry, "impacts": impacts, "events": event_times,
            "corner-friction": corner_friction}


def main() -> None:
    chosen = sys.argv[1:] or list(SECTIONS)
    unknown = [name for name in chosen if name not in SECTIONS]
    if unknown:
        sys.exit(f"unknown section {unknown[0]!r}; choose from {', '.join(SECTIONS)}")
    for name in chosen:
        print(f"== {name}", flush=True)
        SECTIONS[name]()


if __name__ == "__main__":
    main()
