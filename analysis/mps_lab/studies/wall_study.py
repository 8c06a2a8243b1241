"""The wall study: every method with every boundary model on three scenes, and what the wall does.

    /usr/bin/python3 analysis/wall_study.py --out runs/wall_study --parallel 2       # run (resumes), collect, plot
    /usr/bin/python3 analysis/wall_study.py --methods mps --models default mirror_particles --scenes hydrostatic
    /usr/bin/python3 analysis/wall_study.py --out runs/wall_study --collect  # collect and plot only (needs the binary)
    /usr/bin/python3 analysis/wall_study.py --out /tmp/ws --quick                   # short end times (tests)

A boundary model is the wall treatment that represents the walls to the fluid (core/walls/).
The methods, each method's default boundary model and the others it supports are read from
the binary (`mps_lab methods --parameters`: "wall treatment NAME (boundary model, on by
default)"), so a new method or boundary model joins the study without an edit here. A case is
one `mps_lab run --method=M SCENE` into <out>/cases/<scene>__<method>__<model>/; a model other
than the default is named with `--set methods.M.wall_treatments.MODEL={}` and the default is
switched off (`--set methods.M.wall_treatments.DEFAULT.enabled=false`, for a scene that names
it); the scene's other treatments stay (the MPS clamps, ...). A variant of a model,
`--models distance_function:corners=nearest`, sets its parameters
(`methods.M.wall_treatments.MODEL={"corners":"nearest"}`) and is a model of its own in the
table and the figure. Every
case runs with stability.on_divergence=continue: a wall penetration is counted, not a stop.
Scenes: dambreak (scenes/dambreak.json, T = 2 s), hydrostatic (scenes/hydrostatic.json to
T = 1 s with a frame every 0.05 s), dambreak_obstacle (scenes/dambreak_obstacle.json, T = 2 s),
hydrostatic_slope (still water over a 25-degree wedge, scenes/hydrostatic_slope.json, T = 1 s),
hydrostatic_box (still water around a box on the bed: two convex and two concave corners,
scenes/hydrostatic_box.json, T = 1 s), dambreak_gate (the dam break with its gate lifted,
scenes/dambreak_gate.json, T = 0.4 s: a moving obstacle, run by the combinations whose method
and boundary model declare moving walls; the others are "unsupported", from mps_lab's own
one-line error); --quick ends them at 0.4, 0.6, 0.4, 0.6, 0.6 and 0.2 s.

Cases run through the case runner (mps_lab/runner.py) --parallel at a time with
OMP_NUM_THREADS = cores / parallel. A case whose run.json says completed, diverged,
solver_failed or failed is finished and is not run again; any other case (no run.json,
"interrupted", an error before the run started) runs again, so an interrupted study resumes.
A case that crashed (killed by a signal) is run once more by the runner. An mps_lab that exits
with an error and no run.json (a combination not supported, a bad key) is recorded as status
"error" with the last line of its stderr (kept in the case folder as stderr.txt); a case over
--timeout is "timeout".

<out>/wall_study.csv, one row per case:
  scene, method, boundary_model, default   the combination (default: the method's own model)
  status, message                          run.json's status and message, or error / timeout
  model_in_run                             the boundary model(s) enabled in run.json's wall_treatments
  model_reported, revision                 the boundary model the method reports using (method_summary;
                                           empty: it reports none) and the build's git revision
  simulated_time, steps, wall_seconds, fluid_particles, fluid_final, ghost_final,
  particle_steps_per_second                cost (run.json; fluid particle-steps per second)
  penetrations, escaped, first_penetration_time   stability-monitor event counts (run.json)
  min_wall_distance_over_l0                smallest fluid-wall distance / l0 (< 0: past the wall surface)
  hydrostatic only, means over the frames with t in [0.5, 1.0]:
    wall_pressure_ratio                    p / (rho g (y_top - y)) of the bottom fluid row
                                           (y < 0.0375 m, x in the middle 60 % of 0..0.5 m),
                                           y_top = 0.2875 m (top fluid row 0.275 m + l0/2)
    dpdy_ratio                             least-squares dp/dy / (-rho g) over the fluid below y_top - 0.05 m
    hydro_frames, hydro_max_speed          frames used; the largest max |u| of series.csv in the window [m/s]
  dam breaks, sensor pressure_right_wall_bottom of series.csv, t in [0.3, 2.0]:
    sensor_noise_kpa                       RMS of p - (its centred 0.05 s moving average) [kPa]
    sensor_peak_kpa, sensor_peak_time      the largest p and when
    obstacle_noise_kpa                     the same noise at the obstacle_front sensor (obstacle scene)
  dambreak and dambreak_gate (completed cases): front_rms, front_rms_shifted, front_best_shift
                                           surge front Z against Martin & Moyce (as analysis/compare.py;
                                           the gate's without a shift is the one that counts)
  hydrostatic_slope and hydrostatic_box, means over t in [0.5, 1.0] of series.csv's sensor columns:
    sensor_ratios                          "name=ratio ..." per sensor: mean p / (rho g h), h its depth
                                           below the water's level at rest (rest_level: from the fluid
                                           particle count of frame 0 and the tank less the obstacles)
    sensor_ratio_min, sensor_ratio_max     the smallest and largest of them
    hydro_max_speed, max_speed_run         the largest max |u| in the window and over the whole run [m/s]
--merge CSV adds the rows of an earlier wall_study.csv (e.g. docs/data/wall_study.csv) for the
cases not in this study (other methods), so new methods join the tables and the figure
without running the old cases again.
<out>/wall_study.md: a markdown table per scene. <out>/wall_study_corners.png: the slope's and
the box's worst sensor ratio, the box's fastest particle, the gate's front RMS (when those scenes
ran). <out>/wall_study.png: front RMS, wall-sensor
noise and the hydrostatic wall-pressure ratio per method and boundary model (hatched: the run
penetrated a wall; a cross: no value, the case failed; a triangle: the run lost more than half
of its fluid, its value is in the CSV but not drawn).
"""
from __future__ import annotations

import json
import math
import os
import re
import sys

import numpy as np

from .. import SOURCE_ROOT, data, methods, runner
from .common import FINISHED, case_folder, read_rows, run_summary, status_of, write_csv

DEFAULT_TIMEOUT = 3600.0  # s per case
SCENES = {  # name: scene file, end time, quick end time, extra overrides
    "dambreak": ("scenes/dambreak.json", 2.0, 0.4, {}),
    "hydrostatic": ("scenes/hydrostatic.json", 1.0, 0.6, {"output.frame_interval": 0.05}),
    "dambreak_obstacle": ("scenes/dambreak_obstacle.json", 2.0, 0.4, {}),
    "hydrostatic_slope": ("scenes/hydrostatic_slope.json", 1.0, 0.6, {}),
    "hydrostatic_box": ("scenes/hydrostatic_box.json", 1.0, 0.6, {}),
    "dambreak_gate": ("scenes/dambreak_gate.json", 0.4, 0.2, {}),
}
# Still water read at the scene's pressure sensors (sloped bed, box corners): each sensor's mean
# over HYDRO_WINDOW against rho g h. Dam breaks whose surge front is compared with Martin & Moyce.
SENSOR_STILL_SCENES = ("hydrostatic_slope", "hydrostatic_box")
FRONT_SCENES = ("dambreak", "dambreak_gate")
# A scene a combination cannot run: mps_lab's one-line error for a moving obstacle with a method
# or boundary model that does not declare moving walls (core/run/driver.cpp, check_moving_walls).
UNSUPPORTED = re.compile(r"\.motion: .*expected a (method|boundary model) that does")
COMMON = {"stability.on_divergence": "continue"}
DEFAULT_SLOT = "default"  # the method's own boundary model, whichever it is

# The hydrostatic tank (scenes/hydrostatic.json): fluid rows at y = 0.025 ... 0.275 m.
HYDRO_WINDOW = (0.5, 1.0)  # s, the water has settled
HYDRO_Y_TOP = 0.2875  # m, initial free surface: top fluid row 0.275 + l0/2
HYDRO_BOTTOM_ROW = 0.0375  # m, fluid below this is the bottom row
HYDRO_X_RANGE = (0.1, 0.4)  # m, the middle 60 % of the tank width 0..0.5
HYDRO_SURFACE_BAND = 0.05  # m, fluid above y_top - this is left out of the dp/dy fit
# The dam-break sensors.
SENSOR_WINDOW = (0.3, 2.0)  # s, from just before the impact on the right wall
NOISE_AVERAGE = 0.05  # s, width of the moving average the noise is measured against

COLUMNS = ["scene", "method", "boundary_model", "default", "status", "model_in_run", "model_reported",
           "revision", "simulated_time", "steps",
           "wall_seconds", "fluid_particles", "fluid_final", "ghost_final", "particle_steps_per_second",
           "penetrations", "escaped", "first_penetration_time", "min_wall_distance_over_l0", "wall_pressure_ratio",
           "dpdy_ratio", "hydro_frames", "hydro_max_speed", "sensor_noise_kpa", "sensor_peak_kpa",
           "sensor_peak_time", "obstacle_noise_kpa", "front_rms", "front_rms_shifted", "front_best_shift",
           "sensor_ratios", "sensor_ratio_min", "sensor_ratio_max", "max_speed_run", "message", "name"]
TEXT_COLUMNS = {"scene", "method", "boundary_model", "default", "status", "model_in_run", "model_reported", "revision",
                "sensor_ratios", "message", "name"}


# --- the cases -----------------------------------------------------------------------------

def model_variant(entry: str) -> tuple[str, dict]:
    """A --models entry: a boundary model's name, or a variant "NAME:key=value[,key=value]" that
    sets the model's parameters (each value JSON, or a bare string: corners=blended). A variant
    is its own bar and row, labelled by the entry."""
    name, _, settings = entry.partition(":")
    parameters = {}
    for item in filter(None, settings.split(",")):
        key, equals, value = item.partition("=")
        if not equals or not key:
            raise ValueError(f"--models {entry}: expected NAME:key=value[,key=value], got '{item}'")
        try:
            parameters[key] = json.loads(value)
        except json.JSONDecodeError:
            parameters[key] = value
    return name, parameters


def cases_of(catalogue: dict[str, methods.MethodInfo], chosen: list[str], models: list[str], scenes: list[str],
             quick: bool = False) -> list[dict]:
    """Every scene x method x boundary model the method supports; "default" in models stands
    for each method's own, "NAME:key=value" for a variant of NAME (model_variant).
    catalogue: methods.method_catalogue of the binary."""
    variants = [(entry, *model_variant(entry)) for entry in models if ":" in entry]
    cases = []
    for scene in scenes:
        path, end_time, quick_end, extra = SCENES[scene]
        for method in chosen:
            info = catalogue[method]
            own = info.default_boundary_model
            chosen_models = [(m, m, {}) for m in [own] + [m for m in info.boundary_models if m != own]
                             if m in models or (m == own and DEFAULT_SLOT in models)]
            chosen_models += [v for v in variants if v[1] in info.boundary_models]
            for label, model, parameters in chosen_models:
                overrides = {**COMMON, **extra}
                if model != own or parameters:  # the default switched off too: a scene may name it (wcsph's block does)
                    overrides[f"methods.{method}.wall_treatments.{model}"] = parameters
                if model != own:
                    overrides[f"methods.{method}.wall_treatments.{own}.enabled"] = False
                cases.append({"name": f"{scene}__{method}__{label}", "scene": scene, "scene_file": path,
                              "method": method, "boundary_model": label, "default": label == own,
                              "end_time": quick_end if quick else end_time, "overrides": overrides})
    return cases


def arguments_of(case: dict, out: str) -> list[str]:
    """The `mps_lab` arguments of one case (after the binary)."""
    arguments = ["run", f"--method={case['method']}", os.path.join(SOURCE_ROOT, case["scene_file"]), "--out",
                 case_folder(out, case["name"]), "--quiet", "--end-time", repr(float(case["end_time"]))]
    for key, value in case["overrides"].items():
        arguments += ["--set", f"{key}={json.dumps(value)}"]
    return arguments


def summary_of(out: str, case: dict) -> dict | None:
    return run_summary(case_folder(out, case["name"]))


def record_outcome(case: dict, out: str, result: runner.CaseResult) -> str:
    """The case's status after a run; for a case without a finished run.json, "timeout" or
    "error", with stderr.txt (first line: the outcome) left in its folder."""
    folder = case_folder(out, case["name"])
    stale = os.path.join(folder, "stderr.txt")
    status = status_of(out, case)
    if status in FINISHED:
        if os.path.exists(stale):
            os.remove(stale)
        return status
    outcome = "timeout" if result.timed_out else "error"
    detail = result.start_error or result.stderr
    os.makedirs(folder, exist_ok=True)
    with open(stale, "w") as handle:
        handle.write(f"{outcome} ({result.describe()})\n{detail}")
    return outcome


def run_cases(cases: list[dict], out: str, binary: str, parallel: int, threads: int, timeout: float) -> None:
    pending = [case for case in cases if status_of(out, case) not in FINISHED]
    print(f"wall_study: {len(cases)} cases, {len(cases) - len(pending)} finished, running {len(pending)} "
          f"({parallel} at a time, {threads} thread(s) each)", flush=True)
    requests = [runner.CaseRequest(case["name"], arguments_of(case, out), case_folder(out, case["name"]),
                                   {"case": case}) for case in pending]
    for request, result in runner.run_cases(binary, requests, parallel=parallel, timeout=timeout, threads=threads):
        status = record_outcome(request.extra["case"], out, result)
        print(f"wall_study: {request.name}: {status} ({result.describe()})", flush=True)


# --- the metrics ---------------------------------------------------------------------------

def sensor_noise(t, p, window: tuple[float, float] = SENSOR_WINDOW, average: float = NOISE_AVERAGE) -> float:
    """RMS of p - (centred moving average of p over `average` seconds) at the samples with t in
    `window` whose whole averaging interval lies inside the series. Units of p.

    The moving average is the exact mean of the piecewise-linear p over [t - average/2,
    t + average/2], and each sample weighs its share of time ((t[i+1] - t[i-1]) / 2) in the
    RMS, so that unevenly sampled series (DFSPH's adaptive step) weigh time, not samples. The
    average includes the sample itself: white noise sampled every 0.005 s (series.csv) reads
    sqrt(0.895) ~ 5 % low, sampled densely it reads right."""
    t, p = np.asarray(t, dtype=float), np.asarray(p, dtype=float)
    keep = np.isfinite(t) & np.isfinite(p)
    t, p = t[keep], p[keep]
    if len(t) < 3 or not np.all(np.diff(t) > 0):
        return math.nan
    cumulative = np.concatenate([[0.0], np.cumsum(np.diff(t) * (p[1:] + p[:-1]) / 2.0)])

    def integral_to(a: np.ndarray) -> np.ndarray:  # of the piecewise-linear p from t[0] to a
        k = np.clip(np.searchsorted(t, a, side="right") - 1, 0, len(t) - 2)
        return cumulative[k] + (a - t[k]) * (p[k] + np.interp(a, t, p)) / 2.0

    half = average / 2.0
    inside = ((t >= window[0] - 1e-12) & (t <= window[1] + 1e-12) & (t - half >= t[0] - 1e-12)
              & (t + half <= t[-1] + 1e-12))
    if not inside.any():
        return math.nan
    centres = t[inside]
    smooth = (integral_to(np.minimum(centres + half, t[-1])) - integral_to(np.maximum(centres - half, t[0]))) / average
    share = np.gradient(t)[inside]  # (t[i+1] - t[i-1]) / 2 inside, one-sided at the ends
    residual = p[inside] - smooth
    return float(np.sqrt(np.sum(share * residual ** 2) / np.sum(share)))


def sensor_peak(t, p, window: tuple[float, float] = SENSOR_WINDOW) -> tuple[float, float]:
    """(largest p, its time) on t in window."""
    t, p = np.asarray(t, dtype=float), np.asarray(p, dtype=float)
    inside = (t >= window[0]) & (t <= window[1]) & np.isfinite(p)
    if not inside.any():
        return math.nan, math.nan
    k = int(np.argmax(np.where(inside, p, -np.inf)))
    return float(p[k]), float(t[k])


def hydrostatic_frame(frame: dict[str, np.ndarray], density: float, gravity: float, y_top: float = HYDRO_Y_TOP,
                      bottom_row: float = HYDRO_BOTTOM_ROW, x_range: tuple[float, float] = HYDRO_X_RANGE,
                      surface_band: float = HYDRO_SURFACE_BAND) -> tuple[float, float]:
    """(wall-pressure ratio, dp/dy ratio) of one frame (columns x, y, pressure, type).

    Wall-pressure ratio: mean of p / (rho g (y_top - y)) over the fluid of the bottom row
    (y < bottom_row) in x_range; dp/dy ratio: the least-squares slope of p against y over the
    fluid below y_top - surface_band, divided by -rho g. 1 and 1 for the exact hydrostatic field."""
    fluid = frame["type"] == 0
    x, y, p = frame["x"][fluid], frame["y"][fluid], frame["pressure"][fluid]
    row = (y < bottom_row) & (x >= x_range[0]) & (x <= x_range[1])
    depth = y_top - y[row]
    ratio = float(np.mean(p[row] / (density * gravity * depth))) if row.any() and (depth > 0).all() else math.nan
    below = y < y_top - surface_band
    slope = math.nan
    if below.sum() >= 3 and np.ptp(y[below]) > 0:
        slope = float(np.polyfit(y[below], p[below], 1)[0])
    return ratio, slope / (-density * gravity)


def frame_times(run: data.Run) -> list[tuple[float, str]]:
    """(time, path) of the CSV frames: the times of output.vtk.series when written (exact), else
    the step interpolated in series.csv's (step, time) (exact at a series row, and within a
    step of it otherwise, also for an adaptive time step)."""
    frames = run.frames()
    known = {}
    try:
        with open(os.path.join(run.folder, "output.vtk.series")) as handle:
            for entry in json.load(handle).get("files", []):
                known[entry["name"][:-len(".vtk")]] = float(entry["time"])
    except (OSError, json.JSONDecodeError, KeyError, TypeError, ValueError):
        known = {}
    steps, times = run.series["step"], run.series["time"]
    result = []
    for step, path in frames:
        stem = os.path.basename(path)[:-len(".csv")]
        result.append((known[stem] if stem in known else float(np.interp(step, steps, times)), path))
    return result


def hydrostatic_metrics(run: data.Run, window: tuple[float, float] = HYDRO_WINDOW) -> dict:
    density = float(run.summary["shared"]["density"])
    ratios, slopes = [], []
    for t, path in frame_times(run):
        if window[0] - 1e-9 <= t <= window[1] + 1e-9:
            ratio, slope = hydrostatic_frame(data.read_csv_columns(path), density, run.gravity)
            ratios.append(ratio)
            slopes.append(slope)
    t = run.series["time"]
    inside = (t >= window[0]) & (t <= window[1])
    return {"wall_pressure_ratio": float(np.nanmean(ratios)) if np.isfinite(ratios).any() else math.nan,
            "dpdy_ratio": float(np.nanmean(slopes)) if np.isfinite(slopes).any() else math.nan,
            "hydro_frames": len(ratios),
            "hydro_max_speed": float(run.series["max_speed"][inside].max()) if inside.any() else math.nan}


def horizontal_chord(polygon: list, y: float) -> float:
    """The length of the horizontal line at height y inside a polygon (even-odd crossings), m."""
    crossings = []
    for k, a in enumerate(polygon):
        b = polygon[(k + 1) % len(polygon)]
        if (a[1] <= y) == (b[1] <= y):
            continue
        crossings.append(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]))
    crossings.sort()
    return sum(crossings[k + 1] - crossings[k] for k in range(0, len(crossings) - 1, 2))


def rest_level(scene: dict, fluid_particles: int) -> float:
    """The level at rest of the scene's water, m: N l0^2 fills the tank between its wall surfaces
    (l0/2 inside the domain) above the bed's surface, less the obstacles (a polygon as drawn, a box
    grown by l0/2), up to the level (bisection; midpoint rule over 2000 slices). Not the lattice's top
    + l0/2: against a slope the lattice leaves gaps that the water fills at rest (0.2776 m against
    0.2875 m in scenes/hydrostatic_slope.json; tests/test_wall_polygons.cpp)."""
    l0 = float(scene["particle_spacing"])
    (x0, y0), (x1, y1) = scene["domain"]["min"], scene["domain"]["max"]
    left, right, bed = x0 + l0 / 2, x1 - l0 / 2, y0 + l0 / 2
    shapes = []
    for obstacle in scene.get("walls", {}).get("obstacles", []):
        if "polygon" in obstacle:
            shapes.append(obstacle["polygon"])
        elif "min" in obstacle:
            (a, b), (c, d) = obstacle["min"], obstacle["max"]
            h = l0 / 2
            shapes.append([[a - h, b - h], [c + h, b - h], [c + h, d + h], [a - h, d + h]])

    def area_below(level: float) -> float:
        dy = (level - bed) / 2000
        ys = bed + (np.arange(2000) + 0.5) * dy
        widths = [(right - left) - sum(horizontal_chord(shape, y) for shape in shapes) for y in ys]
        return float(np.sum(widths) * dy)

    water, low, high = fluid_particles * l0 * l0, bed, y1
    for _ in range(50):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if area_below(middle) < water else (low, middle)
    return 0.5 * (low + high)


def initial_surface(run: data.Run) -> float:
    """y of the water's level at rest, m: from the first frame's fluid particle count (rest_level) when
    the resolved scene is in run.json, else the top fluid row of the first frame + l0/2."""
    frames = run.frames()
    if not frames:
        raise ValueError("no frame to find the initial surface in")
    frame = data.read_csv_columns(frames[0][1])
    fluid = frame["type"] == 0
    scene = run.summary.get("scene_resolved")
    if scene and "domain" in scene and "particle_spacing" in scene:
        return rest_level(scene, int(np.count_nonzero(fluid)))
    return float(frame["y"][fluid].max()) + 0.5 * float(run.summary["shared"]["particle_spacing"])


def sensor_still_metrics(run: data.Run, window: tuple[float, float] = HYDRO_WINDOW) -> dict:
    """Still water read by the scene's pressure sensors (module docstring): per sensor the mean
    of its series column over `window` against rho g h, h its depth below the level at rest."""
    density = float(run.summary["shared"]["density"])
    surface = initial_surface(run)
    t = run.series["time"]
    inside = (t >= window[0] - 1e-9) & (t <= window[1] + 1e-9)
    sensors = run.summary.get("scene_resolved", {}).get("diagnostics", {}).get("pressure_sensors", [])
    ratios = {}
    for sensor in sensors:
        column = f"pressure_{sensor['name']}"
        depth = surface - float(sensor["position"][1])
        if column in run.series and inside.any() and depth > 0:
            ratios[sensor["name"]] = float(np.mean(run.series[column][inside])) / (density * run.gravity * depth)
    values = [v for v in ratios.values() if math.isfinite(v)]
    speed = run.series["max_speed"]
    return {"sensor_ratios": " ".join(f"{name}={value:.3f}" for name, value in ratios.items()),
            "sensor_ratio_min": min(values) if values else math.nan,
            "sensor_ratio_max": max(values) if values else math.nan,
            "hydro_max_speed": float(speed[inside].max()) if inside.any() else math.nan,
            "max_speed_run": float(np.nanmax(speed)) if len(speed) else math.nan}


def dambreak_metrics(run: data.Run, scene: str, status: str) -> dict:
    row = {}
    t = run.series["time"]
    if "pressure_right_wall_bottom" in run.series:
        p = run.series["pressure_right_wall_bottom"]
        row["sensor_noise_kpa"] = sensor_noise(t, p) / 1000.0
        peak, when = sensor_peak(t, p)
        row["sensor_peak_kpa"], row["sensor_peak_time"] = peak / 1000.0, when
    if "pressure_obstacle_front" in run.series:
        row["obstacle_noise_kpa"] = sensor_noise(t, run.series["pressure_obstacle_front"]) / 1000.0
    if scene in FRONT_SCENES and status == "completed" and len(t) > 1:
        row.update(data.front_errors(run))
    return row


def model_in_run(summary: dict, boundary_models: list[str]) -> str:
    """The boundary model(s) the run says it used: its enabled wall treatments that are
    boundary models (boundary_models: every boundary model of the binary, sorted)."""
    treatments = summary.get("wall_treatments", {})
    used = [name for name in boundary_models if treatments.get(name, {}).get("enabled", False)]
    if not used:  # a run.json without the enabled flags: the method's own report
        method_summary = summary.get("method_summary", {})
        used = [name for name in method_summary.get("wall_treatments", []) if name in boundary_models]
    return "+".join(used)


def model_reported(summary: dict) -> str:
    """The boundary model the method itself reports in run.json's method_summary ("" when it
    reports none, e.g. a build that predates the boundary-model plugins for that method)."""
    method_summary = summary.get("method_summary", {})
    wall = method_summary.get("wall", {})
    return method_summary.get("boundary_model") or (wall.get("boundary_model", "") if isinstance(wall, dict) else "")


def row_of(case: dict, out: str, boundary_models: list[str]) -> dict:
    """One row of wall_study.csv (the module's docstring)."""
    row = {key: case[key] for key in ("scene", "method", "boundary_model", "default", "name")}
    folder = case_folder(out, case["name"])
    summary = summary_of(out, case)
    if summary is None or summary.get("status") not in FINISHED:
        row["status"] = summary.get("status", "unknown") if summary is not None else "missing"
        try:
            with open(os.path.join(folder, "stderr.txt")) as handle:
                lines = [line.strip() for line in handle if line.strip()]
            row["status"] = lines[0].split()[0]
            row["message"] = lines[-1] if len(lines) > 1 else lines[0]
        except (OSError, IndexError):
            pass
        if row["status"] == "error" and UNSUPPORTED.search(row.get("message", "")):
            row["status"] = "unsupported"
        return row
    row["status"] = summary["status"]
    row["message"] = summary.get("message", "")
    row["model_in_run"] = model_in_run(summary, boundary_models)
    row["model_reported"] = model_reported(summary)
    row["revision"] = summary.get("git_revision", "")
    particles = summary.get("particles", {})
    stability = summary.get("stability", {})
    counts = stability.get("counts", {})
    row.update({
        "simulated_time": summary.get("simulated_time", math.nan), "steps": summary.get("steps", 0),
        "wall_seconds": summary.get("wall_seconds", math.nan), "fluid_particles": particles.get("fluid", 0),
        "fluid_final": particles.get("fluid_final", ""), "ghost_final": particles.get("ghost_final", ""),
        "particle_steps_per_second": summary.get("fluid_particle_steps_per_second", math.nan),
        "penetrations": counts.get("penetration", ""), "escaped": counts.get("escaped", ""),
        "first_penetration_time": stability.get("first_event", {}).get("penetration", {}).get("time", math.nan),
        "min_wall_distance_over_l0": stability.get("min_wall_distance_over_l0", math.nan),
    })
    try:
        run = data.load_run(folder)
        if case["scene"] == "hydrostatic":
            row.update(hydrostatic_metrics(run))
        elif case["scene"] in SENSOR_STILL_SCENES:
            row.update(sensor_still_metrics(run))
        else:
            row.update(dambreak_metrics(run, case["scene"], row["status"]))
    except (OSError, ValueError, KeyError, IndexError) as error:
        row["message"] = (row["message"] + "; " if row["message"] else "") + f"analysis: {error}"
    return row


# --- the report ----------------------------------------------------------------------------

def number(value, form: str) -> str:
    try:
        value = float(value)
    except (TypeError, ValueError):
        return "–"
    return format(value, form) if math.isfinite(value) else "–"


def short_message(message: str, limit: int = 110) -> str:
    """An mps_lab error without its "mps_lab: error: SCENE: KEY: " prefix, cut at limit, for a table."""
    message = re.sub(r"^mps_lab: error: ", "", message.strip())
    message = re.sub(r"^\S+\.json: \S+: ", "", message).replace("|", "/")
    return message if len(message) <= limit else message[:limit - 1] + "…"


def markdown(rows: list[dict], quick: bool = False) -> str:
    titles = {"dambreak": "Dam break (scenes/dambreak.json)", "hydrostatic": "Water at rest (scenes/hydrostatic.json)",
              "dambreak_obstacle": "Dam break with an obstacle (scenes/dambreak_obstacle.json)",
              "hydrostatic_slope": "Water at rest over a 25° slope (scenes/hydrostatic_slope.json)",
              "hydrostatic_box": "Water at rest around a box: convex and concave corners (scenes/hydrostatic_box.json)",
              "dambreak_gate": "Dam break with the gate lifted (scenes/dambreak_gate.json, T = 0.4 s)"}
    lines = ["# Wall study: boundary models per method", "",
             "Generated by `analysis/wall_study.py`" + (" with --quick (short end times)" if quick else "") +
             ". Penetrations: stability-monitor penetration events (escape events in brackets); "
             "lost: fluid particles that became ghosts by the end; "
             "min d/l0: smallest fluid-wall distance over l0 (negative: past the wall surface); "
             "p/ρgh: bottom-row fluid pressure over ρg(y_top − y), mean over t in [0.5, 1] s; "
             "dp/dy: fitted slope over −ρg; noise: RMS of the right-wall sensor pressure minus its "
             "0.05 s moving average on t in [0.3, 2] s; peak: its largest value; front RMS: surge front Z "
             "against Martin & Moyce (completed runs; the gate's unshifted). Sensors p/ρgh (slope, box): each "
             "pressure sensor's mean over t in [0.5, 1] s over ρ g h, h its depth below the level at rest of the particle count; "
             "max |u|: the fastest particle in that window and (after the slash) over the whole run. "
             "unsupported: mps_lab refuses the combination (a moving gate needs a method and a boundary model "
             "that declare moving walls). (d): the method's default boundary model.", ""]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene]
        if scene == "hydrostatic":
            extra = ["p/ρgh", "dp/dy"]
        elif scene in SENSOR_STILL_SCENES:
            extra = ["sensors p/ρgh", "max |u| [m/s]"]
        elif scene in FRONT_SCENES:
            extra = ["noise [kPa]", "peak [kPa]", "front RMS"]
        else:
            extra = ["noise [kPa]", "obstacle noise [kPa]", "peak [kPa]"]
        header = ["method", "boundary model", "status", "penetrations", "lost", "min d/l0", *extra, "wall s"]
        lines += [f"## {titles.get(scene, scene)}", "", "| " + " | ".join(header) + " |",
                  "|" + "---|" * len(header)]
        for r in mine:
            if scene == "hydrostatic":
                values = [number(r.get("wall_pressure_ratio"), ".3f"), number(r.get("dpdy_ratio"), ".3f")]
            elif scene in SENSOR_STILL_SCENES:
                values = [r.get("sensor_ratios") or "–",
                          number(r.get("hydro_max_speed"), ".2f") + " / " + number(r.get("max_speed_run"), ".2f")]
            elif scene in FRONT_SCENES:
                values = [number(r.get("sensor_noise_kpa"), ".2f"), number(r.get("sensor_peak_kpa"), ".1f"),
                          number(r.get("front_rms"), ".3f")]
            else:
                values = [number(r.get("sensor_noise_kpa"), ".2f"), number(r.get("obstacle_noise_kpa"), ".2f"),
                          number(r.get("sensor_peak_kpa"), ".1f")]
            penetrations = (f"{r['penetrations']} ({r.get('escaped', 0)})" if number(r.get("penetrations"), ".0f") != "–"
                            else "–")  # none: the case did not run (a merged row reads NaN)
            status = r["status"] if r["status"] in FINISHED else f"{r['status']}: {short_message(r.get('message', ''))}"
            if r["status"] == "unsupported":  # "walls.obstacles[k].motion: the boundary model X does not move walls; ..."
                status = "unsupported: " + re.sub(r"^.*\.motion: ", "", r.get("message", "")).split(";")[0]
            lines.append("| " + " | ".join([r["method"], r["boundary_model"] + (" (d)" if r["default"] else ""),
                                             status, penetrations, number(r.get("ghost_final"), ".0f"),
                                             number(r.get("min_wall_distance_over_l0"), ".2f"),
                                             *values, number(r.get("wall_seconds"), ".1f")]) + " |")
        lines.append("")
    return "\n".join(lines)


def lost_fluid(row: dict) -> bool:
    """More than half of the fluid became ghosts (left the domain): its metrics describe no flow."""
    try:
        return float(row.get("ghost_final", 0)) > 0.5 * float(row.get("fluid_particles", 0))
    except (TypeError, ValueError):
        return False


def bar_layout(rows: list[dict]) -> tuple[list[str], dict[str, str], list[str], dict[str, str]]:
    """(methods, each method's default model, bar slots, slot colours) from the rows: the
    methods in the order of the rows (the registered order), "default" first then every other
    model, sorted."""
    shown = list(dict.fromkeys(r["method"] for r in rows))
    defaults = {r["method"]: r["boundary_model"] for r in rows if r["default"] in (True, "True")}
    others = sorted({r["boundary_model"] for r in rows if r["default"] not in (True, "True")})
    slots = [DEFAULT_SLOT] + others
    colours = {DEFAULT_SLOT: "0.45", **{slot: f"C{k % 10}" for k, slot in enumerate(others)}}
    return shown, defaults, slots, colours


def bar_value(row: dict | None, key: str) -> tuple[str, float]:
    """("bar", value), or ("none", nan) with no value, or ("lost", value) when the run lost most
    of its fluid (its value describes no flow)."""
    if row is None:
        return "absent", math.nan
    value = row.get(key, math.nan)
    value = float(value) if value not in ("", None) else math.nan
    if not math.isfinite(value):
        return "none", value
    return ("lost" if lost_fluid(row) else "bar"), value


def draw_panel(ax, rows: list[dict], scenes: list[str], key: str, layout) -> None:
    """Bars of one quantity: a group per method, a bar per slot (a pair when two scenes)."""
    shown, defaults, slots, colours = layout
    width = 0.8 / len(slots)
    for k, method in enumerate(shown):
        for s, slot in enumerate(slots):
            model = defaults.get(method, "") if slot == DEFAULT_SLOT else slot
            for j, name in enumerate(scenes):
                x = k + (s - (len(slots) - 1) / 2) * width + (j - (len(scenes) - 1) / 2) * width / len(scenes)
                row = next((r for r in rows if r["scene"] == name and r["method"] == method
                            and r["boundary_model"] == model), None)
                kind, value = bar_value(row, key)
                if kind in ("none", "lost"):
                    ax.plot([x], [0], marker="x" if kind == "none" else "v", color="tab:red", markersize=7, zorder=3,
                            clip_on=False)
                elif kind == "bar":
                    penetrated = bool(row.get("penetrations")) and int(row["penetrations"]) > 0
                    ax.bar(x, value, width / len(scenes) * 0.95, color=colours[slot], alpha=1.0 if j == 0 else 0.55,
                           hatch="///" if penetrated else None, edgecolor="k", linewidth=0.5)
    ax.set_xticks(range(len(shown)))
    ax.set_xticklabels(shown)
    if key in ("front_rms", "sensor_noise_kpa"):
        values = [float(r[key]) for r in rows if r["scene"] in scenes and r.get(key, "") not in ("", None)
                  and math.isfinite(float(r[key])) and float(r[key]) > 0 and not lost_fluid(r)]
        if values and max(values) / min(values) > 30:
            ax.set_yscale("log")


def plot(rows: list[dict], path: str) -> None:
    """wall_study.png: front RMS, wall-sensor noise, hydrostatic wall pressure per method and model."""
    from .. import figures  # noqa: F401  (sets the shared style)
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    layout = bar_layout(rows)
    _, defaults, slots, colours = layout
    panels = [("dambreak", "front_rms", "front RMS in Z against Martin & Moyce", "Dam break: surge front error", None),
              ("dambreak", "sensor_noise_kpa", "noise [kPa] (RMS of p − 0.05 s moving average)",
               "Right-wall sensor noise, t in [0.3, 2] s", "dambreak_obstacle"),
              ("hydrostatic", "wall_pressure_ratio", "bottom-row p / ρg(y_top − y), t in [0.5, 1] s",
               "Water at rest: wall pressure", None)]
    fig, axes = plt.subplots(1, 3, figsize=(16.0, 5.0))
    for ax, (scene, key, ylabel, title, second) in zip(axes, panels):
        draw_panel(ax, rows, [scene] + ([second] if second else []), key, layout)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        if key == "wall_pressure_ratio":
            ax.axhline(1.0, color="k", linestyle="--", linewidth=1.0)
        if second:
            ax.set_xlabel("bar pairs: dam break (left), with the obstacle (right, pale)")
    own = ", ".join(f"{method}: {model}" for method, model in defaults.items())
    handles = [Patch(facecolor=colours[s], edgecolor="k", label=f"default ({own})" if s == DEFAULT_SLOT else s)
               for s in slots]
    handles += [Patch(facecolor="white", edgecolor="k", hatch="///", label="the run penetrated a wall"),
                plt.Line2D([], [], marker="x", color="tab:red", linestyle="none", label="no value (failed / not run)"),
                plt.Line2D([], [], marker="v", color="tab:red", linestyle="none",
                           label="no bar: the run lost most of its fluid (value in wall_study.csv)")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=9, frameon=False)
    fig.suptitle("Boundary models per method (analysis/wall_study.py)")
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(path)
    plt.close(fig)


def worst_sensor_ratio(row: dict) -> float:
    """Of a row's smallest and largest sensor ratio, the one farther from 1 (nan without)."""
    try:
        low, high = float(row.get("sensor_ratio_min", "nan")), float(row.get("sensor_ratio_max", "nan"))
    except (TypeError, ValueError):
        return math.nan
    if not (math.isfinite(low) and math.isfinite(high)):
        return math.nan
    return low if abs(low - 1.0) > abs(high - 1.0) else high


def plot_corners(rows: list[dict], path: str) -> bool:
    """wall_study_corners.png: the sloped bed's and the box's worst sensor ratio, the box's
    fastest particle over the run and the gate's unshifted front RMS, per method and model.
    False (nothing drawn) when the rows have none of those scenes."""
    scenes = ("hydrostatic_slope", "hydrostatic_box", "dambreak_gate")
    mine = [dict(r, sensor_ratio_worst=worst_sensor_ratio(r)) for r in rows if r["scene"] in scenes]
    if not mine:
        return False
    from .. import figures  # noqa: F401  (sets the shared style)
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    layout = bar_layout(mine)
    _, defaults, slots, colours = layout
    panels = [("hydrostatic_slope", "sensor_ratio_worst", "worst sensor p / ρgh, t in [0.5, 1] s", "Still water, 25° slope"),
              ("hydrostatic_box", "sensor_ratio_worst", "worst sensor p / ρgh, t in [0.5, 1] s", "Still water, box corners"),
              ("hydrostatic_box", "max_speed_run", "fastest particle over the run [m/s]", "Box corners: stillness"),
              ("dambreak_gate", "front_rms", "front RMS against Martin & Moyce, no shift", "Gate lifted (T = 0.4 s)")]
    fig, axes = plt.subplots(1, len(panels), figsize=(20.0, 5.0))
    for ax, (scene, key, ylabel, title) in zip(axes, panels):
        draw_panel(ax, mine, [scene], key, layout)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        if key == "sensor_ratio_worst":
            ax.axhline(1.0, color="k", linestyle="--", linewidth=1.0)
    own = ", ".join(f"{method}: {model}" for method, model in defaults.items())
    handles = [Patch(facecolor=colours[s], edgecolor="k", label=f"default ({own})" if s == DEFAULT_SLOT else s)
               for s in slots]
    handles += [Patch(facecolor="white", edgecolor="k", hatch="///", label="the run penetrated a wall"),
                plt.Line2D([], [], marker="x", color="tab:red", linestyle="none",
                           label="no value (failed, unsupported or not run)"),
                plt.Line2D([], [], marker="v", color="tab:red", linestyle="none",
                           label="no bar: the run lost most of its fluid (value in wall_study.csv)")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=9, frameon=False)
    fig.suptitle("Slopes, corners and the gate per method and boundary model (analysis/wall_study.py)")
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(path)
    plt.close(fig)
    return True


# --- main ----------------------------------------------------------------------------------

def choose(catalogue: dict[str, methods.MethodInfo], chosen: list[str] | None,
           models: list[str] | None) -> tuple[list[str], list[str]]:
    """The methods and models asked for, checked against the binary's; raises ValueError."""
    registered = sorted(catalogue)
    every_model = sorted({m for info in catalogue.values() for m in info.boundary_models})
    chosen = chosen or registered
    models = models or [DEFAULT_SLOT] + every_model
    for method in chosen:
        if method not in catalogue:
            raise ValueError(f"--methods: {method}: not a registered method (expected one of: {', '.join(registered)})")
    for model in models:
        name = model_variant(model)[0]  # raises on a malformed variant
        if model != DEFAULT_SLOT and name not in every_model:
            raise ValueError(f"--models: {model}: not a boundary model (expected default or one of: "
                             f"{', '.join(every_model)}, or NAME:key=value)")
    return chosen, models


def wall_study(out: str, binary: str | None = None, chosen: list[str] | None = None, models: list[str] | None = None,
               scenes: list[str] | None = None, parallel: int = 1, timeout: float = DEFAULT_TIMEOUT,
               collect_only: bool = False, quick: bool = False, plots: bool = True, merge: str | None = None) -> int:
    """The whole study (module docstring). The binary is needed also to collect: it names the
    methods and their boundary models. 0, or 2 with one line on stderr."""
    try:
        found = runner.find_binary(binary)
        catalogue = methods.method_catalogue(found)
        chosen, models = choose(catalogue, chosen, models)
        earlier = read_rows(merge, set(COLUMNS) - TEXT_COLUMNS) if merge else []
        for row in earlier:  # the CSV's "True"/"False" back to a boolean
            row["default"] = row["default"] in ("True", "true", "1")
    except (runner.BinaryNotFound, methods.MethodListError, ValueError, OSError, KeyError) as error:
        print(f"wall_study.py: {error}", file=sys.stderr)
        return 2
    cases = cases_of(catalogue, chosen, models, scenes or list(SCENES), quick)
    if not cases:
        print("wall_study.py: no case: no boundary model of --models belongs to a method of --methods", file=sys.stderr)
        return 2
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    parallel = max(1, parallel)
    if not collect_only:
        run_cases(cases, os.path.abspath(out), found, parallel, runner.threads_per_case(parallel), timeout)
    boundary_models = sorted({m for info in catalogue.values() for m in info.boundary_models})
    rows = [row_of(case, out, boundary_models) for case in cases]
    if merge:  # the earlier rows first, in their order, then this study's; a case of both: this study's
        names = {row["name"] for row in rows}
        rows = [row for row in earlier if row["name"] not in names] + rows
        rows.sort(key=lambda row: list(SCENES).index(row["scene"]) if row["scene"] in SCENES else len(SCENES))
    write_csv(rows, COLUMNS, os.path.join(out, "wall_study.csv"))
    with open(os.path.join(out, "wall_study.md"), "w") as handle:
        handle.write(markdown(rows, quick))
    counts = {status: sum(r["status"] == status for r in rows) for status in dict.fromkeys(r["status"] for r in rows)}
    print(f"wall_study: {len(rows)} cases ({', '.join(f'{n} {s}' for s, n in counts.items())}) -> "
          f"{os.path.join(out, 'wall_study.csv')}")
    if plots and rows:
        plot(rows, os.path.join(out, "wall_study.png"))
        plot_corners(rows, os.path.join(out, "wall_study_corners.png"))
    return 0
