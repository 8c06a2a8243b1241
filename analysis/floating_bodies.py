#!/usr/bin/env python3
"""Floating and submerged bodies against theory (docs/bodies.md; issue 15, item 4).

    /usr/bin/python3 analysis/floating_bodies.py --out DIR [--methods dfsph isph] [--cases heave rising sinking]
                                                [--heave-spacings 0.025 0.0125 0.00625] [--drop-spacings 0.02 0.01]

Runs scenes/floating_box_heave.json (draft and heave period), scenes/rising_box.json and
scenes/sinking_box.json (terminal speed) with every registered method (or --methods) at each
spacing, and writes DIR/floating_box_heave.csv, DIR/rising_sinking_box.csv and
DIR/floating_bodies.png. Completed runs in DIR are reused.
"""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import runner  # noqa: E402
from mps_lab.studies import floating  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder for the runs, the tables and the figure")
    parser.add_argument("--methods", nargs="+", help="methods (default: every registered one)")
    parser.add_argument("--cases", nargs="+", choices=sorted(floating.CASES), default=sorted(floating.CASES))
    parser.add_argument("--heave-spacings", type=float, nargs="+", default=list(floating.CASES["heave"][1]))
    parser.add_argument("--drop-spacings", type=float, nargs="+", default=list(floating.CASES["rising"][1]))
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, build/mps_lab, PATH)")
    parser.add_argument("--parallel", type=int, default=1, help="cases run at once")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per case")
    args = parser.parse_args(argv)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    cases = {}
    for case in args.cases:
        scene, _ = floating.CASES[case]
        cases[case] = (scene, tuple(args.heave_spacings if case == "heave" else args.drop_spacings))
    rows = floating.run_study(root, args.out, runner.find_binary(args.binary), args.methods, cases, args.parallel,
                              args.timeout)
    return 0 if rows else 1


if __name__ == "__main__":
    sys.exit(main())
