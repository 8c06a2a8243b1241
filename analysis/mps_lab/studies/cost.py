"""Cost per simulated second of every registered method, side by side (tools/cost-five-methods.sh).

    /usr/bin/python3 analysis/cost_per_method.py --out runs/cost                 # 0.5 s, 3 spacings, 3 repetitions
    /usr/bin/python3 analysis/cost_per_method.py --out runs/cost --docs          # and copy the tables to docs/data/
    /usr/bin/python3 analysis/cost_per_method.py --out /tmp/c --spacings 0.05 --end-time 0.02 --repetitions 2

Every method `mps_lab methods` lists runs at its default settings on the scene (default
scenes/dambreak.json) to --end-time (default 0.5 s) at each spacing (default 0.025, 0.0125 and
0.00625 m), one OpenMP thread with OMP_PROC_BIND=true, CSV output only. The runs are
interleaved: repetition k runs every spacing, and at each spacing the methods in the order
of the registry rotated by k, so a change of the machine's load during the study falls on
every method alike. Each case's cost is the median over the repetitions of
  seconds per simulated second   = wall seconds / simulated time (and the same in CPU seconds,
                                   run.json's profile.cpu_seconds: what load barely changes)
  fluid particle-steps per second = fluid particles x steps / wall seconds,
and its ratio to the --reference method (default: the first `mps_lab methods` lists;
tools/cost-five-methods.sh passes --reference mps). A case whose
run does not complete is reported with its status, not dropped.
Writes <out>/cost_per_method.csv (one row per method and spacing) and cost_per_method.md;
--docs copies both to docs/data/. Measure on an otherwise idle machine for wall times.
"""
from __future__ import annotations

import json
import os
import shutil
import statistics
import sys

from .. import SOURCE_ROOT, methods, runner
from .common import case_folder, run_summary, source_path, write_csv

DEFAULT_SPACINGS = (0.025, 0.0125, 0.00625)  # m
DEFAULT_TIMEOUT = 3600.0  # s per run: far above a 0.5 s dam break of any method at 0.00625 m
COLUMNS = ["method", "l0", "fluid_particles", "steps", "status", "repetitions", "wall_seconds", "cpu_seconds",
           "seconds_per_simulated_second", "cpu_seconds_per_simulated_second", "particle_steps_per_second",
           "ratio_to_reference", "cpu_ratio_to_reference"]


def interleaved_order(method_names: list[str], spacings: list[float], repetitions: int) -> list[tuple[int, float, str]]:
    """(repetition, spacing, method) in the order they run: the method order rotated by one
    per repetition."""
    order = []
    for k in range(repetitions):
        shift = k % len(method_names) if method_names else 0
        rotated = method_names[shift:] + method_names[:shift]
        order += [(k, l0, method) for l0 in spacings for method in rotated]
    return order


def run_name(method: str, l0: float, repetition: int) -> str:
    return f"{method}__l0_{l0:g}__rep_{repetition}"


def arguments_of(scene: str, method: str, l0: float, end_time: float, folder: str) -> list[str]:
    return ["run", f"--method={method}", source_path(scene), "--out", folder, "--quiet", "--end-time",
            repr(float(end_time)), "--set", f"particle_spacing={json.dumps(l0)}", "--set",
            'output.formats=["csv"]']


def measured(summary: dict) -> dict:
    """One run's cost from its run.json."""
    simulated = float(summary.get("simulated_time", 0.0))
    wall = float(summary.get("wall_seconds", float("nan")))
    cpu = float(summary.get("profile", {}).get("cpu_seconds", float("nan")))
    return {"status": summary.get("status", "unknown"), "steps": int(summary.get("steps", 0)),
            "fluid_particles": int(summary.get("particles", {}).get("fluid", 0)), "wall_seconds": wall,
            "cpu_seconds": cpu, "seconds_per_simulated_second": wall / simulated if simulated > 0 else float("nan"),
            "cpu_seconds_per_simulated_second": cpu / simulated if simulated > 0 else float("nan"),
            "particle_steps_per_second": float(summary.get("fluid_particle_steps_per_second", float("nan")))}


def median_row(method: str, l0: float, runs: list[dict]) -> dict:
    """The medians over a case's repetitions; status "completed" only when every run completed."""
    statuses = sorted({run["status"] for run in runs})
    row = {"method": method, "l0": l0, "repetitions": len(runs),
           "status": statuses[0] if len(statuses) == 1 else "/".join(statuses)}
    for key in ("fluid_particles", "steps"):
        row[key] = max(run[key] for run in runs) if runs else 0
    for key in ("wall_seconds", "cpu_seconds", "seconds_per_simulated_second", "cpu_seconds_per_simulated_second",
                "particle_steps_per_second"):
        row[key] = statistics.median(run[key] for run in runs) if runs else float("nan")
    return row


def add_ratios(rows: list[dict], reference: str) -> None:
    """ratio_to_reference: seconds per simulated second over the reference method's, same l0."""
    base = {row["l0"]: row for row in rows if row["method"] == reference}
    for row in rows:
        other = base.get(row["l0"])
        for key, ratio in (("seconds_per_simulated_second", "ratio_to_reference"),
                           ("cpu_seconds_per_simulated_second", "cpu_ratio_to_reference")):
            row[ratio] = row[key] / other[key] if other and other[key] > 0 else float("nan")


def markdown(rows: list[dict], reference: str, end_time: float, scene: str) -> str:
    lines = [f"Cost of every method at its defaults on {scene} to {end_time:g} s, one thread, OMP_PROC_BIND=true, "
             f"median of {max((r['repetitions'] for r in rows), default=0)} interleaved repetitions "
             f"(tools/cost-five-methods.sh). Ratios: to `{reference}` at the same l0.", "",
             "| l0 [m] | method | fluid | steps | status | s per simulated s | CPU s per simulated s "
             "| M particle-steps/s | ratio to " + reference + " (wall) | (CPU) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for row in sorted(rows, key=lambda r: (-r["l0"], r["method"])):
        lines.append(f"| {row['l0']:g} | {row['method']} | {row['fluid_particles']} | {row['steps']} | {row['status']} "
                     f"| {row['seconds_per_simulated_second']:.3g} | {row['cpu_seconds_per_simulated_second']:.3g} "
                     f"| {row['particle_steps_per_second'] / 1e6:.3g} | {row['ratio_to_reference']:.2f} "
                     f"| {row['cpu_ratio_to_reference']:.2f} |")
    return "\n".join(lines) + "\n"


def cost(out: str, binary: str | None = None, scene: str = "scenes/dambreak.json", end_time: float = 0.5,
         spacings: tuple[float, ...] = DEFAULT_SPACINGS, repetitions: int = 3, reference: str | None = None,
         timeout: float = DEFAULT_TIMEOUT, docs: bool = False) -> int:
    """The study (module docstring); 0, or 2 with one line on stderr (no binary, unknown reference)."""
    try:
        found = runner.find_binary(binary)
        names = methods.registered_methods(found)
    except (runner.BinaryNotFound, methods.MethodListError) as error:
        print(f"cost_per_method.py: {error}", file=sys.stderr)
        return 2
    reference = reference or names[0]
    if reference not in names:
        print(f"cost_per_method.py: --reference {reference}: not a registered method ({', '.join(names)})",
              file=sys.stderr)
        return 2
    results: dict[tuple[str, float], list[dict]] = {}
    for repetition, l0, method in interleaved_order(names, list(spacings), repetitions):
        folder = case_folder(out, run_name(method, l0, repetition))
        shutil.rmtree(folder, ignore_errors=True)  # a fresh run every time: never a stale one
        result = runner.run_case(found, arguments_of(scene, method, l0, end_time, folder), timeout=timeout,
                                 threads=1, proc_bind="true", folder=folder)
        summary = run_summary(folder)
        print(f"cost: {run_name(method, l0, repetition)}: {result.describe()}", flush=True)
        if summary is not None:
            results.setdefault((method, l0), []).append(measured(summary))
    rows = [median_row(method, l0, results.get((method, l0), [])) for l0 in spacings for method in names]
    add_ratios(rows, reference)
    csv_path = os.path.join(out, "cost_per_method.csv")
    write_csv(rows, COLUMNS, csv_path)
    with open(os.path.join(out, "cost_per_method.md"), "w") as handle:
        handle.write(markdown(rows, reference, end_time, scene))
    print(f"cost: {len(rows)} rows -> {csv_path}")
    if docs:
        for name in ("cost_per_method.csv", "cost_per_method.md"):
            shutil.copy(os.path.join(out, name), os.path.join(SOURCE_ROOT, "docs", "data", name))
    return 0
