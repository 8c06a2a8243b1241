"""Wall pressure against an experimental record: impact time, peak and quasi-static error.

A scene that has pressure sensors may name an experiment for them in its `validation` block
(docs/scene-format.md); mps_lab checks the block and writes it to run.json with the records'
resolved paths ("validation"). Variables (H = validation.length_scale, g = |gravity|,
rho = physics.density):

    T = t sqrt(g/H)                 p* = p / (rho g H)

Definitions, the same for a run and for the experiment (docs/validation.md, "Wall pressure:
Buchner 2002"):

    impact time      the first T at which p* reaches `impact_threshold` (0.1), linearly
                     interpolated between the two samples around the crossing; a run's samples
                     are its series rows (the mean of the steps since the previous row)
    peak             the largest p* from the impact time to the end of the quasi-static window
                     T1: for a run both the per-step peak (pressure_<name>_max) and the
                     largest row mean, which is what a digitised, filtered record compares with
    quasi-static     over T in [T0, T1] (`quasi_static`, [3, 5.5]: after the impact, before the
                     plunging jet's return): the RMS of p*_run - p*_experiment at the
                     experiment's points (the run interpolated there), and both mean levels
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass

import numpy as np

from . import data


@dataclass
class Validation:
    """The `validation` block of a scene: the variables and the records, sensor -> file."""
    length_scale: float
    impact_threshold: float
    quasi_static: tuple[float, float]
    records: dict[str, str]


def validation_from_json(block: dict, base: str = "") -> Validation:
    """From run.json's "validation" (absolute paths) or a scene's block (paths relative to base)."""
    records = {r["sensor"]: os.path.normpath(os.path.join(base, r["file"])) for r in block.get("pressure_records", [])}
    window = block.get("quasi_static", [3.0, 5.5])
    return Validation(float(block["length_scale"]), float(block.get("impact_threshold", 0.1)),
                      (float(window[0]), float(window[1])), records)


def scene_validation(scene_path: str) -> Validation | None:
    """The validation block of a scene file, None without one."""
    with open(scene_path) as handle:
        scene = json.load(handle)
    block = scene.get("validation")
    return validation_from_json(block, os.path.dirname(os.path.abspath(scene_path))) if block else None


def run_validation(run: data.Run) -> Validation | None:
    block = run.summary.get("validation")
    return validation_from_json(block) if block else None


def read_record(path: str) -> tuple[np.ndarray, np.ndarray]:
    """(T, p*) of an experimental record: a CSV with '#' comment lines, a header, two columns."""
    columns = list(data.read_csv_columns(path).values())
    return columns[0], columns[1]


def crossing_time(t: np.ndarray, p: np.ndarray, threshold: float) -> float:
    """The first t at which p reaches threshold, linear between samples; NaN if never."""
    above = np.nonzero(p >= threshold)[0]
    if above.size == 0:
        return math.nan
    k = int(above[0])
    if k == 0:
        return float(t[0])
    fraction = (threshold - p[k - 1]) / (p[k] - p[k - 1])
    return float(t[k - 1] + fraction * (t[k] - t[k - 1]))


def window_max(t: np.ndarray, p: np.ndarray, start: float, end: float) -> float:
    inside = (t >= start) & (t <= end)
    return float(np.max(p[inside])) if inside.any() and not math.isnan(start) else math.nan


def run_curves(run: data.Run, sensor: str, validation: Validation) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(T, p* row mean, p* per-step peak) of a run's sensor."""
    scale = float(run.summary["shared"]["density"]) * run.gravity * validation.length_scale  # rho g H, Pa
    time = run.series["time"] * math.sqrt(run.gravity / validation.length_scale)
    return time, run.series["pressure_" + sensor] / scale, run.series["pressure_" + sensor + "_max"] / scale


def record_measures(t: np.ndarray, p: np.ndarray, validation: Validation) -> dict:
    """impact_time and peak of an experimental record (its samples are its only peak)."""
    impact = crossing_time(t, p, validation.impact_threshold)
    return {"impact_time": impact, "peak": window_max(t, p, impact, validation.quasi_static[1])}


def sensor_measures(run: data.Run, sensor: str, validation: Validation) -> dict:
    """The run's impact time, peaks and quasi-static level at one sensor, and its errors
    against the sensor's record when the validation names one."""
    t, mean, peak = run_curves(run, sensor, validation)
    impact = crossing_time(t, mean, validation.impact_threshold)
    start, end = validation.quasi_static
    quiet = (t >= start) & (t <= end)
    result = {"impact_time": impact, "peak_step": window_max(t, peak, impact, end),
              "peak_row": window_max(t, mean, impact, end),
              "quasi_static_level": float(np.mean(mean[quiet])) if quiet.any() else math.nan}
    if sensor not in validation.records:
        return result
    exp_t, exp_p = read_record(validation.records[sensor])
    measured = record_measures(exp_t, exp_p, validation)
    in_window = (exp_t >= start) & (exp_t <= end) & (exp_t <= t[-1])
    difference = np.interp(exp_t[in_window], t, mean) - exp_p[in_window]
    result.update({
        "exp_impact_time": measured["impact_time"], "exp_peak": measured["peak"],
        "exp_quasi_static_level": float(np.mean(exp_p[in_window])) if in_window.any() else math.nan,
        "impact_time_error": impact - measured["impact_time"],
        "peak_step_error": result["peak_step"] - measured["peak"],
        "peak_row_error": result["peak_row"] - measured["peak"],
        "quasi_static_rms": float(np.sqrt(np.mean(difference ** 2))) if in_window.any() else math.nan,
        "quasi_static_points": int(in_window.sum()),
    })
    return result


def pressure_errors(run: data.Run) -> dict:
    """Flat columns for a sweep or a summary: <sensor>_<measure> for every sensor the run's
    validation names a record for; empty without a validation block."""
    validation = run_validation(run)
    if validation is None:
        return {}
    columns = {}
    for sensor in validation.records:
        if "pressure_" + sensor in run.series:
            for key, value in sensor_measures(run, sensor, validation).items():
                columns[f"{sensor}_{key}"] = value
    return columns
