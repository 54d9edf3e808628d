"""Plan coordinates far from the origin: resolved in the input, computed near a local origin.

A float resolves a coordinate X to its spacing, about |X|·1.1e-16: 0.125 m at 1e15 m, where
a 5 cm gap between two buildings is lost before anything is computed. The time loop is worse
off: the overlap of two slabs is a difference of products of coordinates, so at 3e8 m the
paper's buildings met 35 impacts instead of 32 and a 0.8 % different peak force, and at 1e7 m
(UTM northings are 1e6–1e7 m) the peak force moved by 2e-5.

So pound does two things:

- :func:`check_resolution` refuses a model whose global plan coordinates (slab vertices,
  mass centres, columns, obstacles, moat walls) cannot be written to RESOLUTION: beyond
  about 1.07e9 m. The message names the building's origin or the obstacle's polygon.
- :func:`local_origin` moves the scene by a whole number of metres before the time loop
  (the difference of a coordinate and a whole number of metres near it is exact), and
  :func:`back_to_global` moves the impact log's and the contact histories' points back, so
  that a model placed at surveyed coordinates runs exactly as the same model placed near
  the origin would. Scenes within LOCAL_ORIGIN_FROM of the origin are not moved, so they
  run bit for bit as before.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import InputError

RESOLUTION = 1e-7
"""The finest a global plan coordinate must be resolved, m (0.1 µm: pounding overlaps are
micrometres to millimetres deep). Floats resolve it within ±2^30 m ≈ 1.07e9 m."""

LOCAL_ORIGIN_FROM = 1000.0
"""Scenes with a plan coordinate beyond this (m) are computed about a local origin."""


def check_resolution(points: list[tuple[np.ndarray, str]], source: str) -> None:
    """Refuse where a global plan coordinate is too large to be resolved to RESOLUTION.
    `points` pairs each set of global points (n, 2), m, with the field that places them."""
    for xy, field in points:
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        if xy.size == 0:
            continue
        largest = float(np.max(np.abs(xy)))
        if not np.isfinite(largest) or np.spacing(largest) > RESOLUTION:
            raise InputError(
                f"a plan coordinate of {largest:.4g} m is too far from the origin to be computed with: floats "
                f"resolve it only to {np.spacing(largest):.3g} m, while gaps and overlaps need {RESOLUTION:g} m "
                f"(coordinates within ±{2.0**30:.3g} m); place the scene nearer the origin (only the distances "
                "between bodies matter)",
                file=source,
                field=field,
            )


def scene_points(model, system, contact) -> list[tuple[np.ndarray, str]]:  # type: ignore[no-untyped-def]
    """Every global plan point of the scene with the field that places it (check_resolution):
    each building's slabs, mass centres and columns (its origin), each obstacle's polygon."""
    from .contact import _obstacle_root

    out = []
    for b, bld in enumerate(system.buildings):
        xy = [*bld.slabs, bld.mass_centre, np.array([c.plan for c in bld.column_lines], dtype=float).reshape(-1, 2)]
        out.append((np.concatenate([np.asarray(p, dtype=float).reshape(-1, 2) for p in xy]), f"buildings[{b}].origin"))
    for o, obstacle in enumerate(model.all_obstacles()):
        out.append((np.asarray(obstacle.polygon, dtype=float), f"{_obstacle_root(model, o)}.polygon"
                    if o < len(model.obstacles) else f"{_obstacle_root(model, o)}.gap"))  # fmt: skip
    return out


def reference_point(system, contact) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The local origin (X0, Y0), m: the middle of the scene's bounding box rounded to whole
    metres, or (0, 0) for a scene within LOCAL_ORIGIN_FROM of the origin."""
    points = [system.floor_centre.reshape(-1, 2), system.column_plan.reshape(-1, 2)]
    for k, n in enumerate(contact.body_nv):
        points.append(contact.body_poly[k, : int(n)])
    xy = np.concatenate(points)
    if xy.size == 0 or float(np.max(np.abs(xy))) <= LOCAL_ORIGIN_FROM:
        return np.zeros(2)
    return np.round(0.5 * (xy.min(axis=0) + xy.max(axis=0)))


def local_origin(system, contact, ref: np.ndarray):  # type: ignore[no-untyped-def]
    """(system, contact) with every global plan position moved by −ref (a no-op for ref 0)."""
    if not np.any(ref):
        return system, contact
    system = replace(system, floor_centre=system.floor_centre - ref, column_plan=system.column_plan - ref)
    poly = contact.body_poly.copy()
    for k, n in enumerate(contact.body_nv):
        poly[k, : int(n)] -= ref
    contact = replace(contact, body_poly=poly, body_centre=contact.body_centre - ref)
    return system, contact


def back_to_global(response, ref: np.ndarray):  # type: ignore[no-untyped-def]
    """The response with its points (impact log x, y; contact histories' action points where
    a pair is in contact) moved back by +ref."""
    if not np.any(ref):
        return response
    from ..solver import layout as kernel

    events = response.events.copy()
    if events.shape[0]:
        events[:, kernel.EV_X] += ref[0]
        events[:, kernel.EV_Y] += ref[1]
    history = response.contact.copy()
    if history.size:
        touching = (history[..., kernel.NOW_AREA] != 0) | (history[..., kernel.NOW_FN] != 0)
        history[..., kernel.NOW_X] += np.where(touching, ref[0], 0.0)
        history[..., kernel.NOW_Y] += np.where(touching, ref[1], 0.0)
    return replace(response, events=events, contact=history)
