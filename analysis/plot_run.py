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
import figures  # noqa: E402
import mps_lab_data as data  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="run folders (each with run.json and series.csv)")
    parser.add_argument("--out", help="folder for the figures (default: the first run folder)")
    args = parser.parse_args(argv)
    runs = []
    for folder in args.runs:
        try:
            runs.append(data.load_run(folder))
        except (OSError, KeyError, ValueError) as error:
            print(f"plot_run.py: {folder}: not a readable run folder ({error})", file=sys.stderr)
            return 2
    out = args.out or args.runs[0]
    os.makedirs(out, exist_ok=True)
    figures.plot_front(runs, os.path.join(out, "front.png"))
    figures.plot_height(runs, os.path.join(out, "height.png"))
    exp_t, exp_z = data.martin_moyce_front()
    for run in runs:
        t, z = run.front_curve()
        rms, largest, points = data.curve_error(t, z, exp_t, exp_z)
        shifted = data.best_shift_error(t, z, exp_t, exp_z)
        print(f"{run.folder}: front RMS {rms:.3f} (max {largest:.3f}, {points} points); "
              f"best shift {shifted[3]:+.3f} -> RMS {shifted[0]:.3f}")
    print(f"figures: {os.path.join(out, 'front.png')}, {os.path.join(out, 'height.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
