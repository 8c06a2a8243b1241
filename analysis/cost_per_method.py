#!/usr/bin/env python3
"""Cost per simulated second of every registered method (analysis/mps_lab/studies/cost.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import cost  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=cost.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join("runs", "cost_per_method"), help="study folder")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--scene", default="scenes/dambreak.json", help="scene (relative to the repository)")
    parser.add_argument("--end-time", type=float, default=0.5, help="simulated end time, s")
    parser.add_argument("--spacings", type=float, nargs="+", default=list(cost.DEFAULT_SPACINGS), help="l0, m")
    parser.add_argument("--repetitions", type=int, default=3, help="interleaved repetitions (the median is kept)")
    parser.add_argument("--reference", help="method of the ratios (default: the first registered)")
    parser.add_argument("--timeout", type=float, default=cost.DEFAULT_TIMEOUT, help="seconds before a run is stopped")
    parser.add_argument("--docs", action="store_true", help="copy the CSV and markdown to docs/data/")
    args = parser.parse_args(argv)
    return cost.cost(args.out, args.binary, args.scene, args.end_time, tuple(args.spacings), max(1, args.repetitions),
                     args.reference, args.timeout, args.docs)


if __name__ == "__main__":
    sys.exit(main())
