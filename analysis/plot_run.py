#!/usr/bin/env python3
"""Plot one or more mps_lab run folders against Martin & Moyce (1952).

    /usr/bin/python3 analysis/plot_run.py RUN_FOLDER [RUN_FOLDER ...] [--out DIR]

Writes front.png (surge front Z against T) and height.png (residual height H* against tau)
into the first run folder (or --out), and prints the RMS errors against the experiment.
"""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import report  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="run folders (each with run.json and series.csv)")
    parser.add_argument("--out", help="folder for the figures (default: the first run folder)")
    parser.add_argument("--binary", help="mps_lab binary whose methods fix the colours")
    args = parser.parse_args(argv)
    return report.plot_runs(args.runs, args.out or args.runs[0], args.binary)


if __name__ == "__main__":
    sys.exit(main())
