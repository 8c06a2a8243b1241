#!/usr/bin/env python3
"""The pressure schemes of a method, measured (docs/methods/mps.md, "Pressure schemes").

    /usr/bin/python3 analysis/pressure_schemes.py analysis/sweeps/pressure_schemes.json \\
        --out runs/pressure_schemes [--table docs/data/pressure_schemes.csv] [--parallel 2]

For every case of the plan (a scene with overrides) and every scheme (a list of --set
assignments) it runs the plan's method through the package's case runner with a pressure
sensor on the bed and a series row every step, then reads the run folder with the package:

  noise_pa        RMS of p - its centred moving mean over `noise_window` (5 ms) at the sensor
                  (the column pressure_<sensor>), over the whole run (dam break) or after
                  `settled_after` (still water)
  mean_pa         the sensor's mean over the same rows
  error           still water: mean_pa / (rho g (H - y)) - 1, H the water surface
                  (bed surface l0/2 + the column height of run.json), y the sensor height
  kinetic_energy  still water: mean kinetic energy after settling, J/m
  front_rms ...   dam break: the front against Martin & Moyce (mps_lab.data.front_errors)

and writes one CSV row per run (--table) and a Markdown table beside it.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mps_lab import data, runner  # noqa: E402

COLUMNS = ["case", "scheme", "status", "steps", "mean_iterations", "ghosts", "noise_pa", "mean_pa", "error",
           "kinetic_energy", "front_rms", "front_rms_shifted", "front_best_shift"]


def moving_mean_noise(time: np.ndarray, pressure: np.ndarray, window: float, start: float) -> tuple[float, float]:
    """(RMS of p - centred moving mean over `window`, mean of p) over rows with time >= start whose
    whole window lies inside the series. Rows are assumed evenly spaced (one per step)."""
    if len(time) < 3:
        return math.nan, math.nan
    step = float(np.median(np.diff(time)))
    half = max(1, int(round(window / step / 2.0)))
    kernel = np.ones(2 * half + 1) / (2 * half + 1)
    smooth = np.convolve(pressure, kernel, mode="same")
    inside = np.zeros(len(time), dtype=bool)
    inside[half:len(time) - half] = True
    inside &= time >= start
    if not inside.any():
        return math.nan, math.nan
    residual = pressure[inside] - smooth[inside]
    return float(np.sqrt(np.mean(residual ** 2))), float(np.mean(pressure[inside]))


def case_arguments(plan: dict, case: dict, assignments: list[str], folder: str) -> list[str]:
    sensor = plan["sensor"]
    sensors = [{"name": sensor["name"], "position": [case["sensor_x"], sensor["height"]]}]
    arguments = ["run", f"--method={plan['method']}", case["scene"], "--out", folder,
                 "--set", "output.series_every_steps=1", "--set", "output.series_interval=0",
                 "--set", "output.frame_every_steps=1000000",
                 "--set", "diagnostics.pressure_sensors=" + json.dumps(sensors, separators=(",", ":"))]
    for assignment in case.get("overrides", []) + assignments:
        arguments += ["--set", assignment]
    return arguments


def measure(plan: dict, case: dict, scheme: str, folder: str, status: str) -> dict:
    row = {key: "" for key in COLUMNS}
    row.update(case=case["name"], scheme=scheme, status=status)
    if not os.path.exists(os.path.join(folder, "series.csv")):
        return row
    run = data.load_run(folder)
    series = run.series
    pressure = series["pressure_" + plan["sensor"]["name"]]
    settled = case.get("settled_after", 0.0)
    noise, mean = moving_mean_noise(series["time"], pressure, plan["noise_window"], settled)
    row.update(steps=int(series["step"][-1]), mean_iterations=f"{np.mean(series['solver_iterations']):.1f}",
               ghosts=int(series["ghost_particles"][-1]), noise_pa=f"{noise:.1f}", mean_pa=f"{mean:.1f}")
    if case["kind"] == "hydrostatic":
        spacing = float(run.summary["shared"]["particle_spacing"])
        surface = spacing / 2.0 + run.column_height
        # A wall transducer reads at the wall surface (core/run/pressure_sensors.hpp): a sensor
        # placed on the bed's wall line (height 0) sits l0/2 higher, on the bed surface.
        sensor_height = max(plan["sensor"]["height"], spacing / 2.0)
        expected = float(run.summary["shared"]["density"]) * run.gravity * (surface - sensor_height)
        kinetic = series["kinetic_energy"][series["time"] >= settled]
        row.update(error=f"{mean / expected - 1.0:+.3f}", kinetic_energy=f"{np.mean(kinetic):.2f}")
    else:
        errors = data.front_errors(run)
        row.update(front_rms=f"{errors.get('front_rms', math.nan):.3f}",
                   front_rms_shifted=f"{errors.get('front_rms_shifted', math.nan):.3f}",
                   front_best_shift=f"{errors.get('front_best_shift', math.nan):+.3f}")
    return row


def markdown(rows: list[dict]) -> str:
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(str(row[key]) for key in COLUMNS) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("plan", help="the study plan (JSON), e.g. analysis/sweeps/pressure_schemes.json")
    parser.add_argument("--out", required=True, help="folder for the run folders")
    parser.add_argument("--table", help="CSV to write (default: OUT/pressure_schemes.csv); a .md beside it")
    parser.add_argument("--binary", help="mps_lab binary (default: $MPS_LAB_BINARY, else build/mps_lab, else PATH)")
    parser.add_argument("--parallel", type=int, default=1, help="runs at a time")
    parser.add_argument("--timeout", type=float, default=1800.0, help="seconds before a run is stopped")
    parser.add_argument("--only", action="append", help="only these schemes (repeatable)")
    args = parser.parse_args(argv)
    with open(args.plan) as handle:
        plan = json.load(handle)
    root = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    binary = runner.find_binary(args.binary)
    requests = []
    for case in plan["cases"]:
        case = dict(case, scene=os.path.join(root, case["scene"]))
        for scheme, assignments in plan["schemes"].items():
            if args.only and scheme not in args.only:
                continue
            folder = os.path.join(args.out, case["name"], scheme)
            requests.append(runner.CaseRequest(f"{case['name']}/{scheme}", case_arguments(plan, case, assignments,
                                                                                        folder), folder,
                                               {"case": case, "scheme": scheme}))
    rows = []
    for request, result in runner.run_cases(binary, requests, parallel=args.parallel, timeout=args.timeout,
                                            threads=1):
        status = "completed" if result.ok else result.describe()
        if os.path.exists(os.path.join(request.folder, "run.json")):
            with open(os.path.join(request.folder, "run.json")) as handle:
                status = json.load(handle).get("status", status)
        rows.append(measure(plan, request.extra["case"], request.extra["scheme"], request.folder, status))
        print(f"{request.name}: {status}", flush=True)
    order = {(c["name"], s): k for k, (c, s) in enumerate((c, s) for c in plan["cases"] for s in plan["schemes"])}
    rows.sort(key=lambda row: order[(row["case"], row["scheme"])])
    table = args.table or os.path.join(args.out, "pressure_schemes.csv")
    os.makedirs(os.path.dirname(os.path.abspath(table)), exist_ok=True)
    with open(table, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.splitext(table)[0] + ".md", "w") as handle:
        handle.write(markdown(rows))
    print(markdown(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
