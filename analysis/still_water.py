#!/usr/bin/env python3
"""Still water at the wall sensors (analysis/mps_lab/studies/still_water.py): arguments only."""
from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import methods, runner  # noqa: E402
from mps_lab.studies import still_water  # noqa: E402
from mps_lab.studies.common import SpecError  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=still_water.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join("runs", "still_water"), help="study folder")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--methods", nargs="+", help="methods (default: every one `mps_lab methods` lists)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene override after the load setting and the model (repeatable)")
    parser.add_argument("--models", nargs="+", metavar="MODEL",
                        help="boundary models (default: every one each method supports)")
    parser.add_argument("--model-set", dest="model_settings", action="append", default=[],
                        metavar="MODEL.KEY=VALUE", help="an option of a boundary model, VALUE as JSON, e.g. "
                        "distance_function.velocity='\"free_slip\"' (repeatable)")
    parser.add_argument("--defaults", action="store_true", help="without the methods' load settings")
    parser.add_argument("--realisations", type=int, default=1,
                        help="runs per case, gravity scaled by 1 + k 1e-10 (2 or more: each sensor's expected "
                             "reading, mean ± standard error, and its verdict on 1 %%)")
    parser.add_argument("--end-time", type=float, default=3.0, help="s (the load-setting test's 3 s)")
    parser.add_argument("--window", type=float, nargs=2, default=(0.5, 3.0), metavar=("FROM", "TO"),
                        help="s, the window of the sensors' means (the load-setting test's [0.5, 3])")
    parser.add_argument("--spacing", type=float, nargs="+", metavar="L0",
                        help="m, the tank at these particle spacings (the scene's time step and each method's "
                             "max_time_step scaled with it; two or more: a resolution table and figure)")
    parser.add_argument("--parallel", type=int, default=os.cpu_count() or 1, help="cases at a time")
    args = parser.parse_args(argv)
    if args.realisations < 1:
        parser.error("--realisations: expected an integer >= 1")
    if args.spacing is not None and not all(0.0 < spacing <= 0.05 for spacing in args.spacing):
        parser.error("--spacing: expected a particle spacing in (0, 0.05] m (the tank is 0.5 m wide)")
    if args.spacing is not None and len(set(args.spacing)) != len(args.spacing):
        parser.error("--spacing: expected distinct particle spacings")
    if not 0.0 <= args.window[0] < args.window[1] <= args.end_time:
        parser.error("--window: expected 0 <= FROM < TO <= --end-time")
    try:
        model_options = still_water.parse_model_options(args.model_settings)
        markdown, rows = still_water.still_water(args.out, runner.find_binary(args.binary), args.methods,
                                                 args.realisations, args.end_time, tuple(args.window),
                                                 not args.defaults, args.overrides, max(1, args.parallel),
                                                 spacings=args.spacing, models=args.models,
                                                 model_options=model_options)
    except (runner.BinaryNotFound, methods.MethodListError, SpecError) as error:
        print(f"still_water.py: {error}", file=sys.stderr)
        return 2
    print(markdown, end="")
    return 0 if all(row["status"] == "completed" for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
