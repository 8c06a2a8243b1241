#!/usr/bin/env python3
"""Water entry of a cylinder against Campbell & Weynberg 1980 (analysis/mps_lab/studies/water_entry.py): arguments only.

    /usr/bin/python3 analysis/water_entry.py --out output/water_entry [--divisions 11 22 44] [--large-tank 11 22]
                                              [--collect] [--docs docs]
"""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.methods import registered_methods  # noqa: E402
from mps_lab.runner import find_binary  # noqa: E402
from mps_lab.studies import water_entry  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=water_entry.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder of the runs (OUT/D<n>/<method>)")
    parser.add_argument("--methods", nargs="+", help="methods (default: every registered one)")
    parser.add_argument("--divisions", nargs="+", type=int, default=list(water_entry.DEFAULT_DIVISIONS),
                        help="n of l0 = D/n (default 11 22)")
    parser.add_argument("--window", type=float, default=water_entry.DEFAULT_WINDOW,
                        help="moving-mean window of the force, in D/V (default 0.05)")
    parser.add_argument("--large-tank", nargs="*", type=int, default=[],
                        help="divisions also run in the tank widened and deepened by 2 D (the walls' check)")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--parallel", type=int, default=2, help="cases at a time (one thread each)")
    parser.add_argument("--timeout", type=float, default=water_entry.DEFAULT_TIMEOUT, help="seconds before a case stops")
    parser.add_argument("--collect", action="store_true", help="only tabulate the runs that exist")
    parser.add_argument("--docs", help="write data/water_entry.{csv,md} and figures/water_entry.png here (default: OUT)")
    args = parser.parse_args(argv)
    methods = args.methods or registered_methods(find_binary(args.binary))
    return water_entry.study(args.out, methods, args.divisions, args.binary, args.parallel, args.timeout, args.collect,
                             args.docs, args.window, args.large_tank)


if __name__ == "__main__":
    sys.exit(main())
