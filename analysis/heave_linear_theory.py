#!/usr/bin/env python3
"""The floating box's heave by linear potential flow, against the particle runs (docs/bodies.md,
"Linear theory"; issue 15, item 4).

    /usr/bin/python3 analysis/heave_linear_theory.py [--heave-csv docs/data/floating_box_heave.csv] [--out docs]

For every spacing of the floating study's table (analysis/floating_bodies.py) it solves the box's
heave radiation problem in open water of the run's depth (analysis/mps_lab/radiation.py: panels,
the natural period with the added mass at its own frequency, the radiation damping) and its linear
free decay in the run's tank, fitted as the runs are; writes OUT/data/heave_linear_theory.csv and
.md (the references, and each run's period and damping against the tank's) and
OUT/figures/heave_linear_theory.png (the tank's decay curves).
"""
from __future__ import annotations

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab.studies import common, floating, heave_theory  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--heave-csv", default=os.path.join(root, "docs", "data", "floating_box_heave.csv"),
                        help="the floating study's heave table")
    parser.add_argument("--scene", default=os.path.join(root, "scenes", "floating_box_heave.json"))
    parser.add_argument("--out", default=os.path.join(root, "docs"), help="folder for data/ and figures/")
    args = parser.parse_args(argv)
    with open(args.scene) as handle:
        geometry = floating.scene_geometry(json.load(handle))
    references, comparison = heave_theory.compare(geometry, heave_theory.read_heave_rows(args.heave_csv))
    figure = common.write_study_tables(args.out, "heave_linear_theory", references, heave_theory.COLUMNS,
                                       heave_theory.markdown(references, comparison))
    common.write_csv(comparison, heave_theory.COMPARISON_COLUMNS,
                     os.path.join(args.out, "data", "heave_vs_linear_theory.csv"))
    plot(geometry, references, figure)
    print(heave_theory.markdown(references, comparison), end="")
    return 0


def plot(geometry: dict, references: list[dict], path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(6.5, 3.2))
    for l0, (t, x) in heave_theory.decay_curves(geometry, references).items():
        axes.plot(t, 1000 * x, label=f"linear theory in the tank, depth and release of l0 = {l0:g} m")
    axes.axvspan(0.0, floating.HEAVE_FIT_END, color="0.92", zorder=0)
    axes.set_xlabel("t, s")
    axes.set_ylabel("box centre - rest, mm (fit: grey)")
    axes.legend(fontsize=6)
    figure.tight_layout()
    figure.savefig(path, dpi=150)
    plt.close(figure)


if __name__ == "__main__":
    sys.exit(main())
