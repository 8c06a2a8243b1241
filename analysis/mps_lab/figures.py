"""Figures of mps_lab runs: one function per figure, shared by plot_run.py and the report.

Every function takes loaded runs (data.Run), a path and, where runs are told apart by
colour, the method styles (methods.MethodStyles: one colour per registered method), and
writes one PNG (or, for the animation, a GIF or MP4). Axes carry the non-dimensional
definitions or units. Importing this module sets the shared matplotlib style.
"""
from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402

from . import data  # noqa: E402
from .methods import MethodStyles  # noqa: E402

plt.rcParams.update({
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "savefig.dpi": 150,
})

def run_colours(runs: list[data.Run], styles: MethodStyles) -> list[str]:
    """One colour per run: its method's, or, when two runs share a method (plot_run.py on
    several runs of one method), one per run."""
    methods = [run.method for run in runs]
    if len(set(methods)) == len(methods):
        return [styles.colour(method) for method in methods]
    return [f"C{k % 10}" for k in range(len(runs))]


def label_of(run: data.Run) -> str:
    return f"{run.method} (l0 = {run.summary['shared']['particle_spacing']:g} m)"


def plot_against_experiment(runs: list[data.Run], path: str, styles: MethodStyles, curve_of, experiment,
                            marker: str, labels: dict) -> None:
    """One quantity of every run against its experimental points: curve_of(run) -> (x, y)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    exp_x, exp_y = experiment
    for run, colour in zip(runs, run_colours(runs, styles)):
        x, y = curve_of(run)
        rms, _, _ = data.curve_error(x, y, exp_x, exp_y)
        ax.plot(x, y, color=colour, label=f"{label_of(run)}: RMS {rms:.3f}")
    ax.plot(exp_x, exp_y, marker, color="k", mfc="none", linestyle="none", label="Martin & Moyce (1952), $n^2 = 2$")
    ax.set_xlabel(labels["x"])
    ax.set_ylabel(labels["y"])
    ax.set_xlim(*labels["xlim"])
    ax.set_ylim(*labels["ylim"])
    ax.legend(loc=labels["legend"])
    ax.set_title(labels["title"])
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_front(runs: list[data.Run], path: str, styles: MethodStyles) -> None:
    """Surge front Z = z/a against T = n t sqrt(g/a), with Martin & Moyce (1952) Table 2."""
    plot_against_experiment(runs, path, styles, lambda run: run.front_curve(), data.martin_moyce_front(), "o",
                            {"x": r"$T = n\,t\,\sqrt{g/a}$", "y": r"$Z = z/a$", "xlim": (0, 4.0), "ylim": (1, 4.6),
                             "legend": "upper left", "title": "Surge front"})


def plot_height(runs: list[data.Run], path: str, styles: MethodStyles) -> None:
    """Residual height H* = h/(n^2 a) against tau = t sqrt(g/a), with Martin & Moyce Table 6."""
    plot_against_experiment(runs, path, styles, lambda run: run.height_curve(), data.martin_moyce_height(), "s",
                            {"x": r"$\tau = t\,\sqrt{g/a}$", "y": r"$H^* = h/(n^2 a)$", "xlim": (0, 8.0),
                             "ylim": (0, 1.05), "legend": "upper right",
                             "title": "Residual column height at the back wall"})


def read_frame(path: str) -> np.ndarray:
    """A CSV frame as an array with columns x, y, vx, vy, pressure, type."""
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def frame_times(run: data.Run) -> list[tuple[float, str]]:
    """(time, path) of every CSV frame of a run, the time read from series.csv."""
    time_of_step = dict(zip(run.series["step"].astype(int), run.series["time"]))
    return [(float(time_of_step.get(step, math.nan)), path) for step, path in run.frames()]


def nearest_frame(frames: list[tuple[float, str]], time: float) -> tuple[float, str]:
    return min(frames, key=lambda frame: abs(frame[0] - time))


def pressure_scale(frames: list[np.ndarray]) -> Normalize:
    """One colour scale for all panels: 0 to the 99th percentile of the fluid pressure shown."""
    pressures = np.concatenate([frame[frame[:, 5] == 0, 4] for frame in frames] or [np.zeros(1)])
    top = float(np.percentile(pressures, 99)) if pressures.size else 1.0
    return Normalize(vmin=0.0, vmax=max(top, 1.0))


def draw_particles(ax, frame: np.ndarray, norm: Normalize, size: float):
    wall = frame[:, 5] == 1
    fluid = frame[:, 5] == 0
    ax.scatter(frame[wall, 0], frame[wall, 1], s=size, c="0.6", marker="s", linewidths=0)
    points = ax.scatter(frame[fluid, 0], frame[fluid, 1], s=size, c=frame[fluid, 4], cmap="viridis", norm=norm,
                        linewidths=0)
    ax.set_aspect("equal")
    ax.grid(False)
    return points


def marker_size(run: data.Run, axis_width_inches: float, domain_width: float) -> float:
    """Scatter marker area (points^2) that draws a particle about l0 wide."""
    l0 = run.summary["shared"]["particle_spacing"]
    diameter_points = 72.0 * axis_width_inches * l0 / domain_width
    return max(0.5, 0.8 * diameter_points ** 2)


def domain_of(run: data.Run) -> tuple[list[float], list[float]]:
    scene = run.summary["scene_resolved"]
    return scene["domain"]["min"], scene["domain"]["max"]


def plot_snapshots(runs: list[data.Run], times: list[float], path: str) -> None:
    """Particles coloured by pressure: methods by rows, times by columns, one colour scale."""
    low, high = domain_of(runs[0])
    margin = 0.05
    width, height = high[0] - low[0] + 2 * margin, high[1] - low[1] + 2 * margin
    panel_width = 2.6
    fig, axes = plt.subplots(len(runs), len(times), figsize=(panel_width * len(times) + 1.2,
                                                             panel_width * height / width * len(runs) + 0.8),
                             squeeze=False)
    chosen = [[read_frame(nearest_frame(frame_times(run), t)[1]) for t in times] for run in runs]
    norm = pressure_scale([frame for row in chosen for frame in row])
    points = None
    for r, run in enumerate(runs):
        frames = frame_times(run)
        size = marker_size(run, panel_width, width)
        for c, t in enumerate(times):
            ax = axes[r][c]
            actual, _ = nearest_frame(frames, t)
            points = draw_particles(ax, chosen[r][c], norm, size)
            ax.set_xlim(low[0] - margin, high[0] + margin)
            ax.set_ylim(low[1] - margin, high[1] + margin)
            ax.set_xticks([])
            ax.set_yticks([])
            if r == 0:
                ax.set_title(f"t = {actual:.2f} s")
            if c == 0:
                ax.set_ylabel(run.method)
    fig.subplots_adjust(left=0.04, right=0.9, bottom=0.03, top=0.9, wspace=0.05, hspace=0.08)
    bar = fig.add_axes([0.92, 0.1, 0.015, 0.75])
    fig.colorbar(points, cax=bar, label="pressure [Pa]")
    fig.suptitle("Particles coloured by pressure (one scale for all panels; walls grey)")
    fig.savefig(path)
    plt.close(fig)


def plot_sensor(runs: list[data.Run], path: str, styles: MethodStyles) -> bool:
    """Pressure at the scene's first pressure sensor against time; False if there is none."""
    sensors = [name for name in runs[0].series if name.startswith("pressure_")]
    if not sensors:
        return False
    name = sensors[0]
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    for run, colour in zip(runs, run_colours(runs, styles)):
        if name in run.series:
            ax.plot(run.series["time"], run.series[name] / 1000.0, color=colour, lw=1.0, label=run.method)
    position = next((s["position"] for s in runs[0].summary["scene_resolved"].get("diagnostics", {})
                     .get("pressure_sensors", []) if "pressure_" + s["name"] == name), None)
    where = f" at ({position[0]:g}, {position[1]:g}) m" if position else ""
    ax.set_xlabel("t [s]")
    ax.set_ylabel("pressure [kPa]")
    ax.set_title(f"Wall sensor '{name[len('pressure_'):]}'{where}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True


def plot_pressure_validation(runs: list[data.Run], path: str, styles: MethodStyles) -> bool:
    """Each method's sensor history (series rows, p/(rho g H) against T = t sqrt(g/H)) over the
    experimental record named by the scene's validation block, one panel per record; False if
    the runs have none (analysis/mps_lab/pressure.py)."""
    from . import pressure
    validation = pressure.run_validation(runs[0])
    if validation is None or not validation.records:
        return False
    sensors = list(validation.records)
    fig, axes = plt.subplots(len(sensors), 1, figsize=(8.0, 3.2 * len(sensors)), sharex=True, squeeze=False)
    for axis, sensor in zip(axes[:, 0], sensors):
        for run, colour in zip(runs, run_colours(runs, styles)):
            if "pressure_" + sensor in run.series:
                t, mean, _ = pressure.run_curves(run, sensor, validation)
                axis.plot(t, mean, color=colour, lw=0.7, label=run.method)
        exp_t, exp_p = pressure.read_record(validation.records[sensor])
        axis.plot(exp_t, exp_p, "k.-", lw=1.2, ms=3, label="experiment")
        axis.axvspan(*validation.quasi_static, color="0.9", zorder=0)
        axis.set_ylabel(f"{sensor}: " + r"$p/\rho g H$")
        axis.legend(fontsize=7, ncol=3)
    axes[-1, 0].set_xlabel(r"$T = t\sqrt{g/H}$" + f" (H = {validation.length_scale:g} m)")
    axes[0, 0].set_title("Wall pressure against the experiment (grey: quasi-static window)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True


def plot_energy(runs: list[data.Run], path: str, styles: MethodStyles) -> None:
    """Kinetic energy and the common density error against time."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)
    for run, colour in zip(runs, run_colours(runs, styles)):
        top.plot(run.series["time"], run.series["kinetic_energy"], color=colour, label=run.method)
        bottom.plot(run.series["time"], 100.0 * run.series["density_error"], color=colour, lw=1.0,
                    label=run.method)
    top.set_ylabel("kinetic energy [J/m]")
    top.legend()
    top.set_title("Kinetic energy per metre of depth")
    bottom.set_ylabel(r"mean $|\rho/\rho_L - 1|$ [%]")
    bottom.set_xlabel("t [s]")
    bottom.set_title("Density error (same kernel for every method)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def ffmpeg_available() -> bool:
    """Whether matplotlib can write MP4 (Debian's ffmpeg); without it the animation is a GIF."""
    return animation.writers.is_available("ffmpeg")


def make_animation(runs: list[data.Run], path_stem: str, max_frames: int = 80) -> str:
    """All methods side by side; MP4 when ffmpeg is available, else an animated GIF.

    Returns the path written."""
    low, high = domain_of(runs[0])
    margin = 0.05
    width, height = high[0] - low[0] + 2 * margin, high[1] - low[1] + 2 * margin
    panel_width = 4.0
    frames = [frame_times(run) for run in runs]
    times = [t for t, _ in frames[0]]
    if len(times) > max_frames:
        stride = math.ceil(len(times) / max_frames)
        times = times[::stride]
    fig, axes = plt.subplots(1, len(runs), figsize=(panel_width * len(runs), panel_width * height / width + 0.7),
                             squeeze=False)
    sample = [read_frame(nearest_frame(frames[r], times[len(times) // 3])[1]) for r in range(len(runs))]
    norm = pressure_scale(sample)

    def draw(index: int):
        for r, run in enumerate(runs):
            ax = axes[0][r]
            ax.clear()
            t, frame_path = nearest_frame(frames[r], times[index])
            draw_particles(ax, read_frame(frame_path), norm, marker_size(run, panel_width, width))
            ax.set_xlim(low[0] - margin, high[0] + margin)
            ax.set_ylim(low[1] - margin, high[1] + margin)
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(f"{run.method}, t = {t:.2f} s")
        return []

    movie = animation.FuncAnimation(fig, draw, frames=len(times), blit=False)
    fig.tight_layout()
    if ffmpeg_available():
        path = path_stem + ".mp4"
        movie.save(path, writer=animation.FFMpegWriter(fps=10))
    else:
        path = path_stem + ".gif"
        movie.save(path, writer=animation.PillowWriter(fps=10))
    plt.close(fig)
    return path
