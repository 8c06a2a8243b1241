"""Performance study (issue 7; docs/performance.md): speed against the public reference codes,
where the time goes, O(N) scaling to a million particles, threads and memory.

    /usr/bin/python3 analysis/performance.py --out runs/performance             # everything (~30 min)
    /usr/bin/python3 analysis/performance.py --out runs/performance --only scaling --max-fluid 1e5
    /usr/bin/python3 analysis/performance.py --out runs/performance --only figures --docs
    /usr/bin/python3 analysis/performance.py --out /tmp/perf --quick            # seconds (tests)
    /usr/bin/python3 analysis/performance.py --out runs/performance --only million    # hours
    /usr/bin/python3 analysis/performance.py --out runs/perf --only targets --million-runs RUN... \
        --side-by-side docs/data/reference_codes_*.csv               # the targets from runs made before

The runs, the reference figures and the bench settings per method are data:
analysis/sweeps/performance.json (--plan another). The methods come from the binary
(`mps_lab methods`): a planned run of a method it does not register is left out, and bench
measures every registered method. Every case runs through the case runner
(mps_lab/runner.py: arguments, --timeout per case, one retry after a crash).

Parts (--only picks some; each writes into --out and is reused by the later ones):
  reference    whole runs as the reference figures were taken (`mps_lab run`, 2 threads,
               the scenes' own output, splashes allowed up to 50 %): the plan's
               reference_runs (the dam break at l0 = 0.025, 0.0125 and 0.005 to 2 s or 1 s,
               the last at two density tolerances) -> reference.csv (one row per run: fluid
               particle-steps per second, mean iterations, ms per step of every phase from
               run.json's profile), with the ratio to the plan's reference_figures.
  resolutions  `mps_lab bench` at l0 = 0.025, 0.0125, 0.005, 0.0025 (time step 0.02 s/m x l0),
               after running to 0.02 s, 40 measured steps -> resolutions.json.
  scaling      `mps_lab bench` from about 1e3 to --max-fluid fluid particles (l0 = 0.05/k,
               k = 5 ... 142), with 1 and 2 threads, from rest, 3 + 10 measured steps (5 above
               3e5 particles, where each method and thread count runs in its own process, so
               that its resident memory is its own) -> scaling.json.
  threads      each method alone and beside one CPU-bound process with 1, 2 threads and the team
               mps_lab measures (performance_threads.py) -> threads.csv.
  million      by name only (hours): scenes/dambreak_large.json to 0.1 s, each method, or with
               --million-runs the runs given (performance_million.py) -> million.csv.
  targets      nothing runs: the plan's targets evaluated on the folder's data, met / missed /
               not measured with the ratio to the limit (performance_targets.py; with
               --side-by-side, the reference codes' CSVs) -> targets.csv; also done by every
               other part.
  figures      performance_scaling.png (ns per fluid particle-step against N, log-log, with
               the +-30 % band around each method's median) and performance_phases.png (ms per
               step by phase at each resolution), and performance.md (the tables).
--docs copies the CSV/JSON/markdown to docs/data/ and the figures to docs/figures/.

Every measurement runs with OMP_PROC_BIND=true (unpinned threads on this machine class slow
down many-fold when another process runs); measure on an otherwise idle machine.
"""
from __future__ import annotations

import csv
import json
import shutil
import sys
from pathlib import Path

from .. import SOURCE_ROOT, methods, runner
from . import performance_million, performance_targets, performance_threads
from .performance_cases import load_cases, methods_in, scaling_summary, speedups
from .common import SpecError, load_json, write_csv

ROOT = Path(SOURCE_ROOT)
DEFAULT_PLAN = ROOT / "analysis" / "sweeps" / "performance.json"
DEFAULT_TIMEOUT = 6 * 3600.0  # s per run or bench: above the longest planned run; it stops a hung one
PROC_BIND = "true"  # unpinned threads on this machine class slow down many-fold under load

# Spacings l0 = 0.05 / k (the tank and the column are whole multiples): about 1e3 ... 1e6 fluid.
SCALING_K = [5, 9, 16, 28, 50, 90, 142]


class StudyError(Exception):
    """A run or bench of the study failed; the message is one line."""


def fluid_count(spacing: float) -> int:
    return (round(0.25 / spacing) - 1) * (round(0.5 / spacing) - 1)


def load_plan(path: str | Path) -> dict:
    """The study's plan (analysis/sweeps/performance.json), checked; raises SpecError."""
    plan = load_json(str(path))
    known = {"description", "set", "quick_end_time", "reference_runs", "reference_figures", "bench_per_spacing",
             "threads", "targets"}
    for key in plan:
        if key not in known:
            raise SpecError(f"{path}: {key}: unknown key (expected one of: {', '.join(sorted(known))})")
    for k, run in enumerate(plan.get("reference_runs", [])):
        for key in ("method", "scene", "particle_spacing", "end_time"):
            if key not in run:
                raise SpecError(f"{path}: reference_runs[{k}].{key}: missing")
    for key in plan.get("threads", {}):
        if key not in ("description", "rounds", "shared_end_time", "sizes_k", "sizes_steps"):
            raise SpecError(f"{path}: threads.{key}: unknown key (expected description, rounds, shared_end_time, "
                            f"sizes_k or sizes_steps)")
    performance_targets.check_targets(str(path), plan.get("targets", []))
    return plan


def method_of_key(key: str) -> str | None:
    """The method a scene key belongs to ("methods.<name>.x=..." -> name), None for a shared key."""
    parts = key.split(".")
    return parts[1] if len(parts) > 2 and parts[0] == "methods" else None


def reference_cases(plan: dict, registered: list[str], quick: bool) -> list[dict]:
    """The plan's reference runs of registered methods (--quick: those marked quick, short)."""
    cases = [dict(run) for run in plan.get("reference_runs", []) if run["method"] in registered]
    left_out = sorted({run["method"] for run in plan.get("reference_runs", [])} - set(registered))
    if left_out:
        print(f"performance.py: reference runs of {', '.join(left_out)} left out: not registered", flush=True)
    if quick:
        cases = [dict(run, end_time=plan.get("quick_end_time", 0.02)) for run in cases if run.get("quick")]
    return cases


def reference_figure(plan: dict, method: str, spacing: float, tolerance: float | None) -> dict | None:
    """The reference code's figure for a run ({"code", "particle_steps_per_second"}), if any."""
    return next((figure for figure in plan.get("reference_figures", []) if figure["method"] == method
                 and float(figure["particle_spacing"]) == spacing and figure.get("density_tolerance") == tolerance),
                None)


def case_name(case: dict) -> str:
    tolerance = case.get("density_tolerance")
    return f"{case['method']}_{case['particle_spacing']}" + (f"_tol{tolerance}" if tolerance else "")


def reference_row(case: dict, run: dict) -> dict:
    """One row of reference.csv from a run's run.json."""
    row = dict(method=case["method"], particle_spacing=case["particle_spacing"],
               density_tolerance=case.get("density_tolerance") or "", fluid_particles=run["particles"]["fluid"],
               end_time=case["end_time"], steps=run["steps"], wall_seconds=run["wall_seconds"],
               particle_steps_per_second=run["fluid_particle_steps_per_second"],
               mean_iterations=run["solver"]["mean_iterations"], status=run["status"],
               bytes_per_particle=run["memory"]["bytes_per_particle"])
    for phase, values in run["profile"]["phases"].items():
        row[f"ms_{phase}"] = values["milliseconds_per_step"]
    return row


def run_reference(binary: str, plan: dict, registered: list[str], out: Path, quick: bool, timeout: float) -> None:
    rows = []
    for case in reference_cases(plan, registered, quick):
        folder = out / "reference" / case_name(case)
        arguments = ["run", f"--method={case['method']}", str(ROOT / case["scene"]), "-q", "--out", str(folder),
                     "--end-time", str(case["end_time"])]
        for item in plan.get("set", []) + case.get("set", []):
            arguments += ["--set", item]
        print("performance.py:", " ".join(arguments), flush=True)
        # a run that stops early (exit 1) is reported with its status, not an error
        result = runner.run_case(binary, arguments, timeout=timeout, threads=2, proc_bind=PROC_BIND,
                                 folder=str(folder))
        try:
            run = json.loads((folder / "run.json").read_text())
        except (OSError, json.JSONDecodeError) as error:
            raise StudyError(f"{folder}: no run.json ({result.describe()}: {result.last_error_line()})") from error
        rows.append(reference_row(case, run))
    columns = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    with open(out / "reference.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)


def bench(binary: str, arguments: list[str], json_path: Path, per_spacing: list[str], timeout: float) -> dict:
    """One `mps_lab bench` (every registered method) into json_path; raises StudyError."""
    command = ["bench", str(ROOT / "scenes" / "dambreak.json"), "-q", "--json", str(json_path)]
    for item in per_spacing:
        command += ["--per-spacing", item]
    command += arguments
    print("performance.py:", " ".join(command), flush=True)
    result = runner.run_case(binary, command, timeout=timeout, proc_bind=PROC_BIND, keep=None)  # its whole table
    if not result.ok:
        raise StudyError(f"mps_lab {' '.join(command)}: {result.describe()}: {result.last_error_line()}")
    print(result.stdout, flush=True)
    return json.loads(json_path.read_text())


def bench_per_spacing(plan: dict, registered: list[str]) -> list[str]:
    """The plan's per-spacing keys of registered methods (bench rejects a key of another)."""
    return [item for item in plan.get("bench_per_spacing", []) if method_of_key(item) in (None, *registered)]


def run_resolutions(binary: str, per_spacing: list[str], out: Path, quick: bool, timeout: float) -> None:
    spacings = "0.025" if quick else "0.025,0.0125,0.005,0.0025"
    steps = ["--steps", "3", "--warmup-steps", "1"] if quick else ["--steps", "40", "--warmup-steps", "5",
                                                                    "--start-time", "0.02"]
    bench(binary, ["--spacings", spacings, "--threads", "2"] + steps, out / "resolutions.json", per_spacing, timeout)


def run_scaling(binary: str, per_spacing: list[str], registered: list[str], out: Path, max_fluid: float, quick: bool,
                timeout: float) -> None:
    """Above 3e5 fluid particles each method and thread count runs in a process of its own, so that
    its resident memory (the RSS grown by its simulation) is its own, not what an earlier case freed."""
    ks = [5] if quick else [k for k in SCALING_K if fluid_count(0.05 / k) <= max_fluid * 1.01]
    cases = []
    for k in ks:
        spacing = 0.05 / k
        large = fluid_count(spacing) > 3e5
        steps = ["--steps", "2", "--warmup-steps", "1"] if quick else \
            ["--steps", "5" if large else "10", "--warmup-steps", "3"]
        # (file name, the bench's selection, the per-spacing keys it takes)
        runs = [(f"scaling_k{k}_{m}_t{t}.json", ["--methods", m, "--threads", str(t)],
                 [item for item in per_spacing if method_of_key(item) in (None, m)])
                for m in registered for t in (1, 2)] if large else \
            [(f"scaling_k{k}.json", ["--threads", "1,2"], per_spacing)]
        for name, selection, keys in runs:
            cases += bench(binary, ["--spacings", repr(spacing)] + selection + steps, out / name, keys, timeout)["cases"]
    (out / "scaling.json").write_text(json.dumps({"cases": cases}, indent=1) + "\n")


def reference_table(out: Path, plan: dict) -> list[str]:
    """The whole runs against the reference codes' figures, and their phases."""
    lines = []
    reference_csv = out / "reference.csv"
    if reference_csv.exists():
        with open(reference_csv, newline="") as handle:
            rows = list(csv.DictReader(handle))
        lines += ["## Whole runs against the reference figures (2 threads)", "",
                  "| method | l0 [m] | density tol. | fluid | steps | wall [s] | particle-steps/s | reference | ratio | mean iter. |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for row in rows:
            spacing = float(row["particle_spacing"])
            tolerance = float(row["density_tolerance"]) if row["density_tolerance"] else None
            figure = reference_figure(plan, row["method"], spacing, tolerance)
            code = figure["code"] if figure else None
            reference = float(figure["particle_steps_per_second"]) if figure else None
            speed = float(row["particle_steps_per_second"])
            lines.append(f"| {row['method']} | {spacing:g} | {'' if tolerance is None else f'{100 * tolerance:g} %'} | "
                         f"{row['fluid_particles']} | {row['steps']} | {float(row['wall_seconds']):.1f} | "
                         f"{speed / 1e6:.3f} M | {'' if reference is None else f'{reference / 1e6:.2f} M ({code})'} | "
                         f"{'' if reference is None else f'{speed / reference:.2f}x'} | {float(row['mean_iterations']):.1f} |")
        phases = sorted({key[3:] for row in rows for key in row if key.startswith("ms_") and row[key]})
        lines += ["", "Milliseconds per step by phase (run.json profile of the same runs):", "",
                  "| method | l0 [m] | density tol. | " + " | ".join(phases) + " |",
                  "|---|---|---|" + "---|" * len(phases)]
        for row in rows:
            tolerance = f"{100 * float(row['density_tolerance']):g} %" if row["density_tolerance"] else ""
            cells = [f"{float(row['ms_' + p]):.3f}" if row.get("ms_" + p) else "" for p in phases]
            lines.append(f"| {row['method']} | {float(row['particle_spacing']):g} | {tolerance} | " + " | ".join(cells) + " |")
        lines.append("")
    return lines


def resolutions_table(out: Path) -> list[str]:
    """`mps_lab bench` at the four resolutions: speed, phases, kernels."""
    lines = []
    resolutions = load_cases(out / "resolutions.json")
    if resolutions:
        lines += ["## `mps_lab bench` at the four resolutions (2 threads, 40 steps after t = 0.02 s)", "",
                  "| method | l0 [m] | fluid | particle-steps/s | ms/step | mean iter. | us per iteration | phases (ms/step) |",
                  "|---|---|---|---|---|---|---|---|"]
        for c in resolutions:
            if c["kind"] != "steps" or c["status"] != "completed":
                continue
            phases = ", ".join(f"{name} {v['milliseconds_per_step']:.3g}" for name, v in
                               sorted(c["phases"].items(), key=lambda item: -item[1]["milliseconds_per_step"])
                               if v["milliseconds_per_step"] > 0)
            lines.append(f"| {c['method']} | {c['particle_spacing']:g} | {c['fluid_particles']} | "
                         f"{c['fluid_particle_steps_per_second'] / 1e6:.3f} M | {c['milliseconds_per_step']:.3f} | "
                         f"{c['mean_solver_iterations']:.1f} | {c.get('solver_iteration_microseconds', 0):.1f} | {phases} |")
        lines += ["", "| l0 [m] | particles | neighbours | search ns/particle | number density ns/particle | SPH density ns/particle |",
                  "|---|---|---|---|---|---|"]
        for c in resolutions:
            if c["kind"] == "kernels":
                lines.append(f"| {c['particle_spacing']:g} | {c['particles']} | {c['mean_neighbours']:.2f} | "
                             f"{c['neighbour_search_ns_per_particle']:.1f} | {c['number_density_ns_per_particle']:.1f} | "
                             f"{c['sph_density_ns_per_particle']:.1f} |")
        lines.append("")
    return lines


def scaling_tables(out: Path) -> list[str]:
    """ns per particle-step against size, iterations, speed-up, memory."""
    lines = []
    scaling = load_cases(out / "scaling.json")
    if scaling:
        lines += ["## Scaling (ns per fluid particle-step; bench from rest)", "",
                  "| method | threads | " + " | ".join(f"{n:,}" for n in sorted({c['fluid_particles'] for c in scaling
                                                                                   if c['kind'] == 'steps'})) +
                  " | spread around the median |",
                  "|---|---|" + "---|" * (len({c['fluid_particles'] for c in scaling if c['kind'] == 'steps'}) + 1)]
        sizes = sorted({c["fluid_particles"] for c in scaling if c["kind"] == "steps"})
        for row in scaling_summary(scaling):
            values = dict(row["points"])
            cells = [f"{values[n]:.0f}" if n in values else "" for n in sizes]
            lines.append(f"| {row['method']} | {row['threads']} | " + " | ".join(cells) +
                         f" | {100 * row['low']:+.0f} % / {100 * row['high']:+.0f} % |")
        lines += ["", "Mean solver iterations per step (2 threads):", "",
                  "| method | " + " | ".join(f"{n:,}" for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
        for method in methods_in(scaling):
            values = {c["fluid_particles"]: c["mean_solver_iterations"] for c in scaling
                      if c["kind"] == "steps" and c["method"] == method and c["threads"] == 2 and c["status"] == "completed"}
            if values:
                lines.append(f"| {method} | " + " | ".join(f"{values[n]:.1f}" if n in values else "" for n in sizes) + " |")
        lines += ["", "Speed-up from 1 to 2 threads:", "", "| method | fluid | speed-up |", "|---|---|---|"]
        for method, fluid, ratio in speedups(scaling):
            lines.append(f"| {method} | {fluid:,} | {ratio:.2f} |")
        lines += ["", "Memory held by the simulation (resident, bytes per particle, 2 threads):", "",
                  "| method | " + " | ".join(f"{n:,}" for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
        for method in methods_in(scaling):
            values = {c["fluid_particles"]: c["memory_bytes_per_particle"] for c in scaling
                      if c["kind"] == "steps" and c["method"] == method and c["threads"] == 2 and c["status"] == "completed"}
            if values:
                lines.append(f"| {method} | " + " | ".join(f"{values[n]:.0f}" if n in values else "" for n in sizes) + " |")
        lines.append("")
    return lines


def markdown(out: Path, plan: dict) -> str:
    return "\n".join(performance_targets.targets_table(plan.get("targets", []), out) + reference_table(out, plan) +
                     resolutions_table(out) + scaling_tables(out) + performance_threads.threads_table(out) +
                     performance_million.million_table(out))


def figures(out: Path, styles: methods.MethodStyles) -> None:
    """performance_scaling.png and performance_phases.png from the JSON of the bench parts."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scaling = load_cases(out / "scaling.json")
    if scaling:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for row in scaling_summary(scaling):
            xs, ys = zip(*row["points"])
            style = "-o" if row["threads"] == 2 else "--s"
            ax.plot(xs, ys, style, color=styles.colour(row["method"]), label=f"{row['method']}, {row['threads']} thread(s)",
                    markersize=4)
            if row["threads"] == 2:
                ax.fill_between([min(xs), max(xs)], 0.7 * row["median"], 1.3 * row["median"],
                                color=styles.colour(row["method"]), alpha=0.08)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("fluid particles")
        ax.set_ylabel("wall time per fluid particle-step [ns]")
        ax.set_title("Scaling on the dam break (bands: median +-30 %, 2 threads)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / "performance_scaling.png", dpi=120)
        plt.close(fig)
    resolutions = [c for c in load_cases(out / "resolutions.json") if c["kind"] == "steps" and c["status"] == "completed"]
    if resolutions:
        phases = sorted({name for c in resolutions for name in c["phases"]})
        labels = [f"{c['method']}\nl0={c['particle_spacing']:g}" for c in resolutions]
        fig, ax = plt.subplots(figsize=(max(7, 0.6 * len(labels)), 4.5))
        bottom = [0.0] * len(resolutions)
        cmap = plt.get_cmap("tab20")
        for index, phase in enumerate(phases):
            # ns per fluid particle-step, so that the resolutions share one axis
            heights = [1e6 * c["phases"].get(phase, {}).get("milliseconds_per_step", 0.0) / c["fluid_particles"]
                       for c in resolutions]
            ax.bar(range(len(resolutions)), heights, bottom=bottom, label=phase, color=cmap(index))
            bottom = [b + h for b, h in zip(bottom, heights)]
        ax.set_xticks(range(len(resolutions)))
        ax.set_xticklabels(labels, fontsize=7)
        ax.set_ylabel("ns per fluid particle-step")
        ax.set_title("Where the time goes (mps_lab bench, 2 threads)")
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(out / "performance_phases.png", dpi=120)
        plt.close(fig)


def copy_to_docs(out: Path) -> None:
    for name in ["reference.csv", "resolutions.json", "scaling.json", "threads.csv", "million.csv", "targets.csv",
                 "performance.md"]:
        if (out / name).exists():
            target = name if name.startswith("performance") else "performance_" + name
            shutil.copy(out / name, ROOT / "docs" / "data" / target)
    for name in ["performance_scaling.png", "performance_phases.png"]:
        if (out / name).exists():
            shutil.copy(out / name, ROOT / "docs" / "figures" / name)


PARTS = ["reference", "resolutions", "scaling", "threads", "million", "targets", "figures"]
DEFAULT_PARTS = ["reference", "resolutions", "scaling", "threads", "figures"]  # million: hours, by name only


def copy_side_by_side(files: list[str], out: Path) -> None:
    """tools/reference-codes/side-by-side.sh CSVs into out/side_by_side.csv (their rows, in order;
    the repetitions of each file numbered apart, so that files of several sittings pool)."""
    rows, columns = [], None
    for index, name in enumerate(files):
        try:
            with open(name, newline="") as handle:
                reader = csv.DictReader(handle)
                columns = columns or reader.fieldnames
                rows += [dict(row, repetition=f"{index + 1}.{row['repetition']}") for row in reader]
        except (OSError, KeyError) as error:
            raise SpecError(f"{name}: not a side-by-side CSV ({error})") from error
    write_csv(rows, list(columns or ["repetition"]), str(out / "side_by_side.csv"))


def run_parts(parts: list[str], found: str | None, plan: dict, registered: list[str], folder: Path, quick: bool,
              max_fluid: float, timeout: float, million_runs: list[str] | None) -> None:
    """The parts that run mps_lab, in order; raises StudyError, ThreadsError or MillionError."""
    if "reference" in parts:
        run_reference(found, plan, registered, folder, quick, timeout)
    per_spacing = bench_per_spacing(plan, registered) if found else []
    if "resolutions" in parts:
        run_resolutions(found, per_spacing, folder, quick, timeout)
    if "scaling" in parts:
        run_scaling(found, per_spacing, registered, folder, max_fluid, quick, timeout)
    if "threads" in parts:
        performance_threads.run_threads(found, plan, registered, folder, quick, timeout)
    if million_runs:
        performance_million.write_million([Path(name) for name in million_runs], folder)
    elif "million" in parts:
        performance_million.write_million(performance_million.run_million(found, registered, folder, timeout), folder)


def performance(out: str, binary: str | None = None, only: list[str] | None = None, max_fluid: float = 1.1e6,
                quick: bool = False, docs: bool = False, timeout: float = DEFAULT_TIMEOUT,
                plan_path: str | Path = DEFAULT_PLAN, million_runs: list[str] | None = None,
                side_by_side: list[str] | None = None) -> int:
    """The study (module docstring); 0, 2 for a bad plan, option or no binary, 1 when a part failed."""
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    parts = only or DEFAULT_PARTS
    found, registered = None, []
    try:
        plan = load_plan(plan_path)
        if side_by_side:
            copy_side_by_side(side_by_side, folder)
        if any(part in ("reference", "resolutions", "scaling", "threads") for part in parts) or \
                ("million" in parts and not million_runs):
            found = runner.find_binary(binary)
            registered = methods.registered_methods(found)
    except (SpecError, runner.BinaryNotFound, methods.MethodListError) as error:
        print(f"performance.py: {error}", file=sys.stderr)
        return 2
    try:
        run_parts(parts, found, plan, registered, folder, quick, max_fluid, timeout, million_runs)
    except (StudyError, performance_threads.ThreadsError, performance_million.MillionError) as error:
        print(f"performance.py: {error}", file=sys.stderr)
        return 1
    (folder / "performance.md").write_text(markdown(folder, plan) + "\n")
    performance_targets.write_targets(plan.get("targets", []), folder)
    seen = methods_in(load_cases(folder / "scaling.json") + load_cases(folder / "resolutions.json"))
    figures(folder, methods.styles_for(seen, found or binary))
    if docs:
        copy_to_docs(folder)
    print(f"performance.py: results in {folder}/performance.md", flush=True)
    return 0
