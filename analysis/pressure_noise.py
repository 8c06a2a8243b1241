#!/usr/bin/env python3
"""Pressure noise, front and height of dam-break runs (analysis/mps_lab/studies/pressure_noise.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import pressure_noise  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=pressure_noise.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", help="run folders (run.json, series.csv)")
    parser.add_argument("--sensor", default="right_wall_bottom", help="pressure sensor of the scene")
    parser.add_argument("--average", type=float, default=0.005, help="width of the moving mean, s")
    parser.add_argument("--window", type=float, nargs=2, action="append", metavar=("FROM", "TO"),
                        help="time window of the noise, s (repeatable; default 0-2 and 1-2)")
    args = parser.parse_args(argv)
    windows = [tuple(w) for w in args.window] if args.window else pressure_noise.DEFAULT_WINDOWS
    print(pressure_noise.pressure_noise(args.folders, args.sensor, windows, args.average), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
