#!/usr/bin/env python3
"""The wall study (analysis/mps_lab/studies/wall_study.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import wall_study  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=wall_study.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join("runs", "wall_study"), help="study folder")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--methods", nargs="+", help="methods (default: every one `mps_lab methods` lists)")
    parser.add_argument("--models", nargs="+",
                        help="boundary models; default = each method's own, NAME:key=value[,key=value] a variant of NAME "
                             "(default: default and every other)")
    parser.add_argument("--scenes", nargs="+", default=list(wall_study.SCENES), choices=list(wall_study.SCENES))
    parser.add_argument("--parallel", type=int, default=os.cpu_count() or 1, help="cases at a time")
    parser.add_argument("--timeout", type=float, default=wall_study.DEFAULT_TIMEOUT,
                        help="seconds before a case is stopped")
    parser.add_argument("--collect", action="store_true", help="only collect finished cases and plot")
    parser.add_argument("--quick", action="store_true", help="short end times (for tests)")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--merge", help="an earlier wall_study.csv: its rows of cases not in this study are kept")
    args = parser.parse_args(argv)
    return wall_study.wall_study(args.out, args.binary, args.methods, args.models, args.scenes, args.parallel,
                                 args.timeout, args.collect, args.quick, not args.no_plots, args.merge)


if __name__ == "__main__":
    sys.exit(main())
