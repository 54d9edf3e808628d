"""Running peaks of the storey shears and the column forces the deflection peaks do not give.

Each is a gauge (records.Gauges, built by assembly/force_gauges.py): a linear combination of
one storey's deflection (Ã_x, Ã_y, Δθ), which update_peaks has just computed, less the part
its yielding members' plastic deflections carry,

    q = w · (Ã_x, Ã_y, Δθ) − Σ c · (k_h,x·p_x, k_h,y·p_y)   (N, or N·m for a torque).

update_gauge_peaks raises the running peaks at every state the integrator reaches. Between
two exact states the plastic deflections do not change (the exact branch runs only while no
member can yield), so q is a linear quantity of the motion plus a constant there, and the
crest machinery of peaks.py (quintic_crests, settle_crests) finds its crests exactly as it
finds a column deflection's: peaks_between lists them (CREST_GAUGE), settle_crests values
them from the motion's Taylor series, the constant added to the series' first term.
"""

from __future__ import annotations

from .jit import kernel


@kernel(inline="always")
def gauge_offset(g, gauges):
    """The part of gauge g its yielding members' plastic deflections carry, N (N·m)."""
    plastic, kh = gauges.plastic, gauges.kh
    total = 0.0
    for e in range(gauges.member_start[g], gauges.member_start[g + 1]):
        m = gauges.member[e]
        total -= gauges.member_weight[e, 0] * kh[m, 0] * plastic[m, 0] + gauges.member_weight[e, 1] * kh[m, 1] * \
            plastic[m, 1]  # fmt: skip
    return total


@kernel(inline="always")
def gauge_linear(g, dx, dy, rot, gauges):
    """The linear part of gauge g at the storey deflection (dx, dy, rot), N (N·m)."""
    w = gauges.weight
    return w[g, 0] * dx + w[g, 1] * dy + w[g, 2] * rot


@kernel(inline="always")
def update_gauge_peaks(storey_work, gauges):
    """Running maxima of |q| of every gauge at the state whose storey deflections storey_work
    (n_storeys, 3) holds."""
    peak = gauges.peak
    for g in range(gauges.storey.size):
        s = gauges.storey[g]
        q = abs(gauge_linear(g, storey_work[s, 0], storey_work[s, 1], storey_work[s, 2], gauges) +
                gauge_offset(g, gauges))  # fmt: skip
        if q > peak[g]:
            peak[g] = q
