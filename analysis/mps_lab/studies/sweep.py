"""The speed-accuracy study: a grid of `mps_lab run` cases, their cost and their error.

    /usr/bin/python3 analysis/sweep.py SPEC.json --out runs/sweep            # run (resumes), collect, plot
    /usr/bin/python3 analysis/sweep.py SPEC.json --out runs/sweep --jobs-file jobs.txt   # only write the job list
    /usr/bin/python3 analysis/sweep.py SPEC.json --out runs/sweep --collect  # only collect and plot
    /usr/bin/python3 analysis/sweep.py SPEC.json --out runs/sweep --methods wcsph,eisph \
        --merge docs/data/sweep_dambreak.csv     # run two methods, keep the other rows of an earlier sweep

The grid is method x particle spacing x time-step rule x solver tolerance (SPEC format in
docs/speed-vs-accuracy.md; example: analysis/sweeps/dambreak.json). Every case is one
`mps_lab run` into <out>/cases/<case>/. A case whose run.json says "completed", "diverged",
"solver_failed" or "failed" is finished and is not run again ("interrupted", "running" or no
run.json: it runs again), so an interrupted sweep resumes where it stopped.
Locally, cases run through the case runner (mps_lab/runner.py: a list of arguments, --timeout
per case, one retry after a crash) in parallel up to --parallel (default: the number of
cores), each with OMP_NUM_THREADS = cores / parallel (or --threads). The spec's methods must be registered
in the binary (`mps_lab methods`). The job list has one shell command per line, for GNU
parallel or a Slurm array (`sed -n "${SLURM_ARRAY_TASK_ID}p" jobs.txt | bash`).
--methods runs only those methods' cases (the others are still collected when their folders
exist); --merge CSV takes each case that has no finished run in <out> from an earlier
sweep.csv (its row as it was, self-convergence included: references stay within a method).

Collected into <out>/sweep.csv, one row per case:
  cost:  wall_seconds, cpu_seconds (run.json's profile: the process's user + system CPU time,
         all threads; for a one-thread case the cost that other processes on the cores barely
         change), steps, fluid_particles, particle_steps_per_second, mean_solver_iterations
  error: front_rms (Z against Martin & Moyce, unshifted), front_rms_shifted, front_best_shift
         (completed cases only: a stopped run's front is cut short),
         self_convergence (RMS of Z(T) - Z_ref(T) on T in [0, T_max] every 0.05, against the
         finest completed case of the same method with the same time-step rule and the
         tightest tolerance)
Figures: <out>/pareto.png (front error against one-thread cost: cpu_seconds, or wall_seconds
for a row without it, log axes, Pareto front marked; with
the best time shift, since every converged method leads the experiment's uncertain t = 0, and
unshifted) and <out>/convergence.png (errors against l0, fitted self-convergence order per
method and time-step rule).
A scene whose `validation` block names pressure records adds the pressure-error columns and
<out>/pressure_pareto.png (analysis/mps_lab/studies/sweep_pressure.py).
"""
from __future__ import annotations

import json
import math
import os
import sys

import numpy as np

from .. import data, methods, runner
from . import sweep_pressure
from .common import (FINISHED, SpecError, case_folder, check_methods, check_spec_keys, load_json, merge_rows, read_rows,
                     source_path, status_of, write_csv)

DEFAULT_TIMEOUT = 6 * 3600.0  # s per case: far above any case of analysis/sweeps/*.json; it stops a hung case


def load_spec(path: str) -> dict:
    """The sweep specification, checked; raises SpecError with one line."""
    spec = load_json(path)
    check_spec_keys(path, spec, {"description", "scene", "end_time", "spacings", "methods", "reference_speed"}, ("scene", "spacings", "methods"))
    if not spec["spacings"] or any(not isinstance(l0, (int, float)) or l0 <= 0 for l0 in spec["spacings"]):
        raise SpecError(f"{path}: spacings: expected a non-empty array of numbers > 0")
    for method, axes in spec["methods"].items():
        for key in axes:
            if key not in ("time_step", "tolerance"):
                raise SpecError(f"{path}: methods.{method}.{key}: unknown key (expected time_step, tolerance)")
        for axis in ("time_step", "tolerance"):
            for k, entry in enumerate(axes.get(axis, [{"name": "default"}])):
                where = f"{path}: methods.{method}.{axis}[{k}]"
                if "name" not in entry:
                    raise SpecError(f"{where}.name: missing")
                for key in entry:
                    if key not in ("name", "set", "courant"):
                        raise SpecError(f"{where}.{key}: unknown key (expected name, set, courant)")
    return spec


def case_name(method: str, l0: float, step_rule: str, tolerance: str) -> str:
    return f"{method}__l0_{l0:g}__{step_rule}__{tolerance}"


def cases_of(spec: dict) -> list[dict]:
    """Every case of the grid: name, method, l0 and the --set overrides."""
    speed = float(spec.get("reference_speed", 3.13))  # m/s, sqrt(2 g H) of a 0.5 m column
    cases = []
    for method, axes in spec["methods"].items():
        for step_rule in axes.get("time_step", [{"name": "default"}]):
            for tolerance in axes.get("tolerance", [{"name": "default"}]):
                for l0 in spec["spacings"]:
                    overrides = {"particle_spacing": l0}
                    if "courant" in step_rule:  # fixed dt = C l0 / U, U = reference_speed
                        overrides["time.time_step"] = float(f"{step_rule['courant'] * l0 / speed:.12g}")
                    overrides.update(step_rule.get("set", {}))
                    overrides.update(tolerance.get("set", {}))
                    cases.append({"name": case_name(method, l0, step_rule["name"], tolerance["name"]),
                                  "method": method, "l0": l0, "time_step_rule": step_rule["name"],
                                  "tolerance": tolerance["name"], "overrides": overrides})
    return cases


def arguments_of(case: dict, spec: dict, out: str) -> list[str]:
    """The `mps_lab` arguments of one case (after the binary)."""
    arguments = ["run", f"--method={case['method']}", source_path(spec["scene"]), "--out",
                 case_folder(out, case["name"]), "--quiet"]
    if "end_time" in spec:
        arguments += ["--end-time", repr(float(spec["end_time"]))]
    for key, value in case["overrides"].items():
        arguments += ["--set", f"{key}={json.dumps(value)}"]
    return arguments


def run_cases(cases: list[dict], spec: dict, out: str, binary: str, parallel: int, threads: int,
              timeout: float = DEFAULT_TIMEOUT, label: str = "sweep") -> None:
    """Run every case not finished yet (in the order given), `parallel` at a time."""
    pending = [case for case in cases if status_of(out, case) not in FINISHED]
    print(f"{label}: {len(cases)} cases, {len(cases) - len(pending)} finished, running {len(pending)} "
          f"({parallel} at a time, {threads} thread(s) each)", flush=True)
    requests = [runner.CaseRequest(case["name"], arguments_of(case, spec, out), case_folder(out, case["name"]),
                                   {"case": case}) for case in pending]
    for request, result in runner.run_cases(binary, requests, parallel=parallel, timeout=timeout, threads=threads):
        detail = "" if result.ok else f": {result.last_error_line()}" if result.last_error_line() else ""
        print(f"{label}: {request.name}: {status_of(out, request.extra['case'])} ({result.describe()}){detail}",
              flush=True)


def self_convergence(run: data.Run, reference: data.Run) -> float:
    """RMS of Z(T) - Z_ref(T) on T = 0, 0.05, ... up to the end both reached."""
    t, z = run.front_curve()
    t_ref, z_ref = reference.front_curve()
    end = min(t[-1], t_ref[-1])
    grid = [0.05 * k for k in range(int(end / 0.05) + 1)]
    if len(grid) < 2:
        return math.nan
    differences = [np.interp(T, t, z) - np.interp(T, t_ref, z_ref) for T in grid]
    return float(math.sqrt(sum(d * d for d in differences) / len(differences)))


def measure(folder: str, status: str) -> tuple[data.Run | None, dict]:
    """A finished case's run and its cost; the front error against Martin & Moyce only when it
    completed (a diverged or failed run's front ends early and its error means nothing)."""
    try:
        run = data.load_run(folder)
    except (OSError, ValueError, KeyError, IndexError):
        return None, {}
    summary = run.summary
    row = {
        "wall_seconds": summary.get("wall_seconds", math.nan),
        "cpu_seconds": summary.get("profile", {}).get("cpu_seconds", math.nan),
        "steps": summary.get("steps", 0),
        "fluid_particles": summary.get("particles", {}).get("fluid", 0),
        "particle_steps_per_second": summary.get("fluid_particle_steps_per_second", math.nan),
        "mean_solver_iterations": summary.get("solver", {}).get("mean_iterations", math.nan),
        "front_rms": math.nan, "front_rms_shifted": math.nan, "front_best_shift": math.nan,
    }
    if status == "completed" and len(run.series.get("time", [])) > 1:
        row.update(data.front_errors(run))
        row.update(sweep_pressure.measure(run))  # a scene with a pressure record (studies/sweep_pressure.py)
    return run, row


def collect(cases: list[dict], out: str) -> list[dict]:
    runs = {}
    rows = []
    for case in cases:
        folder = case_folder(out, case["name"])
        row = {key: case[key] for key in ("name", "method", "l0", "time_step_rule", "tolerance")}
        row["status"] = status_of(out, case)
        if row["status"] in FINISHED:
            run, measured = measure(folder, row["status"])
            if run is not None:
                runs[case["name"]] = run
            row.update(measured)
        rows.append(row)
    # Reference of each (method, time-step rule): the finest completed case, tightest
    # tolerance = first tolerance listed in the spec.
    for row in rows:
        row["self_convergence"] = math.nan
        row["reference"] = ""
        candidates = [r for r in rows if r["method"] == row["method"] and r["time_step_rule"] == row["time_step_rule"]
                      and r["status"] == "completed" and r["name"] in runs]
        if not candidates or row["name"] not in runs or row["status"] != "completed":
            continue
        first_tolerance = next(c["tolerance"] for c in cases if c["method"] == row["method"])
        preferred = [r for r in candidates if r["tolerance"] == first_tolerance] or candidates
        reference = min(preferred, key=lambda r: r["l0"])
        row["reference"] = reference["name"]
        if reference["name"] != row["name"]:
            row["self_convergence"] = self_convergence(runs[row["name"]], runs[reference["name"]])
    return rows


COLUMNS = ["name", "method", "l0", "time_step_rule", "tolerance", "status", "wall_seconds", "cpu_seconds", "steps",
           "fluid_particles", "particle_steps_per_second", "mean_solver_iterations", "front_rms",
           "front_rms_shifted", "front_best_shift", "self_convergence", "reference"]


NUMERIC_COLUMNS = {"l0", "wall_seconds", "cpu_seconds", "steps", "fluid_particles", "particle_steps_per_second",
                   "mean_solver_iterations", "front_rms", "front_rms_shifted", "front_best_shift",
                   "self_convergence"}


def cost_seconds(row: dict) -> float:
    """The one-thread cost of a case, s: its CPU seconds, or its wall seconds when the row has
    none (rows of sweeps before run.json recorded CPU time, measured on an idle machine)."""
    cpu = row.get("cpu_seconds", math.nan)
    return cpu if isinstance(cpu, (int, float)) and math.isfinite(cpu) else row["wall_seconds"]


def pareto_front(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points not dominated in (cost, error): nothing is both cheaper and better."""
    front = []
    for i, (cost, error) in enumerate(points):
        dominated = any((c <= cost and e <= error) and (c < cost or e < error) for c, e in points)
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def fitted_order(l0: list[float], error: list[float]) -> float:
    """Least-squares slope of log(error) against log(l0)."""
    pairs = [(math.log(a), math.log(b)) for a, b in zip(l0, error) if a > 0 and b > 0 and math.isfinite(b)]
    if len(pairs) < 2:
        return math.nan
    mean_x = sum(x for x, _ in pairs) / len(pairs)
    mean_y = sum(y for _, y in pairs) / len(pairs)
    denominator = sum((x - mean_x) ** 2 for x, _ in pairs)
    return sum((x - mean_x) * (y - mean_y) for x, y in pairs) / denominator if denominator > 0 else math.nan


RULE_MARKERS = ["o", "s", "^", "D"]  # by time-step rule within a method
RULE_LINES = ["-", "--", ":", "-."]


def plotted_cases(rows: list[dict]) -> tuple[list[dict], list[str], dict, dict]:
    """(completed rows with a front error, their methods sorted, each method's time-step rules,
    each method's tightest tolerance = its first listed)."""
    done = [r for r in rows if r["status"] == "completed" and math.isfinite(r.get("front_rms", math.nan))]
    shown = sorted({r["method"] for r in done})
    rules = {m: sorted({r["time_step_rule"] for r in done if r["method"] == m}) for m in shown}
    tightest = {m: next(r["tolerance"] for r in done if r["method"] == m) for m in shown}
    return done, shown, rules, tightest


def plot_pareto(rows: list[dict], path: str, styles: methods.MethodStyles) -> None:
    """Front error against wall time: with the best time shift (the experiment's t = 0 is
    uncertain and every converged method leads it by a similar time), and unshifted beside it."""
    import matplotlib.pyplot as plt

    done, shown, rules, tightest = plotted_cases(rows)
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.8))
    for ax, key, title in [(axes[0], "front_rms_shifted", "front RMS in Z, best time shift in +-0.3"),
                           (axes[1], "front_rms", "front RMS in Z, unshifted")]:
        points = [(cost_seconds(r), r[key]) for r in done]
        for method in shown:
            colour = styles.colour(method)
            for m, rule in enumerate(rules[method]):
                for filled in (True, False):
                    mine = [r for r in done if r["method"] == method and r["time_step_rule"] == rule
                            and (r["tolerance"] == tightest[method]) == filled]
                    if mine:
                        ax.scatter([cost_seconds(r) for r in mine], [r[key] for r in mine], s=30,
                                   marker=RULE_MARKERS[m % len(RULE_MARKERS)], color=colour if filled else "none",
                                   edgecolors=colour,
                                   label=f"{method} / {rule}" + ("" if filled else " / " + "+".join(
                                       sorted({r["tolerance"] for r in mine}))))
        front = pareto_front(points)
        ax.step([points[i][0] for i in front], [points[i][1] for i in front], "k--", where="post", lw=1.0,
                label="Pareto front (all methods)")
        ax.scatter([points[i][0] for i in front], [points[i][1] for i in front], s=110, facecolors="none",
                   edgecolors="k")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("run time of one thread [s] (CPU s; idle wall s where no CPU time)")
        ax.set_ylabel("error against Martin & Moyce")
        ax.set_title(title)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle("Accuracy for cost (markers: time-step rule; open: the second axis' other value, e.g. a looser tolerance)")
    fig.tight_layout(rect=(0, 0.04 * (len(labels) // 4 + 2), 1, 1))
    fig.savefig(path)
    plt.close(fig)


def plot_convergence(rows: list[dict], path: str, styles: methods.MethodStyles) -> dict:
    """Errors against l0 at the tightest tolerance; returns the fitted self-convergence order
    of each method / time-step rule."""
    import matplotlib.pyplot as plt

    done, shown, rules, tightest = plotted_cases(rows)
    orders = {}
    fig, (left, right) = plt.subplots(1, 2, figsize=(11.0, 4.6))
    for method in shown:
        for m, rule in enumerate(rules[method]):
            mine = sorted([r for r in done if r["method"] == method and r["time_step_rule"] == rule
                           and r["tolerance"] == tightest[method]], key=lambda r: r["l0"])
            l0 = [r["l0"] for r in mine]
            self_error = [r["self_convergence"] for r in mine]
            order = fitted_order(l0, self_error)
            orders[f"{method}/{rule}"] = order
            style = dict(color=styles.colour(method), linestyle=RULE_LINES[m % len(RULE_LINES)],
                         marker=RULE_MARKERS[m % len(RULE_MARKERS)])
            label = f"{method} / {rule}: order {order:.2f}" if math.isfinite(order) else f"{method} / {rule}"
            right.loglog(l0, self_error, label=label, **style)
            left.loglog(l0, [r["front_rms_shifted"] for r in mine], label=f"{method} / {rule}", **style)
    left.set_xlabel("l0 [m]")
    left.set_ylabel("front RMS in Z, best shift")
    left.set_title("Against Martin & Moyce")
    right.set_xlabel("l0 [m]")
    right.set_ylabel("RMS of Z - Z(finest run)")
    right.set_title("Self-convergence (least-squares order)")
    for axis in (left, right):
        axis.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return orders


def plot(rows: list[dict], out: str, styles: methods.MethodStyles) -> dict:
    """pareto.png and convergence.png (colour: the method; marker: the time-step rule);
    returns the fitted self-convergence orders."""
    from .. import figures  # noqa: F401  (sets the shared style)

    plot_pareto(rows, os.path.join(out, "pareto.png"), styles)
    sweep_pressure.plot(rows, os.path.join(out, "pressure_pareto.png"), styles, pareto_front)
    return plot_convergence(rows, os.path.join(out, "convergence.png"), styles)


def write_jobs(cases: list[dict], spec: dict, out: str, binary: str, threads: int, path: str) -> None:
    """One shell line per case (GNU parallel, a Slurm array); nothing is run here."""
    with open(path, "w") as handle:
        for case in cases:
            handle.write(runner.command_line(binary, arguments_of(case, spec, out), threads) + "\n")
    print(f"sweep: {len(cases)} jobs written to {path}")


def sweep(spec_path: str, out: str, binary: str | None = None, parallel: int = 1, timeout: float = DEFAULT_TIMEOUT,
          jobs_file: str | None = None, collect_only: bool = False, plots: bool = True,
          only_methods: list[str] | None = None, merge: str | None = None, threads: int | None = None) -> int:
    """The whole study (module docstring); 0, or 2 with one line on stderr for a bad spec or
    no binary."""
    try:
        spec = load_spec(spec_path)
        found = None if collect_only else runner.find_binary(binary)
        if found is not None:
            check_methods(list(spec["methods"]), methods.registered_methods(found), f"{spec_path}: methods")
        unknown = [m for m in only_methods or [] if m not in spec["methods"]]
        if unknown:
            raise SpecError(f"--methods: {unknown[0]}: not a method of {spec_path} (it has: {', '.join(spec['methods'])})")
        earlier = read_rows(merge, NUMERIC_COLUMNS) if merge else []
    except (SpecError, runner.BinaryNotFound, methods.MethodListError, OSError, KeyError, ValueError) as error:
        print(f"sweep.py: {error}", file=sys.stderr)
        return 2
    cases = cases_of(spec)
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    parallel = max(1, parallel)
    threads = max(1, threads) if threads else runner.threads_per_case(parallel)
    if jobs_file:
        write_jobs(cases, spec, os.path.abspath(out), found, threads, jobs_file)
        return 0
    if not collect_only:
        run_cases([c for c in cases if not only_methods or c["method"] in only_methods], spec, out, found, parallel,
                  threads, timeout)
    rows = collect(cases, out)
    if merge:
        rows, taken = merge_rows(rows, earlier)
        print(f"sweep: {taken} case(s) taken from {merge}")
    write_csv(rows, COLUMNS + sweep_pressure.columns(rows), os.path.join(out, "sweep.csv"), nan_as_empty=False)
    finished = sum(r["status"] in FINISHED for r in rows)
    print(f"sweep: {finished}/{len(rows)} cases finished -> {os.path.join(out, 'sweep.csv')}")
    if plots and any(r["status"] == "completed" for r in rows):
        orders = plot(rows, out, methods.styles_for([r["method"] for r in rows], binary))
        for key, order in orders.items():
            print(f"sweep: fitted self-convergence order {key}: {order:.2f}")
    return 0
