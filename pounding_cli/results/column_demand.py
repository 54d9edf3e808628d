"""What each slab–storey impact puts into the columns it strikes (issue 23: column demand).

A slab that strikes a storey at a = ξ·h above the floor below presses the columns of the struck
façade (assembly/storey_contact.py), which deflect together: column i takes the share
w_i = k_i / Σk of the contact force along each direction (k_i: its stiffness along the façade's
normal n, or along the façade t, for friction). On a column clamped at both ends (h, b = h − a)
a point load P gives the classical fixed-end reactions (Roark, fixed–fixed beam, point load):

    V_bottom = P·b²(3a + b)/h³,   V_top = P·a²(a + 3b)/h³   (V_bottom + V_top = P),
    M_bottom = P·a·b²/h²,         M_top = P·a²·b/h²,        M under the load = 2P·a²b²/h³.

These are the impact's own share of the column's forces, at the step of the impact's peak normal
force (with the friction logged there); they act on top of the shear the storey's drift puts
into the column, K_i·δ_i, which is added at that instant from the stored floor motion (linear
between output samples), so that `shear_*` is the column's whole shear at each end. Columns are
massless here. Where they have local modes (assembly/local_modes.py), the time loop keeps the
bundle's own end shears and moments at the step of each impact at which the larger end shear
peaked (solver/storey_bodies.track_column_shears: the modes' restoring forces, the static
reaction of what of the force they leave, and the inertia of the columns' mass that moves with
the floors); the columns share those by the same weights, the
drift is added at that instant, and the moment under the load is not given (NaN).
"""

from __future__ import annotations

import numpy as np

from ..assembly import ContactArrays, System
from ..assembly.columns import rigid_arm
from ..assembly.storey_contact import StoreyBody

DEMAND_DTYPE = np.dtype(
    [
        ("event", np.int64),
        ("building", object),
        ("column", object),
        ("storey", np.int64),
        ("xi", np.float64),
        ("t_peak", np.float64),
        ("share", np.float64),
        ("impact_shear_bottom_x", np.float64),
        ("impact_shear_bottom_y", np.float64),
        ("impact_shear_top_x", np.float64),
        ("impact_shear_top_y", np.float64),
        ("impact_moment_bottom", np.float64),
        ("impact_moment_top", np.float64),
        ("impact_moment_at_load", np.float64),
        ("shear_bottom_x", np.float64),
        ("shear_bottom_y", np.float64),
        ("shear_top_x", np.float64),
        ("shear_top_y", np.float64),
        ("capacity_x", np.float64),
        ("capacity_y", np.float64),
        ("ratio", np.float64),
    ]
)
"""One row per impact and struck column. event: row of /impacts/events; storey (1-based), xi;
t_peak (s); share: of the normal force, the column's; impact_*: the impact's own part at the
peak, shears along the column's local axes (N; the shear Q, the force of the part of the column
above a section on the part below, just above its foot and just below its top) and moment
magnitudes (N·m); shear_*: the column's whole shear at each end (the impact's plus its storey's
drift, K·δ), local axes, N; capacity_*: the column's shear_capacity (NaN: none given);
ratio: the largest |shear| / capacity over both ends and axes (NaN without a capacity)."""

DEMAND_UNITS = "-, -, -, -, -, s, -, N, N, N, N, N*m, N*m, N*m, N, N, N, N, N, N, -"


def fixed_end_forces(p: float, a: float, h: float) -> tuple[float, float, float, float, float]:
    """(V_bottom, V_top, M_bottom, M_top, M_at_load) of a column of length h clamped at both
    ends under a point load p at a from its foot (N, N·m; module docstring)."""
    b = h - a
    return (p * b * b * (3 * a + b) / h**3, p * a * a * (a + 3 * b) / h**3, p * a * b * b / h**2, p * a * a * b / h**2,
            2 * p * a * a * b * b / h**3)  # fmt: skip


def _at(time: np.ndarray, series: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A (nt, k) history at the times t, linear between samples: (len(t), k)."""
    return np.stack([np.interp(t, time, series[:, k]) for k in range(series.shape[1])], axis=-1)


def struck_column_shears(system: System, body: StoreyBody, column: int, t: np.ndarray, force: np.ndarray,
                         time: np.ndarray, displacement: np.ndarray,
                         ends: tuple[np.ndarray, np.ndarray] | None = None,
                         floors: tuple[np.ndarray, np.ndarray] | None = None) -> dict[str, np.ndarray]:  # fmt: skip
    """What the storey body's struck column `column` (index into its building's `columns`)
    carries when the force `force` (len(t), 2; N, global, on the struck building) acts at the
    times t (s): {"share": of the normal force, "load": (len(t), 2) its share, global, N,
    "impact_bottom", "impact_top": the load's end shears, "bottom", "top": the whole end shears
    with the storey's drift K·δ (len(t), 2 each; local axes, N)} (module docstring). The floors'
    motion comes from `displacement` (nt, n_floors of all buildings, 3) at `time`, linear
    between samples. ends: the bundle's own end shears (Q at the foot, Q at the top; (len(t), 2)
    each, global, N) where its columns have local modes (solver/storey_bodies.track_column_shears):
    the column takes its share of them in place of the point load's fixed-end shears; floors: the
    motion of the floors below and above ((len(t), 3) each) at t, in place of the stored one."""
    struck = system.buildings[body.crossing.struck]
    first = int(system.floor_start[body.crossing.struck])
    normal = body.normal
    along = np.array([-normal[1], normal[0]])
    stiff_n = np.array([normal @ struck.columns[i].plan_stiffness @ normal for i in body.columns])
    stiff_t = np.array([along @ struck.columns[i].plan_stiffness @ along for i in body.columns])
    j = body.columns.index(column)
    share_n = stiff_n[j] / stiff_n.sum() if stiff_n.sum() > 0 else 0.0
    share_t = stiff_t[j] / stiff_t.sum() if stiff_t.sum() > 0 else 0.0
    def shared(f: np.ndarray) -> np.ndarray:
        return share_n * np.outer(f @ normal, normal) + share_t * np.outer(f @ along, along)

    load = shared(force)
    h, xi = body.crossing.height, body.crossing.xi
    v_bottom, v_top, *_ = fixed_end_forces(1.0, xi * h, h)
    col = struck.columns[column]
    angle = struck.rotation + np.radians(struck.column_lines[col.line].angle)
    axes = np.array([[np.cos(angle), np.sin(angle)], [-np.sin(angle), np.cos(angle)]])  # rows: local x, y
    if floors is not None:
        q_bottom, q_top = floors
    else:
        q_top = _at(time, displacement[:, first + body.above], t)
        q_bottom = _at(time, displacement[:, first + body.below], t) if body.below >= 0 else np.zeros_like(q_top)
    # the storey's own shear in the column, K·δ (δ: its top less its bottom); the shear Q(z), the
    # force of the part above a section on the part below, is K·δ all along, and the load adds
    # +V_bottom below it and −V_top above it
    drift = q_top @ rigid_arm(col.arm_top).T - q_bottom @ rigid_arm(col.arm_bottom).T
    storey = drift @ col.plan_stiffness.T
    if ends is None:
        impact_bottom, impact_top = (v_bottom * load) @ axes.T, (-v_top * load) @ axes.T
    else:
        impact_bottom, impact_top = shared(ends[0]) @ axes.T, shared(ends[1]) @ axes.T
    return {"share": share_n, "load": load, "impact_bottom": impact_bottom, "impact_top": impact_top,
            "bottom": storey @ axes.T + impact_bottom, "top": storey @ axes.T + impact_top}  # fmt: skip


def column_demand(system: System, contact: ContactArrays, events: np.ndarray, time: np.ndarray,
                  displacement: np.ndarray, shear_peak: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
    """DEMAND_DTYPE rows for every logged impact of a slab–storey pair (events: EVENT_DTYPE;
    displacement: (nt, n_floors of all buildings, 3) the floors' motion, global axes). Where the
    struck columns have local modes, shear_peak (n_events, 8; integrate.Response.storey_shear_peak)
    holds the bundle's end shears and moments at the step where they peaked in each impact: the
    row is at that instant, the moment under the load NaN."""
    rows = []
    n_slab = contact.n_pairs - len(contact.storeys)
    for k, e in enumerate(events):
        p = int(e["pair"])
        if p < n_slab:
            continue
        body = contact.storeys[p - n_slab]
        struck = system.buildings[body.crossing.struck]
        h, xi = body.crossing.height, body.crossing.xi
        # the force on the struck body (B): F_N·n + F_T·t (t = ẑ × n), at the logged peak
        n_ab = np.array([e["normal_x"], e["normal_y"]])
        f_t = float(e["tangential_force_at_peak"]) if np.isfinite(e["tangential_force_at_peak"]) else 0.0
        force = (float(e["peak_normal_force"]) * n_ab + f_t * np.array([-n_ab[1], n_ab[0]]))[None, :]
        t = np.array([float(e["t_peak"])])
        ends = floors = None
        if body.modes and shear_peak is not None and k < shear_peak.shape[0]:
            row = shear_peak[k]
            t = np.array([row[1]])
            ends = (row[None, 2:4], row[None, 4:6])
            floors = (row[None, 8:11], row[None, 11:14])
        for i in body.columns:
            col = struck.columns[i]
            shears = struck_column_shears(system, body, i, t, force, time, displacement, ends, floors)
            _, _, m_bottom, m_top, m_load = fixed_end_forces(float(np.hypot(*shears["load"][0])), xi * h, h)
            if ends is not None:
                m_bottom, m_top, m_load = shears["share"] * row[6], shears["share"] * row[7], np.nan
            bottom, top = shears["bottom"][0], shears["top"][0]
            capacity = np.asarray(col.shear_capacity if col.shear_capacity is not None else (np.nan, np.nan))
            ratio = float(max(np.max(np.abs(bottom) / capacity), np.max(np.abs(top) / capacity)))
            rows.append((k, struck.name, struck.column_lines[col.line].name, body.crossing.storey, xi, t[0],
                         shears["share"], *shears["impact_bottom"][0], *shears["impact_top"][0], m_bottom, m_top,
                         m_load, *bottom, *top, *capacity, ratio))  # fmt: skip
    return np.array(rows, dtype=DEMAND_DTYPE) if rows else np.zeros(0, DEMAND_DTYPE)
