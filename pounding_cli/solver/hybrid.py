"""The hybrid integrator: exact propagation while no contact is possible, the central
difference method (CDM) around impacts.

While every pair of bodies is apart by more than it can close within the horizon, the
buildings are linear and uncoupled, and each substep h (a divisor of the record's sample
interval) is taken exactly by the state-transition matrices of propagator.py, with the
exact work of the ground and the damping over it: no time-step error; the peaks between
two exact states are exact too (peaks.py: located by the quintic through them, valued on
the motion's Taylor series). Where nothing can touch or yield within 4h, no output or
record sample falls inside and the peaks' search reaches over 2h (ω_max·2h ≤
peaks.CREST_SPAN), two substeps are taken as one (Φ of 2h): the substep grid, on which the
approach below starts, is unchanged. When a contact may begin within 2h (bounding
boxes widened by what velocity and acceleration can add), the exact propagation goes on in
steps of h/2, h/4, … h/2^L (the approach levels), halving while the outlines could touch
within two steps (contact.contact_ruled_out_within), and hands the state to the CDM of
cdm.py at the contact time step Δt = h/sub only at the finest level; the CDM hands it back
at the first h/2^L at which every pair is out of contact and cannot touch within 4·h/2^L.

Yielding members need the CDM too (their stiffness changes), but not the contact's step:
when a member may yield within 2h and no contact is possible, the CDM runs at the yielding
step h/sub_y (the structure's own fraction of its stability limit, often 10–50× the contact
step); it hands the state back at a substep boundary when a contact may begin within 2h (to
re-enter at the contact step) or when no member can yield within 4h. A change of step goes
through the exact state at the boundary: the two hand-overs below, back to back.

Hand-over (both second-order consistent):
- exact → CDM at t_k: v_{k−½} = v_k − (Δt/2)·a_k, with a_k from the equation of motion
  (no contact force: none is possible yet); C·v_{k−½} and K·u_k from the storey kernel.
- CDM → exact at t_n: v_n = v_{n−½} + Δv_n/2, Δv_n from one more CDM residual (no contact).
Energy keeps one account across both: each hand-over closes the interval it ends and marks
the instant as counted; exact steps add their exact work (propagate: the ground's and the
damping's over the step, from the same matrix exponentials as the step itself), the CDM
integrates the powers by the trapezoidal rule.
"""

from __future__ import annotations

from .cdm import (
    ACC_DAMPING,
    ACC_FRESH,
    ACC_INPUT,
    ACC_HYSTERETIC,
    ACC_STEP_DAMPING,
    ACC_STEP_INPUT,
    STATUS_DIVERGED,
    STATUS_OK,
    accumulate_energy,
    advance,
    damping_force,
    ground_at,
    solve_blocks,
    storey_matvec,
    storey_matvec_pair,
    write_output,
)
from .broad_phase import BR_N_LIVE
from .contact import contact_possible_within, contact_ruled_out_within
from .hysteresis import member_states, plastic_correction, plastic_energy_terms, update_members, yield_possible_within
from .jit import REASSOCIATE, kernel
from .peaks import peaks_between, settle_crests, update_peaks

# exact (substeps of h); CDM at the contact step; CDM at the yielding step; exact in finer steps
# toward a contact that may begin within the substep
MODE_EXACT, MODE_CDM, MODE_CDM_YIELD, MODE_APPROACH = 0, 1, 2, 3
ENTER_HORIZON = 2.0  # substeps ahead a contact must be ruled out to stay exact
LEAVE_HORIZON = 4.0  # substeps ahead it must be ruled out to leave the CDM
# counters: exact steps (substeps and the approach's shorter ones), CDM steps, hand-overs, the
# step (in CDM steps) whose state failed the divergence check (−1 while none has), and the
# time propagated exactly, in CDM steps
CNT_EXACT, CNT_CDM, CNT_SWITCHES, CNT_FAILED_STEP, CNT_EXACT_SPAN = range(5)
N_COUNTERS = 5
N_RATES = 7  # rows of exact_point's `rates`


@kernel
def exact_state(t, u, v, ku, kv, cv, a_abs, a_rel, mass, damping, storey_k, bottom, top,
                ground, ground_dt, g):  # fmt: skip
    """K·u, C·v and the accelerations (absolute and relative) at time t from the state (u, v)
    and the members' plastic correction g. Returns the ground acceleration (X, Y) at t."""
    agx, agy = ground_at(t, ground, ground_dt)
    n_dof = mass.size
    storey_matvec_pair(u, v, storey_k, bottom, top, ku, kv)
    damping_force(v, kv, mass, damping, n_dof, cv)
    for d in range(n_dof):
        a_abs[d] = -(ku[d] - g[d] + cv[d]) / mass[d]
    for d in range(0, n_dof, 3):
        a_rel[d] = a_abs[d] - agx
        a_rel[d + 1] = a_abs[d + 1] - agy
        a_rel[d + 2] = a_abs[d + 2]
    return agx, agy


@kernel
def exact_point(t, gap, u, v, ku, kv, cv, a_abs, a_rel, mass, damping, storey_k, bottom, top, ground, ground_dt,
                g, acc, storey_axes, centre, col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp,
                peak_acc, kept, between, first, rates, crest_work):  # fmt: skip
    """Everything the exact propagation owes the state (u, v) it reached at t: forces and
    accelerations (exact_state), the energy account over the `gap` s since the last state
    accounted for (over an exact step, the work propagate left in acc[ACC_STEP_INPUT] and
    acc[ACC_STEP_DAMPING], exact; else trapezoidal), the peaks. When that last state was the
    previous exact point (an open account: no hand-over since), the peaks include those of
    the step between (peaks_between, from what kept and between hold of that state; first:
    the storeys' first columns); for the accelerations' it needs their first two rates:
    ȧ = −M⁻¹(K·v + C·a_rel) (the ground's own rate drops out: a_abs depends on u and v
    alone), left in rates[2], and
    ä = −M⁻¹(K·a_rel + C·ȧ_rel) with ȧ_rel = ȧ − ȧ_g, whose part without the ground's rate ȧ_g
    is left in rates[3] (rates[0], rates[1], rates[4]: K·a_rel, C·a_rel, C·ȧ; rates[5],
    rates[6] hold M⁻¹·C·e_X and M⁻¹·C·e_Y, e the floors' unit translations, which carry the
    rest: integrate.ground_rate_response). The crests peaks_between lists are valued
    exactly (settle_crests) from the motion's derivatives at t (state_series); crest_work =
    (floor_ratio, crests, series, series_k, coef): the share of a running peak a quintic crest
    must pass to be listed, and the work arrays of both. Returns the ground acceleration (X, Y)
    at t."""
    smooth = gap > 0.0 and acc[ACC_FRESH] == 0.0
    agx, agy = exact_state(t, u, v, ku, kv, cv, a_abs, a_rel, mass, damping, storey_k, bottom, top, ground,
                           ground_dt, g)  # fmt: skip
    n_dof = mass.size
    storey_matvec(a_rel, storey_k, bottom, top, rates[0])
    damping_force(a_rel, rates[0], mass, damping, n_dof, rates[1])
    for d in range(n_dof):
        rates[2, d] = -(kv[d] + rates[1, d]) / mass[d]
    storey_matvec(rates[2], storey_k, bottom, top, rates[3])
    damping_force(rates[2], rates[3], mass, damping, n_dof, rates[4])
    for d in range(n_dof):
        rates[3, d] = -(rates[0, d] + rates[4, d]) / mass[d]
    # the ground acceleration's rate over the step (linear within it: steps never cross a
    # record sample), which the peaks' second derivatives of the accelerations need
    a0x = a0y = sx = sy = 0.0
    if smooth:
        a0x, a0y = ground_at(t - gap, ground, ground_dt)
        sx = (agx - a0x) / gap
        sy = (agy - a0y) / gap
    p_in = 0.0
    p_damp = 0.0
    for d in range(0, n_dof, 3):
        p_in -= mass[d] * (agx * v[d] + agy * v[d + 1])
    for d in range(n_dof):
        p_damp += v[d] * cv[d]
    if smooth:  # the exact step's own work (propagate), then the powers for a later trapezoid
        acc[ACC_INPUT] += acc[ACC_STEP_INPUT]
        acc[ACC_DAMPING] += acc[ACC_STEP_DAMPING]
        accumulate_energy(acc, 0.0, p_in, p_damp, 0.0)
    else:
        accumulate_energy(acc, gap, p_in, p_damp, 0.0)
    update_peaks(u, a_abs, n_dof, bottom, top, storey_axes, centre, col_storey, col_arm, storey_work, peak_col,
                 peak_rot, peak_disp, peak_acc)  # fmt: skip
    floor_ratio, crests, series, series_k, coef = crest_work
    n_crests = peaks_between(gap, smooth, u, v, a_rel, a_abs, rates, sx, sy, n_dof, bottom, top, storey_axes, centre,
                             col_arm, first, storey_work, kept, between, peak_col, peak_rot, peak_disp, peak_acc,
                             floor_ratio, crests)  # fmt: skip
    if n_crests > 0:
        state_series(u, v, a_rel, sx, sy, mass, damping, storey_k, bottom, top, series, series_k)
        settle_crests(gap, crests, n_crests, series, agx, agy, sx, sy, bottom, top, storey_axes, centre, col_storey,
                      col_arm, coef, peak_col, peak_rot, peak_disp, peak_acc)  # fmt: skip
    return agx, agy


@kernel
def state_series(u, v, a_rel, sx, sy, mass, damping, storey_k, bottom, top, series, series_k):
    """The exact motion's derivatives at a state reached by exact propagation: series[j] =
    u⁽ʲ⁾ for j = 0 … R − 1 (R = series.shape[0]), from u, v, a_rel and the ground acceleration's
    rate (sx, sy) m/s³ over the step: u⁽ʲ⁺²⁾ = −M⁻¹(K·u⁽ʲ⁾ + C·u⁽ʲ⁺¹⁾) − ι·a_g⁽ʲ⁾ for j ≥ 1,
    where a_g⁽ʲ⁾ is the rate for j = 1 and 0 after (a_g is linear within the step; the members'
    plastic correction is constant and drops out). series_k: work (2, n_dof + 3)."""
    n_dof = mass.size
    for d in range(n_dof):
        series[0, d] = u[d]
        series[1, d] = v[d]
        series[2, d] = a_rel[d]
    storey_matvec(series[1], storey_k, bottom, top, series_k[1])
    for j in range(1, series.shape[0] - 2):
        # series_k[(j + 1) % 2] = K·u⁽ʲ⁺¹⁾; series_k[j % 2] holds K·u⁽ʲ⁾ from the last order
        storey_matvec(series[j + 1], storey_k, bottom, top, series_k[(j + 1) % 2])
        damping_force(series[j + 1], series_k[(j + 1) % 2], mass, damping, n_dof, series[j + 2])
        for d in range(n_dof):
            series[j + 2, d] = -(series_k[j % 2, d] + series[j + 2, d]) / mass[d]
        for d in range(n_dof, series.shape[1]):  # the ground's row (damping links may write it)
            series[j + 2, d] = 0.0
        if j == 1:
            for d in range(0, n_dof, 3):
                series[3, d] -= sx
                series[3, d + 1] -= sy


@kernel(fastmath=REASSOCIATE)
def propagate(t, h, u, v, phi, g0, g1, mean_rows, damping_form, dof_start, dof_count, mass, ground, ground_dt, x, y,
              acc):  # fmt: skip
    """(u, v) at t + h from (u, v) at t, exactly, building by building, and the exact work
    over the step of the ground, into acc[ACC_STEP_INPUT], and of the damping, into
    acc[ACC_STEP_DAMPING], J (propagator.py: from z₀ = (u, v, a₀, Δa), the mean rows r and the
    damping form G of each building). x (2·n_max + 4), y (2·n_max): scratch."""
    a0x, a0y = ground_at(t, ground, ground_dt)
    a1x, a1y = ground_at(t + h, ground, ground_dt)
    dx = a1x - a0x
    dy = a1y - a0y
    w_in = 0.0
    w_damp = 0.0
    for b in range(dof_start.size):
        d0 = dof_start[b]
        n = dof_count[b]
        for i in range(n):
            x[i] = u[d0 + i]
            x[n + i] = v[d0 + i]
        x[2 * n] = a0x
        x[2 * n + 1] = a0y
        x[2 * n + 2] = dx
        x[2 * n + 3] = dy
        # the damping's work z₀ᵀ·G·z₀ (G symmetric: the upper triangle, twice) and the means
        # S̄ of the mass-weighted translations over the step
        mean_x = 0.0
        mean_y = 0.0
        for i in range(2 * n + 4):
            row = 0.5 * damping_form[b, i, i] * x[i]
            for j in range(i + 1, 2 * n + 4):
                row += damping_form[b, i, j] * x[j]
            w_damp += 2.0 * x[i] * row
            mean_x += mean_rows[b, 0, i] * x[i]
            mean_y += mean_rows[b, 1, i] * x[i]
        s0x = 0.0
        s0y = 0.0
        for i in range(0, n, 3):
            s0x += mass[d0 + i] * x[i]
            s0y += mass[d0 + i + 1] * x[i + 1]
        for i in range(2 * n):
            acc_i = g0[b, i, 0] * a0x + g0[b, i, 1] * a0y + g1[b, i, 0] * dx + g1[b, i, 1] * dy
            for j in range(2 * n):
                acc_i += phi[b, i, j] * x[j]
            y[i] = acc_i
        s1x = 0.0
        s1y = 0.0
        for i in range(0, n, 3):
            s1x += mass[d0 + i] * y[i]
            s1y += mass[d0 + i + 1] * y[i + 1]
        w_in -= a0x * (s1x - s0x) + dx * (s1x - mean_x) + a0y * (s1y - s0y) + dy * (s1y - mean_y)
        for i in range(n):
            u[d0 + i] = y[i]
            v[d0 + i] = y[n + i]
    acc[ACC_STEP_INPUT] = w_in
    acc[ACC_STEP_DAMPING] = w_damp


@kernel
def propagate_elastic(t, h, u, v, phi, g0, g1, mean_rows, damping_form, dof_start, dof_count, mass, ground, ground_dt,
                      x, y, acc, has_members, u_static):  # fmt: skip
    """propagate() about the static offset u_static of the members' plastic deflections (the
    work is the same: the offset is constant)."""
    if has_members:
        for d in range(u_static.size):
            u[d] -= u_static[d]
    propagate(t, h, u, v, phi, g0, g1, mean_rows, damping_form, dof_start, dof_count, mass, ground, ground_dt, x, y,
              acc)  # fmt: skip
    if has_members:
        for d in range(u_static.size):
            u[d] += u_static[d]


@kernel
def _enter_cdm(step, u, v_exact, a_rel, v_half, dv, storey_k, bottom, top, z, mass, damping, cv_half, acc):
    """Hand the exact state at an instant already accounted for to the CDM at `step`:
    v_{−½} = v − (Δt/2)·a (no contact force: none is possible yet), C·v_{−½}."""
    n_dof = mass.size
    for d in range(n_dof):
        v_half[d] = v_exact[d] - 0.5 * step * a_rel[d]
        dv[d] = step * a_rel[d]
    storey_matvec(v_half, storey_k, bottom, top, z)
    damping_force(v_half, z, mass, damping, n_dof, cv_half)
    acc[ACC_FRESH] = 1.0  # the instant is already integrated


@kernel
def hybrid_advance(
    k_start, k_stop, k_end, h, sub, sub_y, binv_y, stride_h, u_limit,
    # exact propagation: Φ, Γ₀, Γ₁, the mean rows and damping forms of the work per level
    # (level j: steps of h/2^j; propagator.building_propagators); kinv: K⁻¹ blocks,
    # u_static: K⁻¹·g while the members stay elastic; gap: the last exact step, s; kept, between,
    # first: what peaks_between keeps of the last exact state, and the storeys' first columns;
    # rates: exact_point's work (N_RATES, n_dof + 3; integrate.ground_rate_response); phi2, g02,
    # g12, mean2, form2: the same of a double substep 2h (none, for no building: no double
    # substeps, as their ω_max·2h would pass peaks.CREST_SPAN); crest_work: exact_point's
    phi, g0, g1, mean_rows, damping_form, v_exact, kv, a_rel, xbuf, ybuf, mode, counters, kinv, u_static, gap, kept,
    between, first, rates, phi2, g02, g12, mean2, form2, crest_work,
    # everything cdm.advance takes after its first five arguments
    mass, damping, storey_k, storey_bottom, storey_top, binv, dof_start, dof_count,
    ground, ground_dt, storey_axes, centre, col_storey, col_arm,
    u, v_half, ku, cv_half, acc,
    peak_col, peak_rot, peak_disp, peak_acc,
    out_u, out_v, out_a, out_ground, out_energy, out_contact,
    r, dv, v, a_abs, z, cv_next, storey_work,
    geometry, params, pair_state, pair_now, events, n_events, fc, v_est, cbuf, broad,
    members, plastic, g, out_member, peak_member,
):  # fmt: skip
    """Advance substeps k_start … k_stop − 1 of length h; returns (status, substeps done). A
    displacement that passes u_limit or is not finite stops the run at the substep (or the CDM
    step) that made it: STATUS_DIVERGED, with that step (in CDM steps at the contact step)
    in counters[CNT_FAILED_STEP]. At k = k_end, the end of the analysis, only the state at t_k
    is taken (output, peaks): nothing is integrated past it.
    The CDM takes sub steps per substep around contacts, sub_y (with the step matrices
    binv_y) where only yielding members need it.

    Approach levels (phi.shape[0] = L + 1 > 1): when a contact may begin within 2h, the exact
    propagation goes on in steps of h/2, h/4, … h/2^L, halving while a contact may begin
    within two steps, and hands over to the CDM only at the finest level (h/2^L, sub/2^L
    CDM steps); the CDM checks every sub/2^L steps whether every contact has ended and none
    can begin within 4·h/2^L, and hands back there. So the CDM runs only around the impacts
    themselves, not for the whole substeps in which one may happen.

    Yielding members: exact propagation holds while they are elastic, about the static
    offset u_static = K⁻¹·g of their plastic deflections (M·ẅ + C·ẇ + K·w = p for
    w = u − u_static); the CDM takes over while any member may reach its yield surface
    within the horizon, as around contacts (at substep boundaries, at the yielding step)."""
    dt = h / sub
    dt_y = h / sub_y
    n_dof = mass.size
    has_pairs = params[0].size > 0
    has_members = plastic.shape[0] > 0
    levels = phi.shape[0] - 1
    fine = 1 << levels  # finest exact steps per substep
    q = sub // fine  # CDM steps per finest exact step
    h_fine = h / fine
    per_record = int(round(ground_dt / h))  # substeps per record interval
    skip = False  # the last substep was a double one: this k is already passed
    for k in range(k_start, k_stop):
        if skip:
            skip = False
            continue
        t = k * h
        if mode[0] == MODE_EXACT:
            # the state at t_k: forces, energy, peaks, output
            yielded = 0
            if has_members:  # elastic unless the last substep overshot the yield surface
                dissipated, yielded = update_members(u, members, plastic, g)
                acc[ACC_HYSTERETIC] += dissipated
            agx, agy = exact_point(t, gap[0], u, v_exact, ku, kv, cv_next, a_abs, a_rel, mass, damping, storey_k,
                                   storey_bottom, storey_top, ground, ground_dt, g, acc, storey_axes, centre,
                                   col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc, kept,
                                   between, first, rates, crest_work)  # fmt: skip
            e_plastic = 0.0
            if has_members:
                member_states(u, members, plastic, k // stride_h if k % stride_h == 0 else -1, out_member, peak_member)
                e_plastic = plastic_energy_terms(u, g, members, plastic)
            if k % stride_h == 0:
                status = write_output(k // stride_h, u, v_exact, a_abs, ku, agx, agy, mass, acc, pair_now,
                                      out_u, out_v, out_a, out_ground, out_energy, out_contact, u_limit,
                                      e_plastic)  # fmt: skip
                if status != STATUS_OK:
                    counters[CNT_FAILED_STEP] = k * sub
                    return status, k
            if k == k_end:
                return STATUS_OK, k + 1
            # two substeps at once where their span allows it (phi2), no output sample, record
            # sample, call's end or the analysis' end falls inside them, and nothing can touch or
            # yield within 2·2h
            double = (phi2.shape[0] > 0 and k + 2 <= min(k_stop, k_end) and (k + 1) % stride_h != 0
                      and (k + 1) % per_record != 0 and yielded == 0
                      and not (has_pairs and contact_possible_within(ENTER_HORIZON * 2.0 * h, u, v_exact, a_rel,
                                                                     geometry, params, broad))
                      and not (has_members and yield_possible_within(ENTER_HORIZON * 2.0 * h, u, v_exact, a_rel,
                                                                     members, plastic)))  # fmt: skip
            contact_soon = False
            may_yield = False
            if not double:
                contact_soon = has_pairs and contact_possible_within(ENTER_HORIZON * h, u, v_exact, a_rel, geometry,
                                                                     params, broad)  # fmt: skip
                may_yield = has_members and (yielded > 0 or yield_possible_within(ENTER_HORIZON * h, u, v_exact,
                                                                                  a_rel, members, plastic))  # fmt: skip
            if not (contact_soon or may_yield):
                span = 2 if double else 1
                if double:
                    propagate_elastic(t, 2.0 * h, u, v_exact, phi2, g02, g12, mean2, form2, dof_start, dof_count,
                                      mass, ground, ground_dt, xbuf, ybuf, acc, has_members, u_static)  # fmt: skip
                else:
                    propagate_elastic(t, h, u, v_exact, phi[0], g0[0], g1[0], mean_rows[0], damping_form[0],
                                      dof_start, dof_count, mass, ground, ground_dt, xbuf, ybuf, acc, has_members,
                                      u_static)  # fmt: skip
                gap[0] = span * h
                counters[CNT_EXACT] += 1
                counters[CNT_EXACT_SPAN] += span * sub
                # a bad value stops the run at the substep that made it (a non-finite velocity
                # makes the displacement non-finite within the same substep: propagate mixes them)
                for d in range(n_dof):
                    if not abs(u[d]) <= u_limit:
                        counters[CNT_FAILED_STEP] = (k + span) * sub
                        return STATUS_DIVERGED, k + span
                skip = double
                continue
            if contact_soon and levels > 0 and not may_yield:
                mode[0] = MODE_APPROACH  # finer exact steps first
            else:  # hand the state to the CDM at t_k: at the contact step, or at the yielding step
                mode[0] = MODE_CDM if contact_soon else MODE_CDM_YIELD
                _enter_cdm(dt if contact_soon else dt_y, u, v_exact, a_rel, v_half, dv, storey_k, storey_bottom,
                           storey_top, z, mass, damping, cv_half, acc)  # fmt: skip
                counters[CNT_SWITCHES] += 1
        if mode[0] == MODE_CDM_YIELD or levels == 0 or k == k_end:
            # CDM through the whole substep, at the contact step or at the yielding step
            if mode[0] == MODE_CDM:
                step, steps, step_matrix = dt, sub, binv
            else:
                step, steps, step_matrix = dt_y, sub_y, binv_y
            last = k * steps + 1 if k == k_end else (k + 1) * steps  # at the end: the state at t_k only
            status, failed_at = advance(k * steps, last, step, stride_h * steps, u_limit,
                                mass, damping, storey_k, storey_bottom, storey_top, step_matrix, dof_start, dof_count,
                                ground, ground_dt, storey_axes, centre, col_storey, col_arm,
                                u, v_half, ku, cv_half, acc,
                                peak_col, peak_rot, peak_disp, peak_acc,
                                out_u, out_v, out_a, out_ground, out_energy, out_contact,
                                r, dv, v, a_abs, z, cv_next, storey_work,
                                geometry, params, pair_state, pair_now, events, n_events, fc, v_est, cbuf, broad,
                                members, plastic, g, out_member, peak_member)  # fmt: skip
            if status != STATUS_OK:
                counters[CNT_FAILED_STEP] = failed_at * sub // steps  # in contact steps
                return status, k
            if k == k_end:
                return STATUS_OK, k + 1
            counters[CNT_CDM] += steps
            for d in range(n_dof):
                a_rel[d] = dv[d] / step  # the CDM's acceleration at the last step
            if mode[0] == MODE_CDM:  # leave once no contact is possible; the exact branch then decides
                leave = broad[BR_N_LIVE][0] == 0 and not contact_possible_within(  # (contact_forces counts live pairs)
                    LEAVE_HORIZON * h, u, v_half, a_rel, geometry, params, broad)  # fmt: skip
            else:  # leave when a contact may begin (to come back at the contact step) or nothing can yield
                leave = (has_pairs and contact_possible_within(ENTER_HORIZON * h, u, v_half, a_rel, geometry,
                                                               params, broad)) or not yield_possible_within(  # fmt: skip
                    LEAVE_HORIZON * h, u, v_half, a_rel, members, plastic)
            if leave:
                _leave_cdm_exact((k + 1) * h, step, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping,
                                 storey_k, storey_bottom, storey_top, step_matrix, dof_start, dof_count, ground,
                                 ground_dt, acc, cv_next, g, has_members, members, plastic, kinv, u_static)  # fmt: skip
                mode[0] = MODE_EXACT
                counters[CNT_SWITCHES] += 1
            continue
        # within the substep, finest step by finest step: approach by exact steps, or the CDM
        pos = 0  # finest exact steps done in this substep
        level = 1
        while pos < fine:
            t_pos = t + pos * h_fine
            if mode[0] == MODE_APPROACH:
                size = fine >> level
                if not contact_ruled_out_within(ENTER_HORIZON * size * h_fine, u, v_exact, a_rel, geometry, params,
                                                broad, cbuf[0], cbuf[1]):  # fmt: skip
                    if level < levels:
                        level += 1
                        continue
                    mode[0] = MODE_CDM
                    _enter_cdm(dt, u, v_exact, a_rel, v_half, dv, storey_k, storey_bottom, storey_top, z, mass,
                               damping, cv_half, acc)  # fmt: skip
                    counters[CNT_SWITCHES] += 1
                    continue
                propagate_elastic(t_pos, size * h_fine, u, v_exact, phi[level], g0[level], g1[level],
                                  mean_rows[level], damping_form[level], dof_start, dof_count, mass, ground, ground_dt,
                                  xbuf, ybuf, acc, has_members, u_static)  # fmt: skip
                counters[CNT_EXACT] += 1
                counters[CNT_EXACT_SPAN] += size * q
                pos += size
                gap[0] = size * h_fine
                for d in range(n_dof):
                    if not abs(u[d]) <= u_limit:
                        counters[CNT_FAILED_STEP] = k * sub + pos * q
                        return STATUS_DIVERGED, k + 1
                if pos == fine:
                    mode[0] = MODE_EXACT  # the state at t_{k+1} is the exact branch's
                    break
                exact_point(t + pos * h_fine, gap[0], u, v_exact, ku, kv, cv_next, a_abs, a_rel, mass, damping,
                            storey_k, storey_bottom, storey_top, ground, ground_dt, g, acc, storey_axes, centre,
                            col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc, kept,
                            between, first, rates, crest_work)  # fmt: skip
                if level > 1 and pos % (2 * size) == 0:
                    level -= 1  # try the coarser step: the next pass checks it
                continue
            # MODE_CDM: the next finest step's worth of CDM steps
            n0 = k * sub + pos * q
            status, failed_at = advance(n0, n0 + q, dt, stride_h * sub, u_limit,
                                mass, damping, storey_k, storey_bottom, storey_top, binv, dof_start, dof_count,
                                ground, ground_dt, storey_axes, centre, col_storey, col_arm,
                                u, v_half, ku, cv_half, acc,
                                peak_col, peak_rot, peak_disp, peak_acc,
                                out_u, out_v, out_a, out_ground, out_energy, out_contact,
                                r, dv, v, a_abs, z, cv_next, storey_work,
                                geometry, params, pair_state, pair_now, events, n_events, fc, v_est, cbuf, broad,
                                members, plastic, g, out_member, peak_member)  # fmt: skip
            if status != STATUS_OK:
                counters[CNT_FAILED_STEP] = failed_at
                return status, k
            counters[CNT_CDM] += q
            pos += 1
            for d in range(n_dof):
                a_rel[d] = dv[d] / dt  # the CDM's acceleration at the last step
            if broad[BR_N_LIVE][0] > 0 or not contact_ruled_out_within(LEAVE_HORIZON * h_fine, u, v_half, a_rel,
                                                                       geometry, params, broad, cbuf[0], cbuf[1]):  # fmt: skip
                continue
            if pos < fine and has_members and yield_possible_within(LEAVE_HORIZON * h, u, v_half, a_rel, members,
                                                                    plastic):  # fmt: skip
                continue  # members may yield: the exact branch decides at the substep's end
            t_pos = t + pos * h_fine
            _leave_cdm_exact(t_pos, dt, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping, storey_k,
                             storey_bottom, storey_top, binv, dof_start, dof_count, ground, ground_dt, acc, cv_next,
                             g, has_members, members, plastic, kinv, u_static)  # fmt: skip
            counters[CNT_SWITCHES] += 1
            if pos == fine:
                mode[0] = MODE_EXACT
                break
            mode[0] = MODE_APPROACH
            level = levels
            exact_point(t_pos, 0.0, u, v_exact, ku, kv, cv_next, a_abs, a_rel, mass, damping, storey_k,
                        storey_bottom, storey_top, ground, ground_dt, g, acc, storey_axes, centre, col_storey,
                        col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc, kept, between,
                        first, rates, crest_work)  # fmt: skip
    return STATUS_OK, k_stop


@kernel
def _leave_cdm_exact(t, dt, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping, storey_k, bottom, top, binv,
                     dof_start, dof_count, ground, ground_dt, acc, cv, g, has_members, members, plastic, kinv,
                     u_static):  # fmt: skip
    """Hand the CDM's state at t back to the exact propagation (_leave_cdm), with the members'
    static offset u_static = K⁻¹·g for their plastic deflections."""
    if has_members:
        plastic_correction(members, plastic, g)
        solve_blocks(kinv, dof_start, dof_count, g, u_static)
    _leave_cdm(t, dt, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping, storey_k, bottom, top, binv,
               dof_start, dof_count, ground, ground_dt, acc, cv, g)  # fmt: skip


@kernel
def _leave_cdm(t, dt, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping, storey_k, bottom, top,
               binv, dof_start, dof_count, ground, ground_dt, acc, cv, g):  # fmt: skip
    """v_n = v_{n−½} + Δv_n/2 at t_n (no contact force), close the energy account up to t_n."""
    n_dof = mass.size
    agx, agy = ground_at(t, ground, ground_dt)
    storey_matvec(u, storey_k, bottom, top, ku)
    for d in range(0, n_dof, 3):
        r[d] = -mass[d] * agx - ku[d] + g[d] - cv_half[d]
        r[d + 1] = -mass[d + 1] * agy - ku[d + 1] + g[d + 1] - cv_half[d + 1]
        r[d + 2] = -ku[d + 2] + g[d + 2] - cv_half[d + 2]
    solve_blocks(binv, dof_start, dof_count, r, dv)
    for d in range(n_dof):
        v_exact[d] = v_half[d] + 0.5 * dv[d]
    storey_matvec(v_exact, storey_k, bottom, top, kv)
    damping_force(v_exact, kv, mass, damping, n_dof, cv)
    p_in = 0.0
    p_damp = 0.0
    for d in range(0, n_dof, 3):
        p_in -= mass[d] * (agx * v_exact[d] + agy * v_exact[d + 1])
    for d in range(n_dof):
        p_damp += v_exact[d] * cv[d]
    accumulate_energy(acc, dt, p_in, p_damp, 0.0)
    acc[ACC_FRESH] = 1.0  # t_n is integrated; the exact loop starts from here
