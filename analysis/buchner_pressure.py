#!/usr/bin/env python3
"""Wall pressure against Buchner 2002 (analysis/mps_lab/studies/buchner.py): arguments only.

    /usr/bin/python3 analysis/buchner_pressure.py --out output/buchner [--collect] [--docs docs]
    /usr/bin/python3 analysis/buchner_pressure.py --out output/buchner_schemes --divisions 40 \
        --schemes analysis/sweeps/pressure_schemes.json     (one method, each pressure scheme)
"""
from __future__ import annotations

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.methods import registered_methods  # noqa: E402
from mps_lab.runner import find_binary  # noqa: E402
from mps_lab.studies import buchner  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=buchner.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder of the runs (OUT/H<n>/<method>)")
    parser.add_argument("--methods", nargs="+", help="methods (default: every registered one)")
    parser.add_argument("--divisions", nargs="+", type=int, default=list(buchner.DEFAULT_DIVISIONS),
                        help="n of l0 = H/n (default 40 60 80)")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--parallel", type=int, default=2, help="cases at a time (one thread each)")
    parser.add_argument("--timeout", type=float, default=buchner.DEFAULT_TIMEOUT, help="seconds before a case stops")
    parser.add_argument("--collect", action="store_true", help="only tabulate the runs that exist")
    parser.add_argument("--docs", help="write data/buchner_pressure.{csv,md} and figures/ here (default: OUT)")
    parser.add_argument("--schemes", help="a schemes plan (JSON with 'method' and 'schemes': name -> --set "
                                           "assignments): run its method once per scheme instead of --methods")
    args = parser.parse_args(argv)
    schemes = None
    if args.schemes:
        with open(args.schemes) as handle:
            schemes = json.load(handle)
        methods = [schemes["method"]]
    else:
        methods = args.methods or registered_methods(find_binary(args.binary))
    return buchner.study(args.out, methods, args.divisions, args.binary, args.parallel, args.timeout, args.collect,
                         args.docs, schemes)


if __name__ == "__main__":
    sys.exit(main())
