#!/usr/bin/env python3
"""The solver comparison's table (analysis/mps_lab/studies/solver_comparison.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import solver_comparison  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=solver_comparison.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("inputs", nargs="+", type=Path, help="JSON files of build/mps_lab_solver_bench")
    parser.add_argument("--out", type=Path, required=True, help="the Markdown table")
    args = parser.parse_args(argv)
    sys.stdout.write(solver_comparison.write_table(args.inputs, args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
