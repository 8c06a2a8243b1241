#!/usr/bin/env python3
"""The released gate against the instantaneous release (docs/validation.md, "The released gate").

    /usr/bin/python3 analysis/gate_study.py --out DIR [--spacings 0.025 0.0125] [--methods mps isph]

Runs scenes/dambreak.json and scenes/dambreak_gate.json with every method (or --methods) at
each spacing, and writes DIR/gate_front.csv (front RMS against Martin & Moyce, unshifted and
with the best shift) and DIR/gate_front.png (Z against T).
"""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import runner  # noqa: E402
from mps_lab.studies import gate  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder for the runs, the table and the figure")
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.025, 0.0125], help="l0 values, m")
    parser.add_argument("--methods", nargs="+", help="methods (default: every registered one)")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, build/mps_lab, PATH)")
    parser.add_argument("--parallel", type=int, default=2, help="cases run at once")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per case")
    args = parser.parse_args(argv)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    rows = gate.run_study(root, args.out, runner.find_binary(args.binary), args.spacings, args.methods,
                          args.parallel, args.timeout)
    return 0 if all(row["status"] == "completed" for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
