"""The hybrid integrator: exact propagation while no contact is possible, the central
difference method (CDM) around impacts.

While every pair of bodies is apart by more than it can close within the horizon, the
buildings are linear and uncoupled, and each substep h (a divisor of the record's sample
interval) is taken exactly by the state-transition matrices of propagator.py: no time-step
error, only the sampling of peaks every h. When a contact may begin within 2h (bounding
boxes widened by what velocity and acceleration can add), the loop hands the state to the
CDM of cdm.py at the contact time step Δt = h/sub; it takes the state back at a substep
boundary once every pair is out of contact and apart by more than 4h of motion.

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
Energy keeps one trapezoidal account across both: each hand-over closes the interval it
ends and marks the instant as counted.
"""

from __future__ import annotations

import numpy as np

from .cdm import (
    ACC_FRESH,
    ACC_HYSTERETIC,
    STATUS_DIVERGED,
    STATUS_OK,
    accumulate_energy,
    advance,
    damping_force,
    ground_at,
    solve_blocks,
    storey_matvec,
    storey_matvec_pair,
    update_peaks,
    write_output,
)
from .broad_phase import BR_N_LIVE
from .contact import contact_possible_within
from .hysteresis import member_states, plastic_correction, plastic_energy_terms, update_members, yield_possible_within
from .jit import REASSOCIATE, kernel

MODE_EXACT, MODE_CDM, MODE_CDM_YIELD = 0, 1, 2  # exact; CDM at the contact step; CDM at the yielding step
ENTER_HORIZON = 2.0  # substeps ahead a contact must be ruled out to stay exact
LEAVE_HORIZON = 4.0  # substeps ahead it must be ruled out to leave the CDM
# counters: exact substeps, CDM steps, hand-overs, and the step (in CDM steps) whose state
# failed the divergence check (−1 while none has)
CNT_EXACT, CNT_CDM, CNT_SWITCHES, CNT_FAILED_STEP = range(4)
N_COUNTERS = 4


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


@kernel(fastmath=REASSOCIATE)
def propagate(t, h, u, v, phi, g0, g1, dof_start, dof_count, ground, ground_dt, x, y):
    """(u, v) at t + h from (u, v) at t, exactly, building by building (x, y: scratch)."""
    a0x, a0y = ground_at(t, ground, ground_dt)
    a1x, a1y = ground_at(t + h, ground, ground_dt)
    dx = a1x - a0x
    dy = a1y - a0y
    for b in range(dof_start.size):
        d0 = dof_start[b]
        n = dof_count[b]
        for i in range(n):
            x[i] = u[d0 + i]
            x[n + i] = v[d0 + i]
        for i in range(2 * n):
            acc = g0[b, i, 0] * a0x + g0[b, i, 1] * a0y + g1[b, i, 0] * dx + g1[b, i, 1] * dy
            for j in range(2 * n):
                acc += phi[b, i, j] * x[j]
            y[i] = acc
        for i in range(n):
            u[d0 + i] = y[i]
            v[d0 + i] = y[n + i]


@kernel
def hybrid_advance(
    k_start, k_stop, k_end, h, sub, sub_y, binv_y, stride_h, u_limit,
    # exact propagation (kinv: K⁻¹ blocks, u_static: K⁻¹·g while the members stay elastic)
    phi, g0, g1, v_exact, kv, a_rel, xbuf, ybuf, mode, counters, kinv, u_static,
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

    Yielding members: exact propagation holds while they are elastic, about the static
    offset u_static = K⁻¹·g of their plastic deflections (M·ẅ + C·ẇ + K·w = p for
    w = u − u_static); the CDM takes over while any member may reach its yield surface
    within the horizon, as around contacts."""
    dt = h / sub
    dt_y = h / sub_y
    n_dof = mass.size
    has_pairs = params[0].size > 0
    has_members = plastic.shape[0] > 0
    for k in range(k_start, k_stop):
        t = k * h
        if mode[0] == MODE_EXACT:
            # the state at t_k: forces, energy, peaks, output
            yielded = 0
            if has_members:  # elastic unless the last substep overshot the yield surface
                dissipated, yielded = update_members(u, members, plastic, g)
                acc[ACC_HYSTERETIC] += dissipated
            agx, agy = exact_state(t, u, v_exact, ku, kv, cv_next, a_abs, a_rel, mass, damping, storey_k,
                                   storey_bottom, storey_top, ground, ground_dt, g)  # fmt: skip
            p_in = 0.0
            p_damp = 0.0
            for d in range(0, n_dof, 3):
                p_in -= mass[d] * (agx * v_exact[d] + agy * v_exact[d + 1])
            for d in range(n_dof):
                p_damp += v_exact[d] * cv_next[d]
            accumulate_energy(acc, h, p_in, p_damp, 0.0)
            update_peaks(u, a_abs, n_dof, storey_bottom, storey_top, storey_axes, centre,
                         col_storey, col_arm, storey_work, peak_col, peak_rot, peak_disp, peak_acc)  # fmt: skip
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
            contact_soon = has_pairs and contact_possible_within(ENTER_HORIZON * h, u, v_exact, a_rel, geometry,
                                                                 params, broad)  # fmt: skip
            if not (
                contact_soon
                or (has_members and (yielded > 0 or yield_possible_within(ENTER_HORIZON * h, u, v_exact, a_rel,
                                                                          members, plastic)))  # fmt: skip
            ):
                if has_members:
                    for d in range(n_dof):
                        u[d] -= u_static[d]
                propagate(t, h, u, v_exact, phi, g0, g1, dof_start, dof_count, ground, ground_dt, xbuf, ybuf)
                if has_members:
                    for d in range(n_dof):
                        u[d] += u_static[d]
                counters[CNT_EXACT] += 1
                # a bad value stops the run at the substep that made it (a non-finite velocity
                # makes the displacement non-finite within the same substep: propagate mixes them)
                for d in range(n_dof):
                    if not abs(u[d]) <= u_limit:
                        counters[CNT_FAILED_STEP] = (k + 1) * sub
                        return STATUS_DIVERGED, k + 1
                continue
            # a contact may begin soon, or a member yield: hand the state to the CDM at t_k
            mode[0] = MODE_CDM if contact_soon else MODE_CDM_YIELD
            step = dt if contact_soon else dt_y
            for d in range(n_dof):
                v_half[d] = v_exact[d] - 0.5 * step * a_rel[d]
                dv[d] = step * a_rel[d]
            storey_matvec(v_half, storey_k, storey_bottom, storey_top, z)
            damping_force(v_half, z, mass, damping, n_dof, cv_half)
            acc[ACC_FRESH] = 1.0  # t_k is already integrated
            counters[CNT_SWITCHES] += 1
        # CDM through this substep, at the contact step or at the yielding step
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
            leave = (has_pairs and contact_possible_within(ENTER_HORIZON * h, u, v_half, a_rel, geometry, params,
                                                           broad)) or not yield_possible_within(  # fmt: skip
                LEAVE_HORIZON * h, u, v_half, a_rel, members, plastic)
        if leave:
            if has_members:
                plastic_correction(members, plastic, g)
                solve_blocks(kinv, dof_start, dof_count, g, u_static)
            _leave_cdm((k + 1) * h, step, u, v_half, ku, cv_half, v_exact, kv, r, dv, mass, damping,
                       storey_k, storey_bottom, storey_top, step_matrix, dof_start, dof_count, ground, ground_dt,
                       acc, cv_next, g)  # fmt: skip
            mode[0] = MODE_EXACT
            counters[CNT_SWITCHES] += 1
    return STATUS_OK, k_stop


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
