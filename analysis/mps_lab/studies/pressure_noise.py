"""Pressure noise, front and residual height of finished dam-break runs, one row per run
(docs/speed-vs-accuracy.md, "When the explicit methods win").

    mps_lab compare scenes/dambreak.json --out runs/noise --end-time 2 --set output.series_every_steps=1
    /usr/bin/python3 analysis/pressure_noise.py runs/noise/*/ --sensor right_wall_bottom

For each run folder: the method, l0, steps, the surge front against Martin & Moyce (RMS,
best time shift and RMS after it: mps_lab.data.front_errors), the residual height's RMS
against Table 6, and at the pressure sensor (series.csv column pressure_<sensor>) the
noise = RMS of p minus its centred moving mean over --average (5 ms) seconds, over each
--window, with the mean of p there. The moving mean and the RMS weigh time, not samples
(studies/wall_study.sensor_noise), so adaptive steps and fixed steps compare; write the
series every step (output.series_every_steps = 1), or the window holds too few samples.
"""
from __future__ import annotations

import math

import numpy as np

from .. import data
from .wall_study import sensor_noise

DEFAULT_WINDOWS = ((0.0, 2.0), (1.0, 2.0))  # s: the whole run; the quasi-static phase after the slosh


def height_rms(run: data.Run) -> float:
    """RMS of H*(tau) - Martin & Moyce's Table 6 over the simulated range."""
    exp_tau, exp_h = data.martin_moyce_height()
    tau, height = run.height_curve()
    return data.curve_error(tau, height, exp_tau, exp_h)[0]


def row_of(folder: str, sensor: str, windows, average: float) -> dict:
    run = data.load_run(folder)
    summary = run.summary
    row = {"folder": folder, "method": run.method, "status": summary.get("status", ""),
           "l0": summary.get("scene_resolved", {}).get("particle_spacing", math.nan), "steps": summary.get("steps", 0),
           "simulated_time": summary.get("simulated_time", math.nan), "height_rms": height_rms(run)}
    row.update({"front_rms": math.nan, "front_rms_shifted": math.nan, "front_best_shift": math.nan})
    row.update(data.front_errors(run))
    t, p = run.series["time"], run.series.get(f"pressure_{sensor}")
    for start, end in windows:
        key = f"{start:g}-{end:g}s"
        inside = (t >= start) & (t <= end)
        row[f"noise_pa_{key}"] = sensor_noise(t, p, (start, end), average) if p is not None else math.nan
        row[f"mean_pa_{key}"] = float(np.mean(p[inside])) if p is not None and inside.any() else math.nan
    return row


def markdown(rows: list[dict], windows) -> str:
    keys = [f"{a:g}-{b:g}s" for a, b in windows]
    header = ("| method | l0 [m] | status | steps | front RMS | best shift -> RMS | height RMS | "
              + " | ".join(f"noise {k} [Pa] (mean)" for k in keys) + " |")
    lines = [header, "|" + "---|" * (7 + len(keys))]
    for r in rows:
        noise = " | ".join(f"{r[f'noise_pa_{k}']:.0f} ({r[f'mean_pa_{k}']:.0f})" for k in keys)
        lines.append(f"| {r['method']} | {r['l0']:g} | {r['status']} | {r['steps']} | {r['front_rms']:.3f} "
                     f"| {r['front_best_shift']:+.3f} -> {r['front_rms_shifted']:.3f} | {r['height_rms']:.3f} | {noise} |")
    return "\n".join(lines) + "\n"


def pressure_noise(folders: list[str], sensor: str = "right_wall_bottom", windows=DEFAULT_WINDOWS,
                   average: float = 0.005) -> str:
    rows = [row_of(folder, sensor, windows, average) for folder in folders]
    return markdown(rows, windows)
