#!/usr/bin/env python3
"""The stability map (analysis/mps_lab/studies/stability_map.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import stability_map  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=stability_map.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("spec", help="stability map specification (JSON)")
    parser.add_argument("--out", required=True, help="map folder")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--parallel", type=int, default=os.cpu_count() or 1, help="cases at a time")
    parser.add_argument("--timeout", type=float, default=stability_map.DEFAULT_TIMEOUT,
                        help="seconds before a case is stopped")
    parser.add_argument("--collect", action="store_true", help="only collect finished cases and plot")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--maps", help="run only these maps' cases (comma-separated; the others are collected)")
    parser.add_argument("--merge", help="an earlier stability.csv: its rows stand for the cases not finished in --out")
    args = parser.parse_args(argv)
    only = [name for name in args.maps.split(",") if name] if args.maps else None
    return stability_map.stability_map(args.spec, args.out, args.binary, args.parallel, args.timeout, args.collect,
                                       not args.no_plots, only, args.merge)


if __name__ == "__main__":
    sys.exit(main())
