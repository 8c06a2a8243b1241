"""The sweep's pressure-error axis (analysis/mps_lab/studies/sweep.py): for a scene whose
`validation` block names experimental pressure records (scenes/dambreak_buchner.json), each
completed case gets, per sensor with a record, the columns

    <sensor>_quasi_static_rms    RMS of p*_run - p*_experiment over the quasi-static window
    <sensor>_peak_row_error      largest row mean from the impact to T1, minus the experiment's peak
    <sensor>_peak_step_error     the same with the per-step peak (pressure_<sensor>_max)
    <sensor>_impact_time_error   impact time of the run minus the experiment's (T units)

(definitions: analysis/mps_lab/pressure.py), and pressure_pareto.png plots cost against the
quasi-static RMS and the absolute row-peak error of the first sensor, Pareto front marked.
A scene without a record adds nothing."""
from __future__ import annotations

import math

from .. import data, pressure

MEASURES = ("quasi_static_rms", "peak_row_error", "peak_step_error", "impact_time_error")


def split_key(key: str) -> tuple[str, str] | None:
    """("P1", "quasi_static_rms") of "P1_quasi_static_rms"; None for any other column (sensor
    names may hold underscores: the measure is matched at the end)."""
    for name in MEASURES:
        if key.endswith("_" + name) and len(key) > len(name) + 1:
            return key[:-len(name) - 1], name
    return None


def measure(run: data.Run) -> dict:
    """The pressure columns of one completed run (empty without a validation block)."""
    return {key: value for key, value in pressure.pressure_errors(run).items() if split_key(key)}


def columns(rows: list[dict]) -> list[str]:
    """The pressure columns present in any row, sensor by sensor in the order of MEASURES."""
    sensors = []
    for row in rows:
        for key in row:
            parts = split_key(key)
            if parts and parts[0] not in sensors:
                sensors.append(parts[0])
    return [f"{sensor}_{m}" for sensor in sensors for m in MEASURES]


def plot(rows: list[dict], path: str, styles, pareto_front) -> bool:
    """Wall time against the first sensor's quasi-static RMS and |row-peak error|; False when no
    row has them."""
    keys = columns(rows)
    if not keys:
        return False
    import matplotlib.pyplot as plt

    sensor = split_key(keys[0])[0]
    done = [r for r in rows if r.get("status") == "completed" and math.isfinite(r.get(keys[0], math.nan))]
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.6))
    for ax, key, title in [(axes[0], f"{sensor}_quasi_static_rms", "quasi-static RMS of p/(rho g H)"),
                           (axes[1], f"{sensor}_peak_row_error", "|peak error| of p/(rho g H), row means")]:
        points = [(r["wall_seconds"], abs(r[key])) for r in done]
        for method in sorted({r["method"] for r in done}):
            mine = [(c, e) for r, (c, e) in zip(done, points) if r["method"] == method]
            ax.scatter([c for c, _ in mine], [e for _, e in mine], s=30, color=styles.colour(method), label=method)
        front = pareto_front(points)
        ax.step([points[i][0] for i in front], [points[i][1] for i in front], "k--", where="post", lw=1.0,
                label="Pareto front")
        ax.set_xscale("log")
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(f"{sensor}: error against the experiment")
        ax.set_title(title)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True
