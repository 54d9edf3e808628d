#!/usr/bin/env python
"""Write inputs/city_block.toml: a 10 × 10 block of 2–6-storey buildings about 10 cm apart
(plan sizes 8–12 m, gaps 8–12 cm, drawn from seed 30), shaken by the shipped Ridgecrest record
(34 s). The generator is pounding_cli/city/block.py; other blocks and districts:

    python inputs/make_city_block.py                      # the shipped example
    python inputs/make_city_block.py --rows 5 --cols 5 -o block25.toml
    python inputs/make_city_block.py --blocks 10 -o district.toml   # 10 blocks, 20 m streets

Needs tomli_w (a test dependency: pip install -e '.[test]').
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import tomli_w

from pounding_cli.city.block import Block, city_document, district_buildings


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=10)
    parser.add_argument("--cols", type=int, default=10)
    parser.add_argument("--blocks", type=int, default=1, help="blocks, on a square-ish grid")
    parser.add_argument("--street", type=float, default=20.0, help="street width between blocks, m")
    parser.add_argument("--storey-spread", type=float, default=0.0, help="± storey height, m")
    parser.add_argument("--seed", type=int, default=30)
    parser.add_argument("-o", "--out", type=Path, default=Path(__file__).with_name("city_block.toml"))
    args = parser.parse_args()
    block = Block(rows=args.rows, cols=args.cols, storey_spread=args.storey_spread, seed=args.seed)
    bx = math.ceil(math.sqrt(args.blocks))
    by = math.ceil(args.blocks / bx)
    buildings = district_buildings(block, bx, by, args.street)[: args.blocks * args.rows * args.cols]
    n = len(buildings)
    title = f"City block: {n} buildings of 2-6 storeys about 10 cm apart, Ridgecrest 2019 CI.CCC"
    doc = city_document(buildings, title)
    header = (f"# Written by inputs/make_city_block.py (pounding_cli/city/block.py): {n} buildings,\n"
              "# 8-12 m plans on a grid, 8-12 cm gaps, 2-6 storeys of 3 m; do not edit by hand.\n")
    args.out.write_text(header + tomli_w.dumps(doc))
    print(f"wrote {args.out} ({n} buildings)")


if __name__ == "__main__":
    main()
