"""Floating and submerged bodies against theory (issue 15, item 4; docs/bodies.md "Floating box:
draft and heave" and "Rising and sinking boxes").

Scenes (each a polygon body, so its surface and mass are the same at every l0):
  - scenes/floating_box_heave.json: a box B x H = 0.2 x 0.1 m, rho_b = 500 kg/m^3, released at
    rest a few mm off its equilibrium draft d = rho_b/rho_w H (`rest_level`). The equilibrium
    draft (the rest level less the bottom's time-mean height over whole heave periods after the
    first one) against d, and the
    heave (a damped sinusoid fitted to the centre height) against T = 2 pi sqrt((m + a33) /
    (rho g B)) with the Lewis-form added mass a33 (below).
  - scenes/rising_box.json, scenes/sinking_box.json: a square a = 0.06 m, rho_b = 500 / 1500,
    released at rest; the largest vertical speed (0.05 s running mean) against the terminal
    speed U = sqrt(2 |rho_b - rho_w| g a / (rho_w C_d)).

The runs differ from the scenes only by --set particle_spacing (the time step is the scene's:
the body speeds, below 0.6 m/s, keep the Courant number u dt / l0 below 0.06 at l0 = 0.005 m).
Every registered method is run; a method that cannot report loads on a body stops at start
(exit 2, the scene's one-line error) and is listed as such.
"""
from __future__ import annotations

import csv
import json
import math
import os

import numpy as np

from mps_lab import data, runner
from mps_lab.methods import registered_methods
from mps_lab.studies import common

# Study cases: name -> (scene, default spacings, m).
CASES = {
    "heave": ("scenes/floating_box_heave.json", (0.025, 0.0125, 0.00625)),
    "rising": ("scenes/rising_box.json", (0.02, 0.01)),
    "sinking": ("scenes/sinking_box.json", (0.02, 0.01)),
}
HEAVE_FIT_END = 1.0  # s: about the first period; the longest waves the box radiates (sqrt(g h) =
#                      1.7 m/s) are back from the tank's sides (0.5 m away) after 0.6 s, the
#                      wave group (g / (2 omega) = 0.5 m/s) after 2 s, and the tank's first
#                      symmetric sloshing mode has T = 0.92 s: later swings are not the box's alone
# a33(omega) / a33(infinity) once assumed near omega^2 B/(2g) ~ 0.6: the band of the table's
# period_estimate_low/high columns, superseded by linear theory in the tank (studies/heave_theory.py,
# analysis/heave_linear_theory.py; docs/bodies.md "Linear theory").
ADDED_MASS_BAND = (0.6, 1.0)
DRAG_COEFFICIENT = 2.0  # square cylinder broadside, Re 1e4-1e5 (Delany & Sorensen 1953; Hoerner 1965)
SPEED_WINDOW = 0.05  # s: running mean of the body's vertical speed
HEAVE_COLUMNS = ["method", "l0", "status", "draft_theory", "rest_level", "release_offset", "draft", "draft_error", "period", "damping_ratio",
                 "natural_period", "period_estimate_low", "period_estimate_high", "frequency_number", "theta_max"]
DROP_COLUMNS = ["case", "method", "l0", "status", "speed_max", "speed_drag", "speed_drag_blocked", "reynolds",
                "time_of_max", "theta_max"]


def polygon_box(polygon: list) -> tuple[float, float, float, float]:
    """(x_min, y_min, x_max, y_max) of an axis-aligned rectangle's vertices, m."""
    xs, ys = [p[0] for p in polygon], [p[1] for p in polygon]
    return min(xs), min(ys), max(xs), max(ys)


def scene_geometry(scene: dict) -> dict:
    """What the theory needs from a scene with one rectangular polygon body."""
    body = scene["walls"]["obstacles"][0]
    x0, y0, x1, y1 = polygon_box(body["polygon"])
    gx, gy = scene["physics"]["gravity"]
    return {"width": x1 - x0, "height": y1 - y0, "centre_y": 0.5 * (y0 + y1), "rho_b": body["body"]["density"],
            "rho_w": scene["physics"]["density"], "g": math.hypot(gx, gy), "nu": scene["physics"]["kinematic_viscosity"],
            "level": max(block["max"][1] for block in scene["fluid_blocks"]),
            "tank_width": scene["domain"]["max"][0] - scene["domain"]["min"][0]}


def lewis_coefficients(half_beam_draft: float, area_coefficient: float) -> tuple[float, float]:
    """Lewis (1929) form parameters (a1, a3) of a section with H0 = B/(2T) and sigma = A/(B T):
    H0 = (1 + a1 + a3)/(1 - a1 + a3), sigma = pi (1 - a1^2 - 3 a3^2) / (4 ((1 + a3)^2 - a1^2))
    (Journee & Massie 2001, Offshore Hydromechanics, section 7.3.1), solved by Newton's method."""
    a1, a3 = 0.3, -0.1
    for _ in range(100):
        def residual(p, q):
            return (half_beam_draft - (1 + p + q) / (1 - p + q),
                    area_coefficient - math.pi * (1 - p * p - 3 * q * q) / (4 * ((1 + q) ** 2 - p * p)))
        r = residual(a1, a3)
        h = 1e-7
        j = [[(residual(a1 + h, a3)[k] - r[k]) / h, (residual(a1, a3 + h)[k] - r[k]) / h] for k in range(2)]
        det = j[0][0] * j[1][1] - j[0][1] * j[1][0]
        a1 -= (r[0] * j[1][1] - r[1] * j[0][1]) / det
        a3 -= (j[0][0] * r[1] - j[1][0] * r[0]) / det
        if abs(r[0]) + abs(r[1]) < 1e-13:
            break
    return a1, a3


def heave_added_mass_infinite(geometry: dict) -> float:
    """Infinite-frequency heave added mass of the box's immersed rectangle, kg/m: the Lewis form's
    a33 = rho pi B^2 / 8 C, C = ((1 + a1)^2 + 3 a3^2) / (1 + a1 + a3)^2 (Journee & Massie 2001)."""
    draft = geometry["rho_b"] / geometry["rho_w"] * geometry["height"]
    a1, a3 = lewis_coefficients(geometry["width"] / (2 * draft), 1.0)
    coefficient = ((1 + a1) ** 2 + 3 * a3 ** 2) / (1 + a1 + a3) ** 2
    return geometry["rho_w"] * math.pi * geometry["width"] ** 2 / 8 * coefficient


def heave_theory(geometry: dict) -> dict:
    """Draft d = rho_b/rho_w H, mass m = rho_b B H, and the undamped heave period
    T = 2 pi sqrt((m + a33) / (rho_w g B)) for a33 over ADDED_MASS_BAND x a33(infinity)."""
    mass = geometry["rho_b"] * geometry["width"] * geometry["height"]
    stiffness = geometry["rho_w"] * geometry["g"] * geometry["width"]  # N/m per m of heave
    a33 = heave_added_mass_infinite(geometry)
    periods = [2 * math.pi * math.sqrt((mass + f * a33) / stiffness) for f in ADDED_MASS_BAND]
    return {"draft": geometry["rho_b"] / geometry["rho_w"] * geometry["height"], "mass": mass,
            "added_mass_infinite": a33, "period_low": periods[0], "period_high": periods[1]}


def linear_heave_fit(t: np.ndarray, y: np.ndarray, decay: float, omega: float) -> tuple[float, np.ndarray]:
    """For a given decay rate and omega, y = y0 + exp(-decay t)(a sin(omega t) + b cos(omega t)) is
    linear in (y0, a, b): its least-squares residual and coefficients."""
    envelope = np.exp(-decay * t)
    basis = np.column_stack([np.ones_like(t), envelope * np.sin(omega * t), envelope * np.cos(omega * t)])
    coefficients, *_ = np.linalg.lstsq(basis, y, rcond=None)
    return float(np.sum((basis @ coefficients - y) ** 2)), coefficients


def fit_damped_heave(t: np.ndarray, y: np.ndarray) -> dict:
    """y = y0 + A exp(-zeta omega_n t) sin(omega_d t + phi) fitted by least squares over the samples
    given (numpy only): a grid over omega_d (periods 0.3-1.5 s) and the decay rate (0-20 1/s),
    linear least squares for the rest, refined twice on a grid ten times finer around the best.
    Returns the damped period 2 pi/omega_d, zeta and y0."""
    omegas = np.linspace(2 * math.pi / 1.5, 2 * math.pi / 0.3, 200)
    decays = np.linspace(0.0, 20.0, 101)
    for _ in range(3):
        best = min((linear_heave_fit(t, y, decay, omega)[0], decay, omega) for omega in omegas for decay in decays)
        _, decay, omega = best
        d_omega, d_decay = omegas[1] - omegas[0], decays[1] - decays[0]
        omegas = np.linspace(omega - d_omega, omega + d_omega, 21)
        decays = np.linspace(max(decay - d_decay, 0.0), decay + d_decay, 21)
    _, coefficients = linear_heave_fit(t, y, decay, omega)
    zeta = decay / math.hypot(omega, decay)  # decay = zeta omega_n, omega_d = omega_n sqrt(1 - zeta^2)
    return {"y0": float(coefficients[0]), "amplitude": float(math.hypot(coefficients[1], coefficients[2])),
            "period": 2 * math.pi / omega, "damping_ratio": zeta, "natural_period": 2 * math.pi / math.hypot(omega, decay)}


def rest_level(series: dict, geometry: dict, l0: float) -> float:
    """The water level at rest with the body at its draft d, m. The fluid's particles sit on the
    lattice domain.min + k l0, the first wall particles of the bed and the sides on the domain's
    edges, and the wall surfaces l0/2 inside them (docs/walls.md): the water is N l0^2 of area
    (its lattice points outside the body) over a bed at y = l0/2 between sides W - l0 apart, so
    (W - l0)(eta - l0/2) = N l0^2 + B d. (Not the fluid block's top: with l0 = 0.025 m the block
    [0, 0.3] gives a surface at 0.2875 m.)"""
    draft = geometry["rho_b"] / geometry["rho_w"] * geometry["height"]
    area = series["fluid_particles"][0] * l0 * l0 + geometry["width"] * draft
    return l0 / 2 + area / (geometry["tank_width"] - l0)


def heave_metrics(series: dict, geometry: dict, l0: float) -> dict:
    """Draft (the rest level less the bottom's time-mean height over whole periods from the end
    of the first one) and the fitted heave of one run; the draft error is (d_measured - d) / d,
    positive when deeper."""
    t, y = series["time"], series["body_0_y"]
    level = rest_level(series, geometry, l0)
    if float(np.min(y)) < level - geometry["height"]:  # its centre went H below the surface: it sank
        return {"floats": False, "draft": float("nan")}
    fit = fit_damped_heave(t[t <= HEAVE_FIT_END], y[t <= HEAVE_FIT_END])
    period = fit["period"]
    whole = math.floor((t[-1] - period) / period)
    window = (t >= period) & (t <= period * (1 + whole))
    theory = heave_theory(geometry)
    draft = level - (float(np.mean(y[window])) - geometry["height"] / 2)
    omega = 2 * math.pi / period
    return {"floats": True, "draft_theory": theory["draft"], "draft": draft, "rest_level": level,
            "rest_centre": level - theory["draft"] + geometry["height"] / 2,
            "release_offset": float(y[0]) - (level - theory["draft"] + geometry["height"] / 2),
            "draft_error": (draft - theory["draft"]) / theory["draft"], "period": period,
            "damping_ratio": fit["damping_ratio"], "natural_period": fit["natural_period"],
            "period_estimate_low": theory["period_low"], "period_estimate_high": theory["period_high"],
            "frequency_number": omega ** 2 * geometry["width"] / (2 * geometry["g"]),
            "theta_max": float(np.max(np.abs(series["body_0_theta"])))}


def drag_speed(geometry: dict, drag_coefficient: float = DRAG_COEFFICIENT) -> float:
    """Terminal speed of a 2-D box, weight less buoyancy = drag: |rho_b - rho_w| g B H =
    1/2 rho_w C_d B U^2, m/s."""
    net = abs(geometry["rho_b"] - geometry["rho_w"]) * geometry["g"] * geometry["width"] * geometry["height"]
    return math.sqrt(2 * net / (geometry["rho_w"] * drag_coefficient * geometry["width"]))


def blocked_drag_coefficient(geometry: dict) -> float:
    """C_d seen in the tank: the flow past the body is faster by W/(W - B) (continuity), and the
    drag scales with its square (a first blockage estimate, as Maskell 1963 for closed tunnels)."""
    ratio = geometry["tank_width"] / (geometry["tank_width"] - geometry["width"])
    return DRAG_COEFFICIENT * ratio ** 2


def drop_metrics(series: dict, geometry: dict) -> dict:
    """Largest vertical speed of the body (running mean over SPEED_WINDOW), its time, and the
    drag estimates."""
    t, v = series["time"], series["body_0_v"]
    samples = max(1, int(round(SPEED_WINDOW / max(float(np.median(np.diff(t))), 1e-12))))
    speed = np.convolve(np.abs(v), np.ones(samples) / samples, mode="valid")
    k = int(np.argmax(speed))
    u_drag = drag_speed(geometry)
    return {"speed_max": float(speed[k]), "time_of_max": float(t[k + samples // 2]), "speed_drag": u_drag,
            "speed_drag_blocked": drag_speed(geometry, blocked_drag_coefficient(geometry)),
            "reynolds": u_drag * geometry["width"] / geometry["nu"],
            "theta_max": float(np.max(np.abs(series["body_0_theta"])))}


def requests(root: str, out: str, methods: list[str], cases: dict):
    """One CaseRequest per case x method x spacing."""
    for case, (scene, spacings) in cases.items():
        for method in methods:
            for l0 in spacings:
                name = f"{case}_{method}_{l0:g}"
                folder = os.path.join(out, name)
                arguments = ["run", os.path.join(root, scene), "--method", method, "--out", folder, "--quiet",
                             "--set", f"particle_spacing={l0}", "--set", "output.series_every_steps=2",
                             "--set", "output.frame_every_steps=1000000"]
                yield runner.CaseRequest(name, arguments, folder, {"case": case, "method": method, "l0": l0,
                                                                   "scene": os.path.join(root, scene)})


def status_of(result) -> str:
    if result.ok:
        return "completed"
    if result.exit_code == runner.EXIT_BAD_INPUT:
        return "cannot run: " + result.last_error_line()
    return result.describe()


def row_of(request, status: str) -> dict:
    """The case's metrics from its series.csv (also for a run that diverged part way)."""
    row = dict(request.extra, folder=request.folder, status=status)
    series_path = os.path.join(request.folder, "series.csv")
    if not status.startswith("cannot run") and os.path.exists(series_path):
        with open(request.extra["scene"]) as handle:
            geometry = scene_geometry(json.load(handle))
        series = data.read_csv_columns(series_path)
        if len(series["time"]) > 20:
            if request.extra["case"] == "heave":
                row.update(heave_metrics(series, geometry, request.extra["l0"]))
                if not row["floats"]:
                    row["status"] += " (the box sank)"
            else:
                row.update(drop_metrics(series, geometry))
    return row


def completed_before(request) -> bool:
    """A run folder this study already completed (the study resumes where it stopped)."""
    summary = common.run_summary(request.folder)
    return summary is not None and summary.get("status") == "completed"


def observed_orders(rows: list[dict]) -> dict[str, float]:
    """Per method, the order p of the draft error between its two finest spacings,
    log(e_coarse / e_fine) / log(l0_coarse / l0_fine)."""
    orders = {}
    for method in sorted({r["method"] for r in rows}):
        done = sorted((r for r in rows if r["method"] == method and r.get("floats")), key=lambda r: -r["l0"])
        if len(done) >= 2 and done[-1]["draft_error"] * done[-2]["draft_error"] > 0:
            coarse, fine = done[-2], done[-1]
            orders[method] = math.log(coarse["draft_error"] / fine["draft_error"]) / math.log(coarse["l0"] / fine["l0"])
    return orders


def write_tables(rows: list[dict], out: str) -> None:
    def write(path, columns, selected):
        with open(path, "w", newline="") as handle:
            writer = csv.DictWriter(handle, columns, extrasaction="ignore")
            writer.writeheader()
            for row in sorted(selected, key=lambda r: (r.get("case", ""), r["method"], -r["l0"])):
                writer.writerow({k: (f"{v:.5g}" if isinstance(v, float) and k != "l0" else v) for k, v in row.items()})
    write(os.path.join(out, "floating_box_heave.csv"), HEAVE_COLUMNS, [r for r in rows if r["case"] == "heave"])
    write(os.path.join(out, "rising_sinking_box.csv"), DROP_COLUMNS, [r for r in rows if r["case"] != "heave"])


def plot(rows: list[dict], path: str) -> None:
    """Three panels: heave y(t) at the finest spacing per method, draft error against l0, and
    the vertical speed of the rising and sinking boxes against the drag estimate."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(1, 3, figsize=(14, 4.0))
    heave = [r for r in rows if r["case"] == "heave" and r.get("floats")]
    for row in heave:
        series = data.read_csv_columns(os.path.join(row["folder"], "series.csv"))
        axes[0].plot(series["time"], series["body_0_y"] - row["rest_centre"], lw=0.8, label=f"{row['method']} l0 = {row['l0']:g}")
    axes[0].set_xlabel("t, s")
    axes[0].axhline(0.0, color="k", lw=0.5)
    axes[0].axvspan(0.0, HEAVE_FIT_END, color="0.92", zorder=0)
    axes[0].set_ylabel("box centre - its rest position, m (fit: grey)")
    axes[0].legend(fontsize=6)
    for method in sorted({r["method"] for r in heave}):
        done = sorted((r for r in heave if r["method"] == method), key=lambda r: r["l0"])
        axes[1].loglog([r["l0"] for r in done], [abs(r["draft_error"]) for r in done], "o-", label=method)
    axes[1].axhline(0.02, color="k", ls=":", label="2 % (issue 15)")
    axes[1].set_xlabel("l0, m")
    axes[1].set_ylabel("|draft error| / draft")
    axes[1].legend(fontsize=7)
    for row in (r for r in rows if r["case"] != "heave" and "speed_max" in r):
        series = data.read_csv_columns(os.path.join(row["folder"], "series.csv"))
        samples = max(1, int(round(SPEED_WINDOW / float(np.median(np.diff(series["time"]))))))
        mean = np.convolve(np.abs(series["body_0_v"]), np.ones(samples) / samples, mode="same")
        axes[2].plot(series["time"], mean, "-" if row["case"] == "rising" else "--", lw=0.8,
                     label=f"{row['case']} {row['method']} l0 = {row['l0']:g}")
    drops = [r for r in rows if r["case"] != "heave" and "speed_drag" in r]
    if drops:
        axes[2].axhline(drops[0]["speed_drag"], color="k", ls="--", label="drag, C_d = 2.0")
        axes[2].axhline(drops[0]["speed_drag_blocked"], color="k", ls=":", label="drag with blockage")
    axes[2].set_xlabel("t, s")
    axes[2].set_ylabel(f"|v| of the box ({SPEED_WINDOW} s running mean), m/s")
    axes[2].set_ylim(0.0, 1.0)
    axes[2].legend(fontsize=5)
    figure.tight_layout()
    figure.savefig(path, dpi=120)


def earlier_cases(root: str, out: str, cases: dict, names: set[str]):
    """Requests for the completed case folders of DIR that this invocation did not ask for (another
    method or spacing run before), so that the tables hold every case DIR has."""
    for entry in sorted(os.listdir(out)):
        parts = entry.split("_")
        if entry in names or len(parts) != 3 or parts[0] not in cases:
            continue
        folder = os.path.join(out, entry)
        summary = common.run_summary(folder)
        if summary is None or summary.get("status") != "completed":
            continue
        yield runner.CaseRequest(entry, [], folder, {"case": parts[0], "method": parts[1], "l0": float(parts[2]),
                                                     "scene": os.path.join(root, cases[parts[0]][0])})


def run_study(root: str, out: str, binary: str, methods: list[str] | None, cases: dict, parallel: int,
              timeout: float) -> list[dict]:
    methods = methods or registered_methods(binary)
    os.makedirs(out, exist_ok=True)
    rows = []
    todo = []
    for request in requests(root, out, methods, cases):
        if completed_before(request):
            rows.append(row_of(request, "completed"))
        else:
            todo.append(request)
    for request, result in runner.run_cases(binary, todo, parallel=parallel, timeout=timeout,
                                            threads=runner.threads_per_case(parallel)):
        row = row_of(request, status_of(result))
        print(f"{request.name}: {row['status']} "
              + ", ".join(f"{k} {row[k]:.4g}" for k in ("draft_error", "period", "damping_ratio", "speed_max")
                          if k in row), flush=True)
        rows.append(row)
    names = {row["folder"].rstrip("/").split("/")[-1] for row in rows}
    rows += [row_of(request, "completed") for request in earlier_cases(root, out, cases, names)]
    write_tables(rows, out)
    plot(rows, os.path.join(out, "floating_bodies.png"))
    return rows
