"""Reading mps_lab run folders and the validation data, with the testbed's conventions.

A run folder holds run.json (what was run, the column a x H as the particles represent it),
series.csv (one row every output.series_every_steps steps) and the frames. Martin & Moyce
(1952) variables, for a column of width a and height H = n^2 a:

    surge front      Z  = front / a   against  T   = n t sqrt(g/a) = t sqrt(g H) / a
    residual height  H* = height / H  against  tau = t sqrt(g/a)

The same definitions are in lab/validation.hpp; docs/validation.md explains them.
"""
from __future__ import annotations

import csv
import json
import math
import os
from dataclasses import dataclass

import numpy as np

from . import ANALYSIS_DIR

VALIDATION_DIR = os.path.join(ANALYSIS_DIR, "validation")


def read_csv_columns(path: str) -> dict[str, np.ndarray]:
    """A CSV with a header (comment lines starting with '#' skipped) as named float columns."""
    with open(path, newline="") as handle:
        rows = [row for row in csv.reader(line for line in handle if not line.startswith("#"))]
    header, body = rows[0], rows[1:]
    data = np.array([[float(cell) for cell in row] for row in body], dtype=float).reshape(len(body), len(header))
    return {name: data[:, k] for k, name in enumerate(header)}


@dataclass
class Run:
    folder: str
    summary: dict
    series: dict[str, np.ndarray]

    @property
    def method(self) -> str:
        return self.summary["method"]

    @property
    def column_width(self) -> float:  # a, m
        return float(self.summary["column"]["width"])

    @property
    def column_height(self) -> float:  # H, m
        return float(self.summary["column"]["height"])

    @property
    def gravity(self) -> float:  # |g|, m/s^2
        gx, gy = self.summary["shared"]["gravity"]
        return math.hypot(gx, gy)

    def front_curve(self) -> tuple[np.ndarray, np.ndarray]:
        """(T, Z) of the surge front."""
        a, h, g = self.column_width, self.column_height, self.gravity
        return self.series["time"] * math.sqrt(g * h) / a, self.series["front"] / a

    def height_curve(self) -> tuple[np.ndarray, np.ndarray]:
        """(tau, H*) of the residual height at the back wall."""
        a, h, g = self.column_width, self.column_height, self.gravity
        return self.series["time"] * math.sqrt(g / a), self.series["height"] / h

    def frames(self) -> list[tuple[int, str]]:
        """(step, path) of the CSV frames, in step order."""
        names = sorted(n for n in os.listdir(self.folder) if n.startswith("output_") and n.endswith(".csv"))
        return [(int(n[len("output_"):-len(".csv")]), os.path.join(self.folder, n)) for n in names]


def load_run(folder: str) -> Run:
    with open(os.path.join(folder, "run.json")) as handle:
        summary = json.load(handle)
    return Run(folder, summary, read_csv_columns(os.path.join(folder, "series.csv")))


def martin_moyce_front() -> tuple[np.ndarray, np.ndarray]:
    """Martin & Moyce (1952) Table 2, n^2 = 2: (T, Z)."""
    data = read_csv_columns(os.path.join(VALIDATION_DIR, "martin_moyce_1952_n2_front.csv"))
    return data["T_n_t_sqrt_g_over_a"], data["Z_x_over_a"]


def martin_moyce_height() -> tuple[np.ndarray, np.ndarray]:
    """Martin & Moyce (1952) Table 6, n^2 = 2: (tau, H*)."""
    data = read_csv_columns(os.path.join(VALIDATION_DIR, "martin_moyce_1952_n2_height.csv"))
    return data["tau_t_sqrt_g_over_a"], data["H_h_over_n2a"]


def curve_error(sim_x, sim_y, exp_x, exp_y, shift: float = 0.0) -> tuple[float, float, int]:
    """(RMS, max, points) of sim - experiment at the experiment's x, sim evaluated at x - shift.

    Points outside the simulated range are skipped (same rule as lab/validation.cpp)."""
    sim_x, sim_y = np.asarray(sim_x), np.asarray(sim_y)
    x = np.asarray(exp_x) - shift
    inside = (x >= sim_x[0]) & (x <= sim_x[-1])
    if not inside.any():
        return math.nan, math.nan, 0
    difference = np.interp(x[inside], sim_x, sim_y) - np.asarray(exp_y)[inside]
    return float(np.sqrt(np.mean(difference ** 2))), float(np.max(np.abs(difference))), int(inside.sum())


def best_shift_error(sim_x, sim_y, exp_x, exp_y, max_shift: float = 0.3, resolution: float = 0.001):
    """(RMS, max, points, shift) minimising RMS over shifts in [-max_shift, max_shift] that keep
    every point of the unshifted comparison."""
    best = (*curve_error(sim_x, sim_y, exp_x, exp_y), 0.0)
    steps = int(round(max_shift / resolution))
    for k in range(-steps, steps + 1):
        shift = k * resolution
        rms, largest, points = curve_error(sim_x, sim_y, exp_x, exp_y, shift)
        if points == best[2] and rms < best[0]:
            best = (rms, largest, points, shift)
    return best


def front_errors(run) -> dict:
    """front_rms, front_rms_shifted and front_best_shift of a run against Martin & Moyce
    (empty when no experimental point falls in the simulated time)."""
    exp_t, exp_z = martin_moyce_front()
    t, z = run.front_curve()
    rms, _, points = curve_error(t, z, exp_t, exp_z)
    if not points:
        return {}
    shifted = best_shift_error(t, z, exp_t, exp_z)
    return {"front_rms": rms, "front_rms_shifted": shifted[0], "front_best_shift": shifted[3]}
