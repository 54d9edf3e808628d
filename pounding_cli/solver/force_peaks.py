"""Running peaks of the storey shears and the column forces the deflection peaks do not give.

Each is a gauge (records.Gauges, built by assembly/force_gauges.py): a linear combination of
one storey's deflection (Ã_x, Ã_y, Δθ), which update_peaks has just computed, less the part
its yielding members' plastic deflections carry,

    q = w · (Ã_x, Ã_y, Δθ) − k_h,a·p_a (a yielding column's, along its axis a)
                           − c · P_s   (a storey's: its members' plastic resultant)

in N, or N·m for a torque. P_s comes for every storey at once from the plastic correction g
on the floors (plastic_resultants). update_gauge_peaks raises the running peaks at every
state the integrator reaches, but a yielding column's: its force at every state is its
member's, whose peak hysteresis.member_states keeps (Yielding.peak); its gauge adds the crests
between exact states, and the results take the larger (results/forces.column_peaks). Between two exact states the plastic deflections do not change
(the exact branch runs only while no member can yield), so q is a linear quantity of the
motion plus a constant there, and the crest machinery of peaks.py (quintic_crests,
settle_crests) finds its crests exactly as it finds a column deflection's: peaks_between
lists them (CREST_GAUGE) with the constant of the step's start (gauges.offset: a member
that overshot its yield surface at the step's end changes it only there), settle_crests
values them from the motion's Taylor series, the constant added to the series' first term.
"""

from __future__ import annotations

from .jit import kernel


@kernel(inline="always")
def plastic_resultants(gauges):
    """gauges.resultant[s] = P_s of every storey: Σ over the floors from storey s's top floor
    up (in its building) of g (F_X, F_Y and the torque about the plan origin). A member pushes
    its two floors equally and oppositely at one point, so the storeys above s cancel in the
    sum and storey s's members' plastic forces on the floor above are what is left."""
    g, centre, top, above, resultant = gauges.g, gauges.centre, gauges.top, gauges.storey_above, gauges.resultant
    for s in range(top.size - 1, -1, -1):
        t = 3 * top[s]
        fx = g[t]
        fy = g[t + 1]
        resultant[s, 0] = fx
        resultant[s, 1] = fy
        resultant[s, 2] = g[t + 2] + centre[top[s], 0] * fy - centre[top[s], 1] * fx
        if above[s] >= 0:
            for j in range(3):
                resultant[s, j] += resultant[above[s], j]


@kernel(inline="always")
def gauge_offset(g, gauges):
    """The part of gauge g its yielding members' plastic deflections carry, N (N·m)
    (gauges.resultant as plastic_resultants left it)."""
    s = gauges.storey[g]
    w = gauges.plastic_weight
    total = -(w[g, 0] * gauges.resultant[s, 0] + w[g, 1] * gauges.resultant[s, 1] + w[g, 2] * gauges.resultant[s, 2])
    m = gauges.member[g]
    if m >= 0:
        a = gauges.member_axis[g]
        total -= gauges.kh[m, a] * gauges.plastic[m, a]
    return total


@kernel(inline="always")
def gauge_linear(g, dx, dy, rot, gauges):
    """The linear part of gauge g at the storey deflection (dx, dy, rot), N (N·m)."""
    w = gauges.weight
    return w[g, 0] * dx + w[g, 1] * dy + w[g, 2] * rot


@kernel(inline="always")
def gauge_floor(g, gauges):
    """The running peak of gauge g so far: its own, or a yielding column's member's."""
    m = gauges.member[g]
    if m >= 0:
        return max(gauges.peak[g], gauges.member_peak[m, 3 + gauges.member_axis[g]])
    return gauges.peak[g]


@kernel(inline="always")
def update_gauge_peaks(storey_work, gauges, g0, g1):
    """Running maxima of |q| of the gauges g0 … g1 − 1 at the state whose storey deflections
    storey_work (n_storeys, 3) holds (and whose plastic correction gauges.g holds)."""
    peak = gauges.peak
    if gauges.plastic.shape[0] > 0:
        plastic_resultants(gauges)
    for g in range(g0, g1):
        if gauges.member[g] >= 0:
            continue  # a yielding column: member_states has its state's force
        s = gauges.storey[g]
        q = abs(gauge_linear(g, storey_work[s, 0], storey_work[s, 1], storey_work[s, 2], gauges) +
                gauge_offset(g, gauges))  # fmt: skip
        if q > peak[g]:
            peak[g] = q


@kernel(inline="always")
def keep_offsets(gauges, g0, g1):
    """gauges.offset = the plastic part of the gauges g0 … g1 − 1 at this state, for the exact
    step from it."""
    for g in range(g0, g1):
        gauges.offset[g] = gauge_offset(g, gauges)
