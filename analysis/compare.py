#!/usr/bin/env python3
"""Figures and a report comparing methods on one scene (analysis/mps_lab/report.py).

Called by `mps_lab compare` (app/commands.cpp) as `compare.py RUNS_FOLDER [--quiet]`."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import report  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=report.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("root", help="folder with one run folder per method (what mps_lab compare writes)")
    parser.add_argument("--runs", nargs="+", help="run folders to compare instead of the root's sub-folders")
    parser.add_argument("--times", nargs="+", type=float, default=report.DEFAULT_TIMES, help="snapshot times [s]")
    parser.add_argument("--no-animation", action="store_true", help="skip the animation")
    parser.add_argument("--binary", help="mps_lab binary whose methods fix the colours")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    return report.compare(args.root, args.runs, args.times, animation=not args.no_animation, quiet=args.quiet,
                          binary=args.binary)


if __name__ == "__main__":
    sys.exit(main())
