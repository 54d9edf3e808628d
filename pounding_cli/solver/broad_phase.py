"""Broad phase of the contact search: which candidate pairs' bounding boxes overlap, compiled.

A body's box is its outline's bounding box at rest, moved by the floor's (u_x, u_y) and
widened on every side by |θ|·r (r: the largest distance from the mass centre to a vertex, so
no vertex of the turned outline leaves it); an obstacle's box does not move. Two bodies can
touch only if their boxes overlap along x and along y.

Testing every candidate pair costs a few operations per pair and step, but pairs grow with the
square of the buildings at a level (3·n(n−1)/2 in a row of n three-storey buildings). Sweep and
prune (sort and sweep) makes the cost linear in the bodies plus the pairs whose boxes overlap:

* Pairs are grouped by the level they belong to: the floors joined by floor–floor pairs (one
  level, different buildings) and the obstacles that pair with them. An obstacle spanning
  several levels is a member of several groups; every pair belongs to exactly one group.
* Each group keeps its members ordered by the lower bound of their boxes along its sweep axis
  (x or y, whichever spreads the rest boxes' centres more; fixed at set-up). Bodies move
  little in a step, so an insertion sort of the last step's order costs O(members).
* A sweep along the sorted members finds the pairs whose intervals overlap on that axis:
  member i meets the members after it until one starts beyond i's upper bound. Those are
  tested on the other axis, and a dense local index matrix of the group gives their pair
  index (−1: not a candidate, e.g. two obstacles).

The comparisons are the all-pairs test's, on bounds computed with the same operations in the
same order, so both find the same pairs, bit for bit. With few pairs per member (below
SWEEP_PAIRS_PER_MEMBER) the plain loop over all pairs is faster and is used instead.
"""

from __future__ import annotations

import numpy as np

from .jit import INTERNAL, kernel
from .records import BroadPhase
from .tunables import SWEEP_PAIRS_PER_MEMBER


# columns of the per-member bounds: lower and upper bound along the group's sweep axis, then
# along the other axis, m
LO_SWEEP, HI_SWEEP, LO_OTHER, HI_OTHER = range(4)


@kernel(inline="always")
def reach(body, u, body_floor, body_radius):
    """(u_x, u_y, how far a rotation can move a vertex) of a body, m."""
    f = body_floor[body]
    if f < 0:
        return 0.0, 0.0, 0.0
    return u[3 * f], u[3 * f + 1], abs(u[3 * f + 2]) * body_radius[body]


@kernel(inline="always")
def reach_over(body, u, v, acc, horizon, body_floor, body_radius):
    """A body's displacement (u_x, u_y) and how much farther (along x, along y, by rotation)
    it can move within `horizon` s from its velocity and acceleration, m."""
    f = body_floor[body]
    if f < 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    half = 0.5 * horizon * horizon
    grow_x = horizon * abs(v[3 * f]) + half * abs(acc[3 * f])
    grow_y = horizon * abs(v[3 * f + 1]) + half * abs(acc[3 * f + 1])
    turn = (abs(u[3 * f + 2]) + horizon * abs(v[3 * f + 2]) + half * abs(acc[3 * f + 2])) * body_radius[body]
    return u[3 * f], u[3 * f + 1], grow_x, grow_y, turn


@kernel(inline="always")
def _store_bounds(bounds, slot, axis, lo_x, hi_x, lo_y, hi_y):
    """Bounds of one member along its group's sweep axis (0: x, 1: y) and the other axis."""
    if axis == 0:
        bounds[slot, LO_SWEEP] = lo_x
        bounds[slot, HI_SWEEP] = hi_x
        bounds[slot, LO_OTHER] = lo_y
        bounds[slot, HI_OTHER] = hi_y
    else:
        bounds[slot, LO_SWEEP] = lo_y
        bounds[slot, HI_SWEEP] = hi_y
        bounds[slot, LO_OTHER] = lo_x
        bounds[slot, HI_OTHER] = hi_x


@kernel(inline="always")
def _displaced_bounds(start, stop, axis, u, group_body, body_floor, body_radius, body_box, bounds):
    """Members start…stop−1: the displaced box, rest box moved by (u_x, u_y) and widened by
    |θ|·r (the expressions of the all-pairs test, evaluated in its order)."""
    for s in range(start, stop):
        k = group_body[s]
        dx, dy, r = reach(k, u, body_floor, body_radius)
        _store_bounds(bounds, s, axis, body_box[k, 0] + dx - r, body_box[k, 2] + dx + r,
                      body_box[k, 1] + dy - r, body_box[k, 3] + dy + r)  # fmt: skip


@kernel(inline="always")
def _widened_bounds(start, stop, axis, horizon, u, v, acc, group_body, body_floor, body_radius, body_box, bounds):
    """Members start…stop−1: the displaced box widened further by how far the body can move
    within `horizon` s. Returns False when a bound is NaN: the sort cannot order it, and the
    caller answers that a contact may begin (the CDM then takes over and stops a run gone
    bad at once)."""
    for s in range(start, stop):
        k = group_body[s]
        ux, uy, gx, gy, r = reach_over(k, u, v, acc, horizon, body_floor, body_radius)
        lo_x = body_box[k, 0] + ux - gx - r
        hi_x = body_box[k, 2] + ux + gx + r
        lo_y = body_box[k, 1] + uy - gy - r
        hi_y = body_box[k, 3] + uy + gy + r
        if lo_x != lo_x or hi_x != hi_x or lo_y != lo_y or hi_y != hi_y:
            return False
        _store_bounds(bounds, s, axis, lo_x, hi_x, lo_y, hi_y)
    return True


@kernel(inline="always")
def _sort_by_lower_bound(start, stop, order, bounds):
    """Insertion sort of order[start:stop] (members' local numbers) by their lower bound along
    the sweep axis: O(members) when the last step's order still nearly holds."""
    for i in range(start + 1, stop):
        k = order[i]
        key = bounds[start + k, LO_SWEEP]
        j = i - 1
        while j >= start and bounds[start + order[j], LO_SWEEP] > key:
            order[j + 1] = order[j]
            j -= 1
        order[j + 1] = k


@kernel(inline="always")
def _sweep(start, stop, order, bounds, index, index_start, g, hits, n_hits, first_only):
    """Append to hits the pairs of group g (members start…stop−1, sorted) whose boxes overlap
    on both axes; returns the new count (after the first such pair when first_only)."""
    m = stop - start
    base = index_start[g]
    for i in range(start, stop):
        a = order[i]
        hi_a = bounds[start + a, HI_SWEEP]
        lo_other_a = bounds[start + a, LO_OTHER]
        hi_other_a = bounds[start + a, HI_OTHER]
        for j in range(i + 1, stop):
            b = order[j]
            if hi_a < bounds[start + b, LO_SWEEP]:
                break  # b and every member after it start beyond a's end
            if hi_other_a < bounds[start + b, LO_OTHER] or bounds[start + b, HI_OTHER] < lo_other_a:
                continue
            p = index[base + a * m + b]
            if p >= 0:
                hits[n_hits] = p
                n_hits += 1
                if first_only:
                    return n_hits
    return n_hits


@kernel(inline="always")
def _sort_ascending(x, n):
    """Shell sort of x[:n] in place (gaps 1, 4, 13, …; an insertion sort when n is small)."""
    gap = 1
    while gap < n // 3:
        gap = 3 * gap + 1
    while gap > 0:
        for i in range(gap, n):
            key = x[i]
            j = i
            while j >= gap and x[j - gap] > key:
                x[j] = x[j - gap]
                j -= gap
            x[j] = key
        gap //= 3


@kernel(inline="always")
def pairs_to_visit(u, bodies, broad):
    """The pairs the contact step must visit, ascending and without repeats, into broad's
    `hits`; returns their number. They are the pairs whose displaced boxes overlap, plus the
    pairs in contact at the last step (`live`), whose episodes end when they no longer touch.
    Every other pair has no overlap now and none at the last step, so visiting it would
    change nothing."""
    body_floor, body_radius, body_box = bodies.floor, bodies.radius, bodies.box
    group_start, group_body, group_axis, index_start, index, order, bounds, hits, live, n_live, _, _ = broad
    n_hits = 0
    for g in range(group_axis.size):
        start = group_start[g]
        stop = group_start[g + 1]
        _displaced_bounds(start, stop, group_axis[g], u, group_body, body_floor, body_radius, body_box, bounds)
        _sort_by_lower_bound(start, stop, order, bounds)
        n_hits = _sweep(start, stop, order, bounds, index, index_start, g, hits, n_hits, False)
    return _with_live(hits, n_hits, live, n_live[0])


@kernel(inline="always")
def _with_live(hits, n_hits, live, n_live):
    """The n_hits pairs in `hits` and the n_live in `live`, ascending and without repeats, into
    `hits`; returns their number."""
    for i in range(n_live):
        hits[n_hits] = live[i]
        n_hits += 1
    _sort_ascending(hits, n_hits)
    n_unique = 0
    for i in range(n_hits):
        if n_unique == 0 or hits[i] != hits[n_unique - 1]:
            hits[n_unique] = hits[i]
            n_unique += 1
    return n_unique


@kernel(inline="always")
def phase_pairs_to_visit(broad):
    """pairs_to_visit while buildings sleep: the phase's pairs and those in contact at the last
    step, ascending and without repeats, into `hits`; returns their number."""
    hits, phase = broad.hits, broad.phase
    n_hits = broad.n_phase[0]
    for i in range(n_hits):
        hits[i] = phase[i]
    return _with_live(hits, n_hits, broad.live, broad.n_live[0])


@kernel(inline="always")
def _widened_sweep(horizon, u, v, acc, bodies, broad, first_only):
    """Sweep and prune on the boxes widened by how far each body can move within `horizon` s:
    the pairs whose widened boxes overlap, into broad's `hits` (only the first when
    first_only); returns their number, or −1 for a state with NaN (no order to sweep)."""
    body_floor, body_radius, body_box = bodies.floor, bodies.radius, bodies.box
    group_start, group_body, group_axis, index_start, index, order, bounds, hits, live, n_live, _, _ = broad
    n_hits = 0
    for g in range(group_axis.size):
        start = group_start[g]
        stop = group_start[g + 1]
        if not _widened_bounds(start, stop, group_axis[g], horizon, u, v, acc, group_body, body_floor, body_radius,
                               body_box, bounds):  # fmt: skip
            return -1
        _sort_by_lower_bound(start, stop, order, bounds)
        n_hits = _sweep(start, stop, order, bounds, index, index_start, g, hits, n_hits, first_only)
        if first_only and n_hits > 0:
            return n_hits
    return n_hits


@kernel(inline="always")
def boxes_may_meet_within(horizon, u, v, acc, bodies, broad):
    """True when some pair's boxes, each widened by how far its body can move within `horizon`
    s, overlap (sweep and prune: the answer of testing every pair, for any state without NaN;
    True for one with NaN)."""
    return _widened_sweep(horizon, u, v, acc, bodies, broad, True) != 0


@kernel(**INTERNAL)
def pairs_may_meet_within(horizon, u, v, acc, bodies, broad):
    """The pairs whose boxes, each widened by how far its body can move within `horizon` s,
    overlap, into broad's `hits` (sweep and prune, by group); returns their number, or −1 for
    a state with NaN (no order to sweep)."""
    return _widened_sweep(horizon, u, v, acc, bodies, broad, False)


def pair_groups(pair_a: np.ndarray, pair_b: np.ndarray, body_floor: np.ndarray) -> list[list[int]]:
    """Candidate pairs grouped by level: floors joined through floor–floor pairs form one group
    (connected components), and a floor–obstacle pair joins its floor's group. Returns the pair
    indices of each group, ascending."""
    parent = {}

    def root(k: int) -> int:
        parent.setdefault(k, k)
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    for a, b in zip(pair_a.tolist(), pair_b.tolist()):
        if body_floor[a] >= 0 and body_floor[b] >= 0:
            parent[root(a)] = root(b)
    groups: dict[int, list[int]] = {}
    for p, (a, b) in enumerate(zip(pair_a.tolist(), pair_b.tolist())):
        groups.setdefault(root(a if body_floor[a] >= 0 or body_floor[b] < 0 else b), []).append(p)
    return list(groups.values())


def sweep_pays(n_pairs: int, n_members: int) -> bool:
    """Whether sweep and prune is cheaper than testing every pair (SWEEP_PAIRS_PER_MEMBER)."""
    return n_pairs > 0 and n_pairs >= SWEEP_PAIRS_PER_MEMBER * n_members


def sweep_arrays(pair_a: np.ndarray, pair_b: np.ndarray, body_floor: np.ndarray, body_box: np.ndarray,
                 sweep: bool | None = None) -> BroadPhase:  # fmt: skip
    """The broad phase's record (records.BroadPhase), made once per run.

    group_body[group_start[g]:group_start[g + 1]] are group g's bodies; group_axis[g] its sweep
    axis (0: x, 1: y); index[index_start[g]:] its m × m local pair matrix (row-major, −1: no
    candidate); order the members' local numbers, sorted by lower bound (carried between
    steps); bounds (members, 4) work space; hits (2·n_pairs) the pairs to visit; live
    (n_pairs) and n_live (1) the pairs in contact at the last step.

    sweep: True for sweep and prune, False for no groups (the contact kernels then test every
    pair), None to choose the cheaper (sweep_pays)."""
    groups = [_group(pairs, pair_a, pair_b, body_box) for pairs in pair_groups(pair_a, pair_b, body_floor)]
    n_members = sum(len(members) for members, _, _ in groups)
    if sweep is None:
        sweep = sweep_pays(pair_a.size, n_members)
    if not sweep:
        groups = []
    sizes = [len(members) for members, _, _ in groups]
    return BroadPhase(
        np.cumsum([0] + sizes, dtype=np.int64),
        np.array([k for members, _, _ in groups for k in members], dtype=np.int64),
        np.array([axis for _, _, axis in groups], dtype=np.int64),
        np.cumsum([0] + [m * m for m in sizes], dtype=np.int64),
        np.concatenate([matrix.ravel() for _, matrix, _ in groups] + [np.zeros(0, dtype=np.int64)]),
        np.concatenate([_rest_order(members, axis, body_box) for members, _, axis in groups]
                       + [np.zeros(0, dtype=np.int64)]),  # fmt: skip
        np.zeros((sum(sizes), 4)),
        np.zeros(2 * pair_a.size, dtype=np.int64),
        np.zeros(pair_a.size, dtype=np.int64),
        np.zeros(1, dtype=np.int64),
        np.zeros(pair_a.size, dtype=np.int64),
        np.full(1, -1, dtype=np.int64),
    )


def _group(pairs: list[int], pair_a: np.ndarray, pair_b: np.ndarray, body_box: np.ndarray):
    """(member bodies ascending, local pair matrix, sweep axis) of one group of pairs. The sweep
    axis is the one along which the members' rest boxes' centres spread more."""
    members = sorted({int(pair_a[p]) for p in pairs} | {int(pair_b[p]) for p in pairs})
    local = {k: i for i, k in enumerate(members)}
    matrix = np.full((len(members), len(members)), -1, dtype=np.int64)
    for p in pairs:
        i, j = local[int(pair_a[p])], local[int(pair_b[p])]
        matrix[i, j] = matrix[j, i] = p
    box = body_box[members]
    centre = 0.5 * (box[:, :2] + box[:, 2:])
    axis = int(np.ptp(centre[:, 1]) > np.ptp(centre[:, 0]))
    return members, matrix, axis


def _rest_order(members: list[int], axis: int, body_box: np.ndarray) -> np.ndarray:
    """Members' local numbers sorted by their rest boxes' lower bound along the sweep axis."""
    return np.argsort(body_box[members, axis], kind="stable").astype(np.int64)
