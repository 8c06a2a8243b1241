"""Wall pressure against Buchner (2002) / Zhou, Kat & Buchner (1999): every method at several
spacings on scenes/dambreak_buchner.json, the impact time, peak and quasi-static error at the
probes P1 and P2 (analysis/mps_lab/pressure.py defines them), a CSV and a Markdown table and a
figure of each method's P1 history over the experiment (docs/validation.md, "Wall pressure:
Buchner 2002").

Each case differs from the scene by --set only: the spacing l0 = H/n, the time step
0.02 s/m x l0 (the fixed-step methods: Courant number 0.13 at the impact's 6.5 m/s), every
`max_time_step` the scene's method blocks give scaled with l0 (the scene's are 0.08 s/m x l0;
docs/methods/eisph.md: scale it with l0), and
the probes' y = l0/2 + height above the bed (the bed's surface is l0/2 above y = 0). A case
folder is OUT/H<n>/<method>; --collect reads the folders that exist and runs nothing.

With a schemes plan (analysis/sweeps/pressure_schemes.json: a method and named lists of --set
assignments), the plan's method runs once per scheme instead, in OUT/H<n>/<method>-<scheme>,
and the tables are buchner_pressure_schemes.{csv,md} (docs/methods/mps.md, "Pressure
schemes")."""
from __future__ import annotations

import json
import math
import os

from mps_lab import data, pressure, runner
from mps_lab.studies.common import formatted, write_study_tables

SCENE = "scenes/dambreak_buchner.json"
HEIGHT = 0.6  # m, H of the experiment
PROBES = {"P1": 0.16, "P2": 0.584}  # m, centre of each probe above the bed (analysis/validation/buchner_2002_p*.csv)
RIGHT_WALL_X = 3.24  # m, the right wall's first particle line (the scene's domain.max)
DEFAULT_DIVISIONS = (40, 60, 80)  # l0 = H / n
DEFAULT_TIMEOUT = 4 * 3600.0  # s per case
MEASURES = ["impact_time", "impact_time_error", "peak_step", "peak_row", "peak_row_error", "quasi_static_level",
            "quasi_static_rms"]
COLUMNS = (["label", "l0", "method", "scheme", "status", "steps", "wall_seconds"]
           + [f"{sensor}_{measure}" for sensor in PROBES for measure in MEASURES])


def scaled_step_bounds(scene: str, l0: float) -> list[str]:
    """--set of every method block of the scene that gives a `max_time_step`, scaled with the
    spacing (the scene's value is 0.08 s/m x its l0); no method is named here."""
    with open(scene) as handle:
        document = json.load(handle)
    ratio = l0 / float(document["particle_spacing"])
    arguments = []
    for name, block in sorted(document.get("methods", {}).items()):
        if isinstance(block, dict) and "max_time_step" in block:
            arguments += ["--set", f"methods.{name}.max_time_step={block['max_time_step'] * ratio:.12g}"]
    return arguments


def case_arguments(scene: str, method: str, divisions: int, folder: str, assignments: list[str] = ()) -> list[str]:
    """The mps_lab arguments of one case (see the module's docstring); `assignments`: a scheme's
    --set assignments."""
    l0 = HEIGHT / divisions
    arguments = ["run", scene, "--method", method, "--out", folder, "--quiet", "--threads", "1",
                 "--set", f"particle_spacing={l0:.12g}", "--set", f"time.time_step={0.02 * l0:.12g}"]
    arguments += scaled_step_bounds(scene, l0)
    for index, height in enumerate(PROBES.values()):
        arguments += ["--set", f"diagnostics.pressure_sensors.{index}.position=[{RIGHT_WALL_X},{l0 / 2 + height:.12g}]"]
    for assignment in assignments:
        arguments += ["--set", assignment]
    return arguments


def variants(methods: list[str], schemes: dict | None) -> list[tuple[str, str, list[str]]]:
    """(method, scheme, assignments) of every run at one spacing: each method with its defaults
    (scheme ""), or the schemes plan's method once per scheme."""
    if schemes is None:
        return [(method, "", []) for method in methods]
    return [(schemes["method"], name, list(assignments)) for name, assignments in schemes["schemes"].items()]


def requests(scene: str, out: str, methods: list[str], divisions: list[int], schemes: dict | None = None):
    for n in divisions:
        for method, scheme, assignments in variants(methods, schemes):
            name = f"{method}-{scheme}" if scheme else method
            folder = os.path.join(out, f"H{n}", name)
            yield runner.CaseRequest(f"H{n}/{name}", case_arguments(scene, method, n, folder, assignments), folder,
                                     {"label": f"H/{n}", "l0": HEIGHT / n, "method": method, "scheme": scheme})


def row_of(folder: str, extra: dict, validation: pressure.Validation) -> dict:
    """A table row of one finished run folder (its run.json and series.csv)."""
    run = data.load_run(folder)
    row = dict(extra, status=run.summary["status"], steps=run.summary.get("steps", 0),
               wall_seconds=run.summary.get("wall_seconds", math.nan))
    for sensor in PROBES:
        for key, value in pressure.sensor_measures(run, sensor, validation).items():
            row[f"{sensor}_{key}"] = value
    return row


def experiment_row(validation: pressure.Validation) -> dict:
    row = {"label": "experiment", "method": "Buchner 2002", "status": "measured"}
    for sensor, path in validation.records.items():
        t, p = pressure.read_record(path)
        measured = pressure.record_measures(t, p, validation)
        window = (t >= validation.quasi_static[0]) & (t <= validation.quasi_static[1])
        row.update({f"{sensor}_impact_time": measured["impact_time"], f"{sensor}_peak_row": measured["peak"],
                    f"{sensor}_quasi_static_level": float(p[window].mean())})
    return row


def markdown(rows: list[dict]) -> str:
    """The table of docs/validation.md: P1 and P2 measures, one line per run (the CSV also has
    wall_seconds: measured on a shared machine, not a speed figure)."""
    header = ("| l0 | method | status | steps | P1 impact T (error) | P1 peak step / row | P1 quasi-static level | "
              "P1 quasi-static RMS | P2 impact T (error) | P2 peak row | P2 quasi-static RMS |")
    lines = [header, "|" + "---|" * 11]
    for r in rows:
        def cell(sensor, key):
            return formatted(r.get(f"{sensor}_{key}", ""))

        def impact(sensor):
            error = r.get(f"{sensor}_impact_time_error", math.nan)
            text = cell(sensor, "impact_time") or "never"
            return text + (f" ({error:+.2f})" if math.isfinite(error) else "")

        peak = (cell("P1", "peak_step") + " / " if "P1_peak_step" in r else "") + cell("P1", "peak_row")
        method = r["method"] + (f" ({r['scheme']})" if r.get("scheme") else "")
        lines.append(f"| {r['label']} | {method} | {r['status']} | {r.get('steps', '')} | "
                     f"{impact('P1')} | {peak} | {cell('P1', 'quasi_static_level')} | {cell('P1', 'quasi_static_rms')} | "
                     f"{impact('P2')} | {cell('P2', 'peak_row')} | {cell('P2', 'quasi_static_rms')} |")
    return "\n".join(lines) + "\n"


def plot(folders: dict, validation: pressure.Validation, path: str, sensor: str = "P1") -> None:
    """Each method's (or scheme's) sensor history (row means) at every spacing over the
    experiment, one panel per method; folders: {(method, n): folder}."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = sorted({method for method, _ in folders})
    figure, axes = plt.subplots(len(methods), 1, figsize=(9.0, 2.3 * len(methods)), sharex=True, squeeze=False)
    exp_t, exp_p = pressure.read_record(validation.records[sensor])
    for axis, method in zip(axes[:, 0], methods):
        for n in sorted(n for m, n in folders if m == method):
            run = data.load_run(folders[(method, n)])
            t, mean, _ = pressure.run_curves(run, sensor, validation)
            axis.plot(t, mean, lw=0.6, label=f"l0 = H/{n}")
        axis.plot(exp_t, exp_p, "k.-", lw=1.2, ms=3, label="Buchner 2002")
        axis.axvspan(*validation.quasi_static, color="0.9", zorder=0)
        axis.set_ylim(-0.1, 1.6)
        axis.set_ylabel(f"{method}\n" + r"$p/\rho g H$")
        axis.legend(loc="upper left", fontsize=7, ncol=4)
    axes[-1, 0].set_xlim(0.0, 7.6)
    axes[-1, 0].set_xlabel(r"$T = t\sqrt{g/H}$")
    axes[0, 0].set_title(f"Probe {sensor} (far wall): 2 ms row means; grey: the quasi-static window")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def study(out: str, methods: list[str], divisions: list[int], binary: str | None, parallel: int, timeout: float,
          collect: bool, docs: str | None, schemes: dict | None = None) -> int:
    """Run (unless collect) and tabulate; docs: the folder of docs/data and docs/figures to write;
    schemes: a schemes plan (the module's docstring) or None."""
    from mps_lab import SOURCE_ROOT
    scene = os.path.join(SOURCE_ROOT, SCENE)
    validation = pressure.scene_validation(scene)
    cases = list(requests(scene, out, methods, divisions, schemes))
    if not collect:
        for request, result in runner.run_cases(runner.find_binary(binary), cases, parallel=parallel,
                                                timeout=timeout, threads=1):
            print(f"{request.name}: {result.describe()}", flush=True)
    rows, folders = [experiment_row(validation)], {}
    for request in cases:
        if os.path.isfile(os.path.join(request.folder, "run.json")):
            rows.append(row_of(request.folder, request.extra, validation))
            label = request.extra["method"] + (f" ({request.extra['scheme']})" if request.extra["scheme"] else "")
            folders[(label, int(round(HEIGHT / request.extra["l0"])))] = request.folder
    target = docs or out
    name = "buchner_pressure_schemes" if schemes else "buchner_pressure"
    figure = write_study_tables(target, name, rows, COLUMNS, markdown(rows))
    if folders:
        plot(folders, validation, figure, "P1")
        plot(folders, validation, os.path.join(target, "figures", f"{name}_p2.png"), "P2")
    print(markdown(rows))
    return 0
