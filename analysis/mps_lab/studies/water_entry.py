"""Water entry of a circular cylinder at constant velocity (scenes/water_entry.json,
docs/validation.md "Water entry"): every method at several resolutions D/l0, the fluid's vertical
force on the cylinder as a slamming coefficient against the non-dimensional penetration, compared
with theory and the empirical fit of Campbell & Weynberg (1980).

Definitions (all read from the run's run.json and series.csv, nothing from a list of methods):

    D, r         the circle obstacle's diameter and radius (walls.obstacles[0].circle), m
    V            the speed of its constant_velocity law (downward), m/s
    y_s          the undisturbed free surface: the top fluid lattice row + l0/2 (the water between
                 the bed's wall surface at l0/2 and y_s holds the particles' volume), m
    d(t)         penetration = y_s - (bottom of the circle at t), m; d/D from 0 at first contact
    F_y          series.csv obstacle_0_fy, the fluid's force on the cylinder, N/m (upward +)
    F_b(d)       buoyancy of the submerged segment below y_s, rho g A_seg(d), N/m
    C_s          (F_y - F_b) / (0.5 rho V^2 D), the slamming coefficient

F_y is noisy (particles arrive on the surface one by one): C_s is taken of the moving mean of F_y
over a centred window of `window` D/V seconds (default 0.05 D/V: 2.75 ms at D = 0.11 m and
V = 2 m/s, a penetration of D/20), every row of the series within half a window of the row.

References for C_s(d/D):
    von Karman (1929)            pi (constant; momentum of the added mass of a flat plate)
    Wagner (1932)                2 pi at d -> 0 (the wetted width grows with the water's rise)
    Campbell & Weynberg (1980)   5.15 / (1 + 19 d/D) + 0.55 d/D, the fit to their drop tests of
                                 cylinders ("Measurement of parameters affecting slamming",
                                 Wolfson Unit for Marine Technology, Southampton, Report 440,
                                 Technology Reports Centre OT-R-8042); the form DNV-RP-C205
                                 (Environmental conditions and environmental loads, section 8)
                                 gives for a smooth circular cylinder.

Per run: the mean of the filtered C_s over d/D in [0.1, 0.5] (trapezoid in d/D over the range)
against the mean of the fit over the same range (1.037), the RMS of the relative difference
(C_s - C_fit)/C_fit over the rows in the range, the peak of the filtered C_s and where it is.

The tank check (--large-tank n ...): the same cases in a tank widened by 2 D on each side and
deepened by 2 D (12 D x 5 D instead of 8 D x 3 D), folders OUT/large/D<n>/<method>, table rows
with tank "large".

Each case differs from the scene by --set only: the spacing l0 = D/n, the time step 0.02 s/m x l0
(as the scene) and every `max_time_step` the scene's method blocks give scaled with l0. A case
folder is OUT/D<n>/<method>; --collect reads the folders that exist and runs nothing. A method
whose walls cannot move (mps_lab's one-line error naming the obstacle's motion, exit 2) is listed
as "unsupported", one that runs but reports no obstacle loads as "no loads"."""
from __future__ import annotations

import math
import os

import numpy as np

from mps_lab import data, runner
from mps_lab.studies.buchner import scaled_step_bounds
from mps_lab.studies.common import formatted, write_study_tables

SCENE = "scenes/water_entry.json"
DEFAULT_DIVISIONS = (11, 22)  # D / l0
DEFAULT_WINDOW = 0.05  # moving-mean window, in D/V
DEFAULT_TIMEOUT = 3600.0  # s per case
RANGE = (0.1, 0.5)  # d/D over which the mean and the RMS are taken
LARGE_TANK_MARGIN = 0.22  # m (2 D) added on each side and below in the large-tank check
COLUMNS = ["tank", "method", "D_over_l0", "l0", "status", "steps", "mean_cs", "fit_mean_cs", "mean_ratio", "rms_relative",
           "peak_cs", "peak_at", "raw_peak_cs", "buoyancy_at_half"]


def campbell_weynberg(x):
    """C_s of Campbell & Weynberg's (1980) fit at x = d/D."""
    x = np.asarray(x, dtype=float)
    return 5.15 / (1.0 + 19.0 * x) + 0.55 * x


def fit_mean(low: float = RANGE[0], high: float = RANGE[1]) -> float:
    """The mean of campbell_weynberg over [low, high] in closed form."""
    integral = 5.15 / 19.0 * math.log((1.0 + 19.0 * high) / (1.0 + 19.0 * low)) + 0.275 * (high ** 2 - low ** 2)
    return integral / (high - low)


def segment_area(d, r: float):
    """Area of a circle of radius r below a line at depth d under its lowest point, m^2 (0 <= d <= 2r)."""
    h = np.clip(np.asarray(d, dtype=float), 0.0, 2.0 * r)
    return r * r * np.arccos((r - h) / r) - (r - h) * np.sqrt(np.maximum(2.0 * r * h - h * h, 0.0))


def entry_geometry(run: data.Run) -> dict:
    """D, r, V, y_s, the circle's initial centre height, start time, rho, g and l0 of a run."""
    scene = run.summary["scene_resolved"]
    obstacle = scene["walls"]["obstacles"][0]
    circle, motion = obstacle["circle"], obstacle["motion"]
    l0 = float(scene["particle_spacing"])
    y_min = float(scene["domain"]["min"][1])
    top = max(float(block["max"][1]) for block in scene["fluid_blocks"])
    top_row = y_min + (math.ceil((top - y_min) / l0 - 1e-9) - 1) * l0  # lattice points strictly inside
    radius = float(circle["radius"])
    return {"D": 2.0 * radius, "r": radius, "V": abs(float(motion["velocity"][1])), "y_s": top_row + 0.5 * l0,
            "centre_y": float(circle["centre"][1]), "start": float(motion.get("start_time", 0.0)),
            "rho": float(scene["physics"]["density"]), "g": abs(float(scene["physics"]["gravity"][1])), "l0": l0}


def moving_mean(t: np.ndarray, f: np.ndarray, window: float) -> np.ndarray:
    """The mean of f over the rows within window/2 of each row's time (a centred box filter)."""
    low = np.searchsorted(t, t - 0.5 * window, side="left")
    high = np.searchsorted(t, t + 0.5 * window, side="right")
    sums = np.concatenate(([0.0], np.cumsum(f)))
    return (sums[high] - sums[low]) / (high - low)


def slamming_curve(run: data.Run, window: float = DEFAULT_WINDOW) -> dict:
    """d/D, raw and filtered C_s, and the buoyancy's share in C_s, per series row after contact."""
    geometry = entry_geometry(run)
    t, fy = run.series["time"], run.series["obstacle_0_fy"]
    bottom = geometry["centre_y"] - geometry["r"] - geometry["V"] * np.maximum(t - geometry["start"], 0.0)
    depth = geometry["y_s"] - bottom
    scale = 0.5 * geometry["rho"] * geometry["V"] ** 2 * geometry["D"]  # N/m
    buoyancy = geometry["rho"] * geometry["g"] * segment_area(depth, geometry["r"])  # N/m
    filtered = moving_mean(t, fy, window * geometry["D"] / geometry["V"])
    wet = depth >= 0.0
    return {"x": depth[wet] / geometry["D"], "raw": (fy[wet] - buoyancy[wet]) / scale,
            "filtered": (filtered[wet] - buoyancy[wet]) / scale, "buoyancy": buoyancy[wet] / scale,
            "time": t[wet], "geometry": geometry}


def curve_measures(x: np.ndarray, filtered: np.ndarray, raw: np.ndarray, buoyancy: np.ndarray) -> dict:
    """mean_cs, fit_mean_cs, mean_ratio, rms_relative, peak_cs, peak_at, raw_peak_cs (see the docstring)."""
    inside = (x >= RANGE[0]) & (x <= RANGE[1])
    if inside.sum() < 2:
        return {}
    xs, cs = x[inside], filtered[inside]
    mean = float(np.trapz(cs, xs) / (xs[-1] - xs[0]))
    fit = fit_mean(xs[0], xs[-1])
    relative = (cs - campbell_weynberg(xs)) / campbell_weynberg(xs)
    peak = int(np.argmax(filtered))
    half = int(np.argmin(np.abs(x - 0.5)))
    return {"mean_cs": mean, "fit_mean_cs": fit, "mean_ratio": mean / fit,
            "rms_relative": float(np.sqrt(np.mean(relative ** 2))), "peak_cs": float(filtered[peak]),
            "peak_at": float(x[peak]), "raw_peak_cs": float(np.max(raw)), "buoyancy_at_half": float(buoyancy[half])}


def case_arguments(scene: str, method: str, divisions: int, folder: str, diameter: float) -> list[str]:
    """The mps_lab arguments of one case (see the module's docstring)."""
    l0 = diameter / divisions
    return (["run", scene, "--method", method, "--out", folder, "--quiet", "--threads", "1",
             "--set", f"particle_spacing={l0:.12g}", "--set", f"time.time_step={0.02 * l0:.12g}"]
            + scaled_step_bounds(scene, l0))


def large_tank_arguments(scene: str, margin: float = LARGE_TANK_MARGIN) -> list[str]:
    """--set that widen the tank by `margin` on each side and deepen it by `margin`, the cylinder
    and its gap to the surface kept (a margin that is a multiple of l0 keeps the lattice under the
    cylinder as it is): the check that the tank's walls do not matter."""
    import json
    with open(scene) as handle:
        document = json.load(handle)
    domain_max = document["domain"]["max"]
    block_max = document["fluid_blocks"][0]["max"]
    centre = document["walls"]["obstacles"][0]["circle"]["centre"]
    width, height = domain_max[0] + 2.0 * margin, domain_max[1] + margin
    return ["--set", f"domain.max=[{width:.12g},{height:.12g}]",
            "--set", f"fluid_blocks.0.max=[{block_max[0] + 2.0 * margin:.12g},{block_max[1] + margin:.12g}]",
            "--set", f"walls.obstacles.0.circle.centre=[{centre[0] + margin:.12g},{centre[1] + margin:.12g}]"]


def scene_diameter(scene: str) -> float:
    import json
    with open(scene) as handle:
        return 2.0 * float(json.load(handle)["walls"]["obstacles"][0]["circle"]["radius"])


def requests(scene: str, out: str, methods: list[str], divisions: list[int], large_tank: list[int] = ()):
    """The scene's cases at every division, then the large-tank cases at the divisions `large_tank`."""
    diameter = scene_diameter(scene)
    for tank, folder_prefix, tank_divisions, extra in (("scene", "", divisions, []),
                                                       ("large", "large", large_tank, large_tank_arguments(scene))):
        for n in tank_divisions:
            for method in methods:
                folder = os.path.join(out, folder_prefix, f"D{n}", method)
                yield runner.CaseRequest(os.path.join(folder_prefix, f"D{n}/{method}"),
                                         case_arguments(scene, method, n, folder, diameter) + extra, folder,
                                         {"tank": tank, "method": method, "D_over_l0": n, "l0": diameter / n})


def row_of(folder: str, extra: dict, window: float, exit_code: int | None = None) -> dict:
    """A table row of one case folder."""
    if exit_code == runner.EXIT_BAD_INPUT:
        return dict(extra, status="unsupported")
    if not os.path.isfile(os.path.join(folder, "run.json")):
        return dict(extra, status="missing")
    run = data.load_run(folder)
    row = dict(extra, status=run.summary["status"], steps=run.summary.get("steps", 0))
    if "obstacle_0_fy" not in run.series:
        row["status"] = "no loads"
        return row
    curve = slamming_curve(run, window)
    row.update(curve_measures(curve["x"], curve["filtered"], curve["raw"], curve["buoyancy"]))
    return row


def markdown(rows: list[dict]) -> str:
    """The table of docs/validation.md."""
    lines = ["| tank | method | D/l0 | status | mean C_s, d/D 0.1-0.5 | / fit | RMS rel. diff. | peak C_s (at d/D) | "
             "raw peak |", "|" + "---|" * 9]
    for r in rows:
        peak = f"{formatted(r.get('peak_cs', ''), 2)} ({formatted(r.get('peak_at', ''), 3)})" if "peak_cs" in r else ""
        lines.append(f"| {r['tank']} | {r['method']} | {r['D_over_l0']} | {r['status']} | {formatted(r.get('mean_cs', ''))} | "
                     f"{formatted(r.get('mean_ratio', ''))} | {formatted(r.get('rms_relative', ''))} | {peak} | "
                     f"{formatted(r.get('raw_peak_cs', ''), 2)} |")
    return "\n".join(lines) + "\n"


def plot(folders: dict, window: float, path: str) -> None:
    """Filtered C_s against d/D, one panel per method, every resolution, with the references;
    folders: {(method, n): folder}."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = sorted({method for method, _ in folders})
    figure, axes = plt.subplots(1, len(methods), figsize=(4.3 * len(methods), 3.8), squeeze=False)
    x = np.linspace(0.0, 0.7, 300)
    for axis, method in zip(axes[0], methods):
        top = 7.0  # the axis' top: the curves' largest value up to 20
        for n in sorted(n for m, n in folders if m == method):
            curve = slamming_curve(data.load_run(folders[(method, n)]), window)
            axis.plot(curve["x"], curve["filtered"], lw=1.0, label=f"D/l0 = {n}")
            top = max(top, min(20.0, 1.05 * float(np.max(curve["filtered"]))))
        axis.plot(x, campbell_weynberg(x), "k-", lw=1.6, label="Campbell & Weynberg (1980)")
        axis.axhline(math.pi, color="0.4", ls=":", lw=1.0, label="von Karman: π")
        axis.plot([0.0], [2.0 * math.pi], "kv", ms=6, label="Wagner: 2π at d → 0")
        axis.axvspan(*RANGE, color="0.92", zorder=0)
        axis.set_xlim(0.0, 0.7)
        axis.set_ylim(-1.0, top)
        axis.set_title(method)
        axis.set_xlabel("d / D")
        axis.legend(fontsize=7)
    axes[0][0].set_ylabel(f"C_s, moving mean over {window:g} D/V")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def study(out: str, methods: list[str], divisions: list[int], binary: str | None, parallel: int, timeout: float,
          collect: bool, docs: str | None, window: float = DEFAULT_WINDOW, large_tank: list[int] = ()) -> int:
    """Run (unless collect) and tabulate; docs: the folder of docs/data and docs/figures to write;
    large_tank: the divisions also run in the tank widened and deepened by LARGE_TANK_MARGIN."""
    from mps_lab import SOURCE_ROOT
    scene = os.path.join(SOURCE_ROOT, SCENE)
    cases = list(requests(scene, out, methods, divisions, large_tank))
    exit_codes = {}
    if not collect:
        for request, result in runner.run_cases(runner.find_binary(binary), cases, parallel=parallel,
                                                timeout=timeout, threads=1):
            exit_codes[request.name] = result.exit_code
            print(f"{request.name}: {result.describe()}", flush=True)
    rows, folders = [], {}
    for request in cases:
        row = row_of(request.folder, request.extra, window, exit_codes.get(request.name))
        rows.append(row)
        if "mean_cs" in row and request.extra["tank"] == "scene":
            folders[(request.extra["method"], request.extra["D_over_l0"])] = request.folder
    figure = write_study_tables(docs or out, "water_entry", rows, COLUMNS, markdown(rows))
    if folders:
        plot(folders, window, figure)
    print(markdown(rows))
    return 0
