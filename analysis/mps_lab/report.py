"""The comparison report: figures and report.md comparing methods on one scene.

    /usr/bin/python3 analysis/compare.py RUNS_FOLDER [--runs A B ...] [--times 0.1 0.2 ...] [--quiet]

RUNS_FOLDER is what `mps_lab compare` writes (it then calls analysis/compare.py with it, from
app/commands.cpp): one sub-folder per method (each a run folder with run.json and series.csv) and
summary.csv. Without summary.csv (runs made one by one), the table is computed here with the
same definitions. --runs takes run folders from anywhere instead of the sub-folders. Writes
into RUNS_FOLDER:

    front.png  height.png  snapshots.png  wall_pressure.png  energy.png
    pressure_validation.png (a scene whose `validation` block names experimental pressure records)
    animation.mp4 (ffmpeg installed) or animation.gif    report.md, report.html (self-contained)

Each method keeps its colour from the sorted list of the binary's methods (--binary, else
MPS_LAB_BINARY, else build/mps_lab, else mps_lab on PATH; without any, from the runs' methods).
"""
from __future__ import annotations

import base64
import csv
import html
import os
import re
import sys

from . import data, figures, methods, pressure

DEFAULT_TIMES = [0.1, 0.2, 0.3, 0.5, 1.0, 2.0]


def find_runs(root: str) -> list[str]:
    folders = [os.path.join(root, name) for name in sorted(os.listdir(root))]
    return [folder for folder in folders if os.path.isfile(os.path.join(folder, "run.json"))]


def summary_rows(root: str, runs: list[data.Run]) -> list[dict[str, str]]:
    """summary.csv as written by mps_lab compare, or the same columns computed here."""
    path = os.path.join(root, "summary.csv")
    if os.path.isfile(path):
        with open(path, newline="") as handle:
            rows = list(csv.DictReader(handle))
        if {row["method"] for row in rows} >= {run.method for run in runs}:
            return rows
    rows = []
    exp_t, exp_z = data.martin_moyce_front()
    exp_tau, exp_h = data.martin_moyce_height()
    for run in runs:
        t, z = run.front_curve()
        rms, largest, points = data.curve_error(t, z, exp_t, exp_z)
        shifted = data.best_shift_error(t, z, exp_t, exp_z)
        tau, h = run.height_curve()
        h_rms, h_max, h_points = data.curve_error(tau, h, exp_tau, exp_h)
        density = run.series["density_error"][1:]
        rows.append({
            "method": run.method, "status": run.summary["status"], "steps": str(run.summary.get("steps", 0)),
            "wall_seconds": str(run.summary.get("wall_seconds", 0.0)),
            "particle_steps_per_second": str(run.summary.get("fluid_particle_steps_per_second", 0.0)),
            "mean_solver_iterations": str(run.summary.get("solver", {}).get("mean_iterations", 0.0)),
            "front_rms": str(rms), "front_max": str(largest), "front_points": str(points),
            "front_best_shift": str(shifted[3]), "front_rms_shifted": str(shifted[0]),
            "height_rms": str(h_rms), "height_max": str(h_max), "height_points": str(h_points),
            "density_error_mean": str(density.mean() if density.size else 0.0),
            "density_error_max": str(density.max() if density.size else 0.0),
            "ghosts": str(run.summary.get("particles", {}).get("ghost_final", 0)),
        })
    return rows


def markdown_table(rows: list[dict[str, str]]) -> str:
    header = ("| method | status | steps | wall time [s] | particle-steps/s | mean solver iterations | "
              "front RMS | front max | best shift | front RMS (shifted) | height RMS | mean density error | ghosts |")
    lines = [header, "|" + "---|" * 13]
    for row in rows:
        f = {key: float(value) for key, value in row.items() if key not in ("method", "status")}
        lines.append(
            f"| {row['method']} | {row['status']} | {int(f['steps'])} | {f['wall_seconds']:.2f} | "
            f"{f['particle_steps_per_second'] / 1e6:.2f} M | {f['mean_solver_iterations']:.1f} | "
            f"{f['front_rms']:.3f} | {f['front_max']:.3f} | {f['front_best_shift']:+.3f} | "
            f"{f['front_rms_shifted']:.3f} | {f['height_rms']:.3f} | {100 * f['density_error_mean']:.2f} % | "
            f"{int(f['ghosts'])} |")
    return "\n".join(lines)


CAPTIONS = {
    "front": "Surge front against Martin & Moyce (1952)",
    "height": "Residual height at the back wall against Martin & Moyce (1952)",
    "snapshots": "Particles coloured by pressure, methods by rows",
    "wall_pressure": "Pressure at the wall sensor",
    "pressure_validation": "Wall pressure against the experiment",
    "energy": "Kinetic energy and density error",
    "animation": "Animation, all methods side by side",
}

DEFINITIONS = (
    "Front: Z = front/a against T = n t sqrt(g/a) at the 15 points of Martin & Moyce (1952) Table 2; "
    "height: H* = h/(n^2 a) against tau = t sqrt(g/a) at the points of Table 6; a and H = n^2 a are the "
    "column between the wall surfaces. The best shift is the T shift in [-0.3, 0.3] with the least RMS "
    "(positive: the simulation is ahead). Density error: mean |rho/rho_L - 1| over fluid particles with "
    "full support, one kernel for every method, averaged over the run. Definitions: docs/validation.md.")


PRESSURE_DEFINITIONS = (
    "Wall pressure (scenes with a `validation` block): p* = p/(rho g H) against T = t sqrt(g/H). Impact: the "
    "first T at which p* reaches the block's impact_threshold, the same rule for the experiment; peak: the "
    "largest p* from the impact to the end of the quasi-static window, per step (the sensor's _max column) and "
    "of the row means; quasi-static: over the block's window, the mean p* and the RMS of run - experiment at "
    "the experiment's points. Definitions: analysis/mps_lab/pressure.py, docs/validation.md.")


def pressure_table(runs: list[data.Run]) -> str:
    """Impact time, peaks and quasi-static error of each method at each sensor with a record;
    "" when the runs have no validation block."""
    lines = []
    for run in runs:
        validation = pressure.run_validation(run)
        if validation is None:
            continue
        for sensor in validation.records:
            if "pressure_" + sensor not in run.series:
                continue
            m = pressure.sensor_measures(run, sensor, validation)
            lines.append(f"| {run.method} | {sensor} | {m['impact_time']:.3f} ({m['exp_impact_time']:.3f}) | "
                         f"{m['peak_step']:.3f} / {m['peak_row']:.3f} ({m['exp_peak']:.3f}) | "
                         f"{m['quasi_static_level']:.3f} ({m['exp_quasi_static_level']:.3f}) | "
                         f"{m['quasi_static_rms']:.3f} |")
    if not lines:
        return ""
    header = ("| method | sensor | impact T (experiment) | peak p* step / row (experiment) | "
              "quasi-static p* (experiment) | quasi-static RMS |")
    return "\n".join([header, "|" + "---|" * 6, *lines])


def report_title(runs: list[data.Run]) -> tuple[str, str]:
    """The report's title and the line under it (scene, spacing, end time, threads, revision)."""
    first = runs[0].summary
    shared = first["shared"]
    return (f"Method comparison: {os.path.basename(first['scene'])}",
            f"Scene `{first['scene']}`, l0 = {shared['particle_spacing']:g} m, end time {shared['end_time']:g} s, "
            f"{first['threads']} threads, mps_lab {first['git_revision']}.")


def overrides_note(run: data.Run) -> str:
    """'; overrides: `a=1`, `b=2`' from run.json (the --set, --end-time and --load-setting
    assignments the run was made with, in the order applied), or '' when there are none."""
    overrides = run.summary.get("overrides") or []
    if not overrides:
        return ""
    return "; overrides: " + ", ".join(f"`{assignment}`" for assignment in overrides)


def write_report(root: str, runs: list[data.Run], rows: list[dict[str, str]], figures_written: dict[str, str]) -> str:
    title, subtitle = report_title(runs)
    lines = [f"# {title}", "", subtitle, "", "## Summary", "", markdown_table(rows), "", DEFINITIONS, ""]
    table = pressure_table(runs)
    if table:
        lines += ["## Wall pressure against the experiment", "", table, "", PRESSURE_DEFINITIONS, ""]
    for key, caption in CAPTIONS.items():
        if key in figures_written:
            lines += [f"## {caption}", "", f"![{caption}]({os.path.basename(figures_written[key])})", ""]
    lines += ["## Runs", ""]
    for run in runs:
        lines.append(f"- `{os.path.relpath(run.folder, root)}`: {run.summary['method_description']}"
                     f"{overrides_note(run)}")
    path = os.path.join(root, "report.md")
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")
    return path


MEDIA_TYPES = {".png": "image/png", ".gif": "image/gif", ".mp4": "video/mp4"}


def embedded_figure(path: str, caption: str) -> str:
    """One figure as HTML with its file inside (a data: URI): a picture or a looping video."""
    extension = os.path.splitext(path)[1].lower()
    with open(path, "rb") as handle:
        uri = f"data:{MEDIA_TYPES[extension]};base64," + base64.b64encode(handle.read()).decode("ascii")
    if extension == ".mp4":
        return f'<video controls loop muted src="{uri}" title="{html.escape(caption)}"></video>'
    return f'<img src="{uri}" alt="{html.escape(caption)}">'


def html_table(rows: list[dict[str, str]]) -> str:
    """The summary table of report.md as HTML (same columns, same formatting)."""
    return markdown_to_html_table(markdown_table(rows))


def markdown_to_html_table(table: str) -> str:
    lines = table.splitlines()
    cells = [[c.strip() for c in line.strip("|").split("|")] for line in lines if not line.startswith("|---")]
    head = "".join(f"<th>{html.escape(c)}</th>" for c in cells[0])
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in cells[1:])
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


HTML_STYLE = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
              "table{border-collapse:collapse;font-size:0.9em}td,th{border:1px solid #bbb;padding:3px 6px;"
              "text-align:right}td:first-child,th:first-child{text-align:left}img,video{max-width:100%}"
              "code{background:#eee;padding:0 3px}")


def write_html_report(root: str, runs: list[data.Run], rows: list[dict[str, str]],
                      figures_written: dict[str, str]) -> str:
    """report.html: report.md's content in one self-contained file (figures embedded), for a browser."""
    title, subtitle = report_title(runs)
    code = lambda text: re.sub(r"`([^`]*)`", r"<code>\1</code>", html.escape(text))  # noqa: E731
    parts = [f"<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>",
             f"<style>{HTML_STYLE}</style></head><body>", f"<h1>{html.escape(title)}</h1>", f"<p>{code(subtitle)}</p>",
             "<h2>Summary</h2>", html_table(rows), f"<p>{html.escape(DEFINITIONS)}</p>"]
    table = pressure_table(runs)
    if table:
        parts += ["<h2>Wall pressure against the experiment</h2>", markdown_to_html_table(table),
                  f"<p>{code(PRESSURE_DEFINITIONS)}</p>"]
    for key, caption in CAPTIONS.items():
        if key in figures_written:
            parts += [f"<h2>{html.escape(caption)}</h2>", embedded_figure(figures_written[key], caption)]
    parts.append("<h2>Runs</h2><ul>")
    for run in runs:
        parts.append(f"<li>{code('`' + os.path.relpath(run.folder, root) + '`')}: "
                     f"{html.escape(run.summary['method_description'])}{code(overrides_note(run))}</li>")
    parts.append("</ul></body></html>")
    path = os.path.join(root, "report.html")
    with open(path, "w") as handle:
        handle.write("\n".join(parts) + "\n")
    return path


def draw_figures(root: str, runs: list[data.Run], times: list[float], animation: bool,
                 styles: methods.MethodStyles) -> dict[str, str]:
    """Every figure of the report into root: {key: path} of those written."""
    written = {}
    for key, draw in [("front", figures.plot_front), ("height", figures.plot_height), ("energy", figures.plot_energy)]:
        written[key] = os.path.join(root, key + ".png")
        draw(runs, written[key], styles)
    written["snapshots"] = os.path.join(root, "snapshots.png")
    figures.plot_snapshots(runs, times, written["snapshots"])
    sensor_path = os.path.join(root, "wall_pressure.png")
    if figures.plot_sensor(runs, sensor_path, styles):
        written["wall_pressure"] = sensor_path
    validation_path = os.path.join(root, "pressure_validation.png")
    if figures.plot_pressure_validation(runs, validation_path, styles):
        written["pressure_validation"] = validation_path
    if animation:
        written["animation"] = figures.make_animation(runs, os.path.join(root, "animation"))
    return written


def compare(root: str, run_folders: list[str] | None = None, times: list[float] = DEFAULT_TIMES,
            animation: bool = True, quiet: bool = False, binary: str | None = None) -> int:
    """The figures and report.md of the runs in root (or of run_folders); 0, or 2 when there
    is nothing readable to compare (message on stderr)."""
    folders = run_folders or find_runs(root)
    if not folders:
        print(f"compare.py: {root}: no run folders (sub-folders with run.json)", file=sys.stderr)
        return 2
    try:
        runs = [data.load_run(folder) for folder in folders]
    except (OSError, KeyError, ValueError) as error:
        print(f"compare.py: cannot read the runs: {error}", file=sys.stderr)
        return 2
    os.makedirs(root, exist_ok=True)
    end = min(float(run.series["time"][-1]) for run in runs)
    shown = [t for t in times if t <= end + 1e-9] or [end]
    styles = methods.styles_for([run.method for run in runs], binary)
    written = draw_figures(root, runs, shown, animation, styles)
    rows = summary_rows(root, runs)
    report = write_report(root, runs, rows, written)
    page = write_html_report(root, runs, rows, written)
    if not quiet:
        print(f"compare.py: {len(written)} figures, {report} and {page} (self-contained)")
    return 0


def plot_runs(run_folders: list[str], out: str, binary: str | None = None) -> int:
    """front.png and height.png of several runs against Martin & Moyce, and their errors
    printed (analysis/plot_run.py); 2 when a folder is not a readable run."""
    runs = []
    for folder in run_folders:
        try:
            runs.append(data.load_run(folder))
        except (OSError, KeyError, ValueError) as error:
            print(f"plot_run.py: {folder}: not a readable run folder ({error})", file=sys.stderr)
            return 2
    os.makedirs(out, exist_ok=True)
    styles = methods.styles_for([run.method for run in runs], binary)
    figures.plot_front(runs, os.path.join(out, "front.png"), styles)
    figures.plot_height(runs, os.path.join(out, "height.png"), styles)
    exp_t, exp_z = data.martin_moyce_front()
    for run in runs:
        t, z = run.front_curve()
        rms, largest, points = data.curve_error(t, z, exp_t, exp_z)
        shifted = data.best_shift_error(t, z, exp_t, exp_z)
        print(f"{run.folder}: front RMS {rms:.3f} (max {largest:.3f}, {points} points); "
              f"best shift {shifted[3]:+.3f} -> RMS {shifted[0]:.3f}")
    print(f"figures: {os.path.join(out, 'front.png')}, {os.path.join(out, 'height.png')}")
    return 0
