"""City-block models: a grid of shear-type buildings a few centimetres apart, and districts of
such blocks separated by streets (issue 30).

A block is `rows × cols` buildings. Column j of the grid is `widths[j]` wide (x) and row i
`depths[i]` deep (y); the gaps between neighbouring columns and rows are drawn around `gap`,
so every building faces up to four neighbours across a gap of a few centimetres. Each
building has 2–6 storeys (uniformly drawn) of one storey height, drawn around `storey_height`
when `storey_spread` > 0 (floors at different heights: slab–storey contacts). The draws come
from numpy's seeded generator, so a seed gives one model on every machine.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Block:
    """How to draw a block (lengths in m)."""

    rows: int = 10
    cols: int = 10
    width: float = 10.0  # mean plan size of a building, m
    width_spread: float = 2.0  # ± uniform, m
    gap: float = 0.10  # mean gap between neighbours, m
    gap_spread: float = 0.02  # ± uniform, m
    storeys: tuple[int, int] = (2, 6)  # inclusive range
    storey_height: float = 3.0  # m
    storey_spread: float = 0.0  # ± uniform, m, per building
    seed: int = 30


def block_buildings(block: Block, origin: tuple[float, float] = (0.0, 0.0), prefix: str = "",
                    rng: np.random.Generator | None = None) -> list[dict[str, Any]]:  # fmt: skip
    """The `buildings` tables of one block whose lower-left corner is at `origin` (m)."""
    rng = np.random.default_rng(block.seed) if rng is None else rng
    widths = block.width + rng.uniform(-block.width_spread, block.width_spread, block.cols)
    depths = block.width + rng.uniform(-block.width_spread, block.width_spread, block.rows)
    gaps_x = block.gap + rng.uniform(-block.gap_spread, block.gap_spread, max(block.cols - 1, 0))
    gaps_y = block.gap + rng.uniform(-block.gap_spread, block.gap_spread, max(block.rows - 1, 0))
    x0 = origin[0] + np.concatenate([[0.0], np.cumsum(widths[:-1] + gaps_x)])
    y0 = origin[1] + np.concatenate([[0.0], np.cumsum(depths[:-1] + gaps_y)])
    out = []
    for i in range(block.rows):
        for j in range(block.cols):
            n = int(rng.integers(block.storeys[0], block.storeys[1] + 1))
            h = block.storey_height + float(rng.uniform(-block.storey_spread, block.storey_spread))
            out.append(_building(f"{prefix}r{i + 1}c{j + 1}", (float(x0[j]), float(y0[i])),
                                 float(widths[j]), float(depths[i]), n, round(h, 3), rng))  # fmt: skip
    return out


def block_extent(block: Block) -> float:
    """The largest plan size a block can take along either axis, m."""
    return block.cols * (block.width + block.width_spread) + (block.cols - 1) * (block.gap + block.gap_spread)


def district_buildings(block: Block, blocks_x: int, blocks_y: int, street: float = 20.0) -> list[dict[str, Any]]:
    """`blocks_x × blocks_y` blocks (each drawn with its own seed) separated by streets `street` m wide."""
    pitch = block_extent(block) + street
    out = []
    for bi in range(blocks_y):
        for bj in range(blocks_x):
            rng = np.random.default_rng([block.seed, bi, bj])
            prefix = f"b{bi + 1}_{bj + 1}" + "_" if blocks_x * blocks_y > 1 else ""
            out.extend(block_buildings(block, (bj * pitch, bi * pitch), prefix, rng))
    return out


def _building(name: str, origin: tuple[float, float], a: float, b: float, storeys: int, height: float,
              rng: np.random.Generator) -> dict[str, Any]:  # fmt: skip
    """One building: an a × b slab (m), columns on a 3 × 3 grid, 1000 kg/m² floors."""
    a, b = round(a, 3), round(b, 3)
    section = round(float(rng.uniform(0.35, 0.5)), 2)
    return {
        "name": name,
        "origin": [round(origin[0], 4), round(origin[1], 4)],
        "floors": [{
            "repeat": storeys,
            "height": height,
            "slab": [[0.0, 0.0], [a, 0.0], [a, b], [0.0, b]],
            "mass_per_area": 1000.0,
            "column_grid": {"x": [0.0, a / 2, a], "y": [0.0, b / 2, b], "section": [section, section],
                            "material": "concrete"},
        }],
    }  # fmt: skip


def city_document(buildings: list[dict[str, Any]], title: str, record_dir: str = "records",
                  duration: float | None = None) -> dict[str, Any]:  # fmt: skip
    """A whole model document around `buildings`: concrete, the shipped Ridgecrest record
    (L = HNE along X, T = HNN along Y), default Δt and contact, the buildings' histories in
    single precision (a city's file is mostly its buildings' histories: half the size)."""
    mseed = f"{record_dir}/ridgecrest2019_ccc.mseed"
    analysis: dict[str, Any] = {"dt": "auto", "output_interval": 0.01, "history_precision": "single"}
    if duration is not None:
        analysis["duration"] = duration
    return {
        "title": title,
        "materials": {"concrete": {"elastic_modulus": 21e9, "poisson_ratio": 0.2}},
        "buildings": buildings,
        "excitation": {"angle": 0.0, "components": ["L", "T"], "scale": 1.0, "record": {
            "name": "2019 Ridgecrest M7.1, CI.CCC (China Lake, Christmas Canyon Rd.)",
            "L": {"file": mseed, "trace": "HNE", "units": "m/s2"},
            "T": {"file": mseed, "trace": "HNN", "units": "m/s2"}}},
        "analysis": analysis,
        "contact": {"k_normal": "auto", "k_tangential": "auto", "friction_static": 0.8, "friction_kinetic": 0.6},
    }  # fmt: skip
