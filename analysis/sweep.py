#!/usr/bin/env python3
"""The speed-accuracy study (analysis/mps_lab/studies/sweep.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import sweep  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=sweep.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("spec", help="sweep specification (JSON)")
    parser.add_argument("--out", required=True, help="sweep folder")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--parallel", type=int, default=os.cpu_count() or 1, help="cases at a time")
    parser.add_argument("--timeout", type=float, default=sweep.DEFAULT_TIMEOUT, help="seconds before a case is stopped")
    parser.add_argument("--jobs-file", help="write the job list (one command per line) and stop")
    parser.add_argument("--collect", action="store_true", help="only collect finished cases and plot")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--methods", help="run only these methods' cases (comma-separated; the others are collected)")
    parser.add_argument("--merge", help="an earlier sweep.csv: its rows stand for the cases not finished in --out")
    parser.add_argument("--threads", type=int, help="OpenMP threads per case (default: cores / parallel)")
    args = parser.parse_args(argv)
    only = [m for m in args.methods.split(",") if m] if args.methods else None
    return sweep.sweep(args.spec, args.out, args.binary, args.parallel, args.timeout, args.jobs_file, args.collect,
                       not args.no_plots, only, args.merge, args.threads)


if __name__ == "__main__":
    sys.exit(main())
