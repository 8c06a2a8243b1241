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

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mps_lab_data as data  # noqa: E402

plt.rcParams.update({"font.size": 11, "axes.grid": True, "grid.alpha": 0.3, "savefig.dpi": 150})


def label_of(run: data.Run) -> str:
    return f"{run.method} (l0 = {run.summary['shared']['particle_spacing']:g} m)"


def plot_front(runs: list[data.Run], path: str) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    exp_t, exp_z = data.martin_moyce_front()
    for run in runs:
        t, z = run.front_curve()
        rms, largest, _ = data.curve_error(t, z, exp_t, exp_z)
        ax.plot(t, z, label=f"{label_of(run)}: RMS {rms:.3f}")
    ax.plot(exp_t, exp_z, "ko", mfc="none", label="Martin & Moyce (1952), $n^2 = 2$")
    ax.set_xlabel(r"$T = n\,t\,\sqrt{g/a}$")
    ax.set_ylabel(r"$Z = z/a$ (surge front)")
    ax.set_xlim(0, 4.0)
    ax.set_ylim(1, 4.6)
    ax.legend(loc="upper left", fontsize=9)
    ax.set_title("Dam break: surge front")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_height(runs: list[data.Run], path: str) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    exp_tau, exp_h = data.martin_moyce_height()
    for run in runs:
        tau, h = run.height_curve()
        rms, _, _ = data.curve_error(tau, h, exp_tau, exp_h)
        ax.plot(tau, h, label=f"{label_of(run)}: RMS {rms:.3f}")
    ax.plot(exp_tau, exp_h, "ks", mfc="none", label="Martin & Moyce (1952), $n^2 = 2$")
    ax.set_xlabel(r"$\tau = t\,\sqrt{g/a}$")
    ax.set_ylabel(r"$H^* = h/(n^2 a)$ (residual height)")
    ax.set_xlim(0, 8.0)
    ax.set_ylim(0, 1.05)
    ax.legend(loc="upper right", fontsize=9)
    ax.set_title("Dam break: residual column height")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


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
    plot_front(runs, os.path.join(out, "front.png"))
    plot_height(runs, os.path.join(out, "height.png"))
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
