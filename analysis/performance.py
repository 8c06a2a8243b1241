#!/usr/bin/env python3
"""The performance study (analysis/mps_lab/studies/performance.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import performance  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=performance.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="runs/performance")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--only", nargs="+", choices=performance.PARTS,
                        help="parts to run (default: " + " ".join(performance.DEFAULT_PARTS) + ")")
    parser.add_argument("--max-fluid", type=float, default=1.1e6)
    parser.add_argument("--quick", action="store_true", help="tiny cases, for the tests")
    parser.add_argument("--docs", action="store_true", help="copy the results into docs/data and docs/figures")
    parser.add_argument("--timeout", type=float, default=performance.DEFAULT_TIMEOUT,
                        help="seconds before a run or bench is stopped")
    parser.add_argument("--plan", default=str(performance.DEFAULT_PLAN),
                        help="the runs, reference figures and bench settings (JSON)")
    parser.add_argument("--million-runs", nargs="+", metavar="RUN_DIR",
                        help="summarise these runs of scenes/dambreak_large.json as the million part (no run)")
    parser.add_argument("--side-by-side", nargs="+", metavar="CSV",
                        help="tools/reference-codes/side-by-side.sh CSVs for the targets against the reference codes")
    args = parser.parse_args(argv)
    return performance.performance(args.out, args.binary, args.only, args.max_fluid, args.quick, args.docs,
                                   args.timeout, args.plan, args.million_runs, args.side_by_side)


if __name__ == "__main__":
    sys.exit(main())
