"""Moving outlines: a slab carried by its floor, a storey carried by the two floors around it,
and the floors' motion between stored samples.

A floor moves rigidly by (u_x, u_y, θ) about its mass centre c (the contact kernel's own
rule): a point p of it moves by u + (R(θ) − I)(p − c). A storey's outline at the height ξ of a
neighbour's slab (assembly/levels.py: the slab of the floor above it) moves, point by point,
by (1 − s)·(the floor below's motion of that point) + s·(the floor above's), s = 3ξ² − 2ξ³
(the fixed-fixed column shape; the ground does not move). Both are affine maps of the
outline at rest, so a convex outline stays convex.

Between two stored samples t₀, t₁ = t₀ + h the motion is the quintic Hermite interpolant of
u, u̇ and ü (relative to the ground) at both ends, as the peaks are located
(solver/peaks.py): within (ω·h)⁶/46080 of each mode's share of the motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Body:
    """A moving outline: the weighted sum of the rigid motions of some floors."""

    rest: np.ndarray  # (k, 2) outline at rest, global, counter-clockwise, m
    floors: tuple[int, ...]  # global floor indices (−1: the ground, which does not move)
    centres: np.ndarray  # (len(floors), 2) their mass centres at rest, m
    weights: tuple[float, ...]  # (1,) for a slab, (1 − s(ξ), s(ξ)) for a storey; () for a fixed obstacle

    def outlines(self, u: np.ndarray) -> np.ndarray:
        """(nt, k, 2) the outline under floor motions u (nt, n_floors, 3): m, m, rad."""
        out = np.broadcast_to(self.rest, (u.shape[0], *self.rest.shape)).copy()
        for f, c, w in zip(self.floors, self.centres, self.weights):
            if f < 0 or w == 0.0:
                continue
            ux, uy, theta = u[:, f, 0], u[:, f, 1], u[:, f, 2]
            cos, sin = np.cos(theta)[:, None], np.sin(theta)[:, None]
            dx, dy = self.rest[:, 0] - c[0], self.rest[:, 1] - c[1]
            out[..., 0] += w * (ux[:, None] + (cos - 1.0) * dx - sin * dy)
            out[..., 1] += w * (uy[:, None] + sin * dx + (cos - 1.0) * dy)
        return out


@dataclass(frozen=True)
class Motion:
    """The floors' motion at the stored samples: u, u̇, ü relative to the ground."""

    time: np.ndarray  # (nt,) s
    u: np.ndarray  # (nt, n_floors, 3) m, m, rad
    v: np.ndarray  # (nt, n_floors, 3) m/s, m/s, rad/s
    a: np.ndarray  # (nt, n_floors, 3) m/s², m/s², rad/s²

    def at(self, t: float) -> np.ndarray:
        """(1, n_floors, 3): u at time t by the quintic Hermite interpolant of the interval
        holding t (a stored sample's own u at a sample)."""
        k = int(np.clip(np.searchsorted(self.time, t, side="right") - 1, 0, self.time.size - 2))
        h = self.time[k + 1] - self.time[k]
        s = (t - self.time[k]) / h
        s2, s3 = s * s, s * s * s
        h00 = 1 - 10 * s3 + 15 * s2 * s2 - 6 * s3 * s2
        h10 = s - 6 * s3 + 8 * s2 * s2 - 3 * s3 * s2
        h20 = 0.5 * s2 - 1.5 * s3 + 1.5 * s2 * s2 - 0.5 * s3 * s2
        h01 = 10 * s3 - 15 * s2 * s2 + 6 * s3 * s2
        h11 = -4 * s3 + 7 * s2 * s2 - 3 * s3 * s2
        h21 = 0.5 * s3 - s2 * s2 + 0.5 * s3 * s2
        u = (h00 * self.u[k] + h * h10 * self.v[k] + h * h * h20 * self.a[k]
             + h01 * self.u[k + 1] + h * h11 * self.v[k + 1] + h * h * h21 * self.a[k + 1])  # fmt: skip
        return u[None]


def motion_of(result, system) -> Motion:  # type: ignore[no-untyped-def]
    """The Motion of a run's buildings (RunResult), floors in the system's global order; ü
    relative = the stored absolute acceleration less the ground's (x and y rows)."""
    names = [b.name for b in system.buildings]
    u = np.concatenate([result.buildings[n].displacement for n in names], axis=1)
    v = np.concatenate([result.buildings[n].velocity for n in names], axis=1)
    a = np.concatenate([result.buildings[n].acceleration for n in names], axis=1).copy()
    a[:, :, :2] -= result.ground_acceleration[:, None, :]
    return Motion(np.asarray(result.time, dtype=float), u, v, a)
