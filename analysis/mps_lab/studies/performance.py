#!/usr/bin/env python3
"""Performance study (issue 7; docs/performance.md): speed against the public reference codes,
where the time goes, O(N) scaling to a million particles, threads and memory.

    /usr/bin/python3 analysis/performance.py --out runs/performance             # everything (~30 min)
    /usr/bin/python3 analysis/performance.py --out runs/performance --only scaling --max-fluid 1e5
    /usr/bin/python3 analysis/performance.py --out runs/performance --only figures --docs
    /usr/bin/python3 analysis/performance.py --out /tmp/perf --quick            # seconds (tests)

Parts (--only picks some; each writes into --out and is reused by the later ones):
  reference    whole runs as the reference figures were taken (`mps_lab run`, 2 threads,
               the scenes' own output, splashes allowed up to 50 %): mps and isph on the dam break at l0 = 0.025, 0.0125
               (time step 2.5e-4 s) to 2 s and at 0.005 (scenes/dambreak_fine.json) to 1 s;
               dfsph at l0 = 0.005 with density tolerance 0.1 % and 0.01 %, and at 0.0025 with
               0.1 %, to 1 s. -> reference.csv (one row per run: fluid particle-steps per second,
               mean iterations, ms per step of every phase from run.json's profile).
  resolutions  `mps_lab bench` at l0 = 0.025, 0.0125, 0.005, 0.0025 (time step 0.02 s/m x l0),
               after running to 0.02 s, 40 measured steps -> resolutions.json.
  scaling      `mps_lab bench` from about 1e3 to --max-fluid fluid particles (l0 = 0.05/k,
               k = 5 ... 142), with 1 and 2 threads, from rest, 3 + 10 measured steps (5 above
               3e5 particles) -> scaling.json.
  figures      performance_scaling.png (ns per fluid particle-step against N, log-log, with
               the +-30 % band around each method's median) and performance_phases.png (ms per
               step by phase at each resolution), and performance.md (the tables).
--docs copies the CSV/JSON/markdown to docs/data/ and the figures to docs/figures/.

Every measurement runs with OMP_PROC_BIND=true (unpinned threads on this machine class slow
down many-fold when another process runs); measure on an otherwise idle machine.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
METHODS = ["mps", "isph", "dfsph"]

# Reference figures of issue 7 (fluid particle-steps per second, 2 threads, same dam break).
REFERENCE = {
    ("MPS-Basic", 0.025, None): 0.23e6,
    ("MPS-Basic", 0.0125, None): 0.22e6,
    ("MPS-Basic", 0.005, None): 0.12e6,
    ("SPlisHSPlasH DFSPH", 0.005, 1e-3): 1.35e6,
    ("SPlisHSPlasH DFSPH", 0.0025, 1e-3): 1.96e6,
    ("SPlisHSPlasH DFSPH", 0.005, 1e-4): 0.5e6,
}

DFSPH_MAX_STEP_PER_SPACING = 1.0  # s/m

# Spacings l0 = 0.05 / k (the tank and the column are whole multiples): about 1e3 ... 1e6 fluid.
SCALING_K = [5, 9, 16, 28, 50, 90, 142]


def fluid_count(spacing: float) -> int:
    return (round(0.25 / spacing) - 1) * (round(0.5 / spacing) - 1)


def binary_path(arg: str | None) -> str:
    path = arg or os.environ.get("MPS_LAB_BINARY") or str(ROOT / "build" / "mps_lab")
    if not Path(path).exists():
        sys.exit(f"performance.py: no mps_lab binary at {path} (build it: tools/build.sh, or pass --binary)")
    return path


def environment(threads: int | None = None) -> dict:
    env = dict(os.environ)
    env["OMP_PROC_BIND"] = "true"
    if threads is not None:
        env["OMP_NUM_THREADS"] = str(threads)
    return env


def reference_cases(quick: bool) -> list[dict]:
    end_long, end_fine = (0.02, 0.01) if quick else (2.0, 1.0)
    cases = []
    for method in ["mps", "isph"]:
        cases.append(dict(method=method, scene="scenes/dambreak.json", spacing=0.025, tolerance=None,
                          sets=[], end=end_long))
        cases.append(dict(method=method, scene="scenes/dambreak.json", spacing=0.0125, tolerance=None,
                          sets=["particle_spacing=0.0125", "time.time_step=2.5e-4"], end=end_long))
        cases.append(dict(method=method, scene="scenes/dambreak_fine.json", spacing=0.005, tolerance=None,
                          sets=[], end=end_fine))
    for spacing, tolerance in [(0.005, 1e-3), (0.005, 1e-4), (0.0025, 1e-3)]:
        sets = [f"methods.dfsph.density_tolerance={tolerance}"]
        if spacing != 0.005:
            sets += [f"particle_spacing={spacing}", "time.time_step=5e-5",
                     f"methods.dfsph.max_time_step={DFSPH_MAX_STEP_PER_SPACING * spacing:g}"]
        cases.append(dict(method="dfsph", scene="scenes/dambreak_fine.json", spacing=spacing, tolerance=tolerance,
                          sets=sets, end=end_fine))
    if quick:
        cases = [c for c in cases if c["spacing"] == 0.025]
    return cases


def run_reference(binary: str, out: Path, quick: bool) -> None:
    rows = []
    for case in reference_cases(quick):
        name = f"{case['method']}_{case['spacing']}" + (f"_tol{case['tolerance']}" if case["tolerance"] else "")
        folder = out / "reference" / name
        # Splashes over the open top are not a failure of a speed run (MPS at l0 = 0.0125 sends
        # 5.1 % of its fluid over the top by 0.68 s, past the monitor's default 5 %).
        command = [binary, "run", f"--method={case['method']}", str(ROOT / case["scene"]), "-q", "--out", str(folder),
                   "--end-time", str(case["end"]), "--set", "stability.max_escaped_fraction=0.5"]
        for item in case["sets"]:
            command += ["--set", item]
        print("performance.py:", " ".join(command[1:]), flush=True)
        subprocess.run(command, check=False, env=environment(2))  # a run that stops early is reported
        run = json.loads((folder / "run.json").read_text())
        profile = run["profile"]
        row = dict(method=case["method"], particle_spacing=case["spacing"],
                   density_tolerance=case["tolerance"] or "", fluid_particles=run["particles"]["fluid"],
                   end_time=case["end"], steps=run["steps"], wall_seconds=run["wall_seconds"],
                   particle_steps_per_second=run["fluid_particle_steps_per_second"],
                   mean_iterations=run["solver"]["mean_iterations"], status=run["status"],
                   bytes_per_particle=run["memory"]["bytes_per_particle"])
        for phase, values in profile["phases"].items():
            row[f"ms_{phase}"] = values["milliseconds_per_step"]
        rows.append(row)
    columns = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    with open(out / "reference.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)


def bench(binary: str, arguments: list[str], json_path: Path) -> dict:
    # DFSPH's largest CFL step scales with l0 (1.0 s/m: SPlisHSPlasH's 5e-3 s at l0 = 0.005); a
    # fixed 5e-3 s makes the first steps from rest diverge below l0 = 0.0025 (docs/performance.md).
    command = [binary, "bench", str(ROOT / "scenes" / "dambreak.json"), "-q", "--json", str(json_path),
               "--per-spacing", f"methods.dfsph.max_time_step={DFSPH_MAX_STEP_PER_SPACING}"] + arguments
    print("performance.py:", " ".join(command[1:]), flush=True)
    result = subprocess.run(command, check=True, env=environment(), capture_output=True, text=True)
    print(result.stdout, flush=True)
    return json.loads(json_path.read_text())


def run_resolutions(binary: str, out: Path, quick: bool) -> None:
    spacings = "0.025" if quick else "0.025,0.0125,0.005,0.0025"
    steps = ["--steps", "3", "--warmup-steps", "1"] if quick else ["--steps", "40", "--warmup-steps", "5",
                                                                    "--start-time", "0.02"]
    bench(binary, ["--spacings", spacings, "--threads", "2"] + steps, out / "resolutions.json")


def run_scaling(binary: str, out: Path, max_fluid: float, quick: bool) -> None:
    ks = [5] if quick else [k for k in SCALING_K if fluid_count(0.05 / k) <= max_fluid * 1.01]
    cases = []
    for k in ks:
        spacing = 0.05 / k
        large = fluid_count(spacing) > 3e5
        steps = ["--steps", "2", "--warmup-steps", "1"] if quick else \
            ["--steps", "5" if large else "10", "--warmup-steps", "3"]
        part = bench(binary, ["--spacings", repr(spacing), "--threads", "1,2"] + steps,
                     out / f"scaling_k{k}.json")
        cases += part["cases"]
    (out / "scaling.json").write_text(json.dumps({"cases": cases}, indent=1) + "\n")


def load_cases(path: Path) -> list[dict]:
    return json.loads(path.read_text())["cases"] if path.exists() else []


def scaling_summary(cases: list[dict]) -> list[dict]:
    """Per method and thread count: ns per particle-step at each size, and the spread around the median."""
    rows = []
    for method in METHODS:
        for threads in (1, 2):
            points = sorted((c["fluid_particles"], c["nanoseconds_per_particle_step"]) for c in cases
                            if c.get("kind") == "steps" and c.get("method") == method and c.get("threads") == threads
                            and c.get("status") == "completed")
            if not points:
                continue
            values = sorted(v for _, v in points)
            median = values[len(values) // 2] if len(values) % 2 else 0.5 * (values[len(values) // 2 - 1] + values[len(values) // 2])
            rows.append(dict(method=method, threads=threads, points=points, median=median,
                             low=min(values) / median - 1.0, high=max(values) / median - 1.0))
    return rows


def speedups(cases: list[dict]) -> list[tuple]:
    out = []
    by_key = {(c["method"], c["fluid_particles"], c["threads"]): c for c in cases
              if c.get("kind") == "steps" and c.get("status") == "completed"}
    for (method, fluid, threads), case in sorted(by_key.items()):
        if threads == 2 and (method, fluid, 1) in by_key:
            one = by_key[(method, fluid, 1)]["seconds"]
            out.append((method, fluid, one / case["seconds"]))
    return out


def markdown(out: Path) -> str:
    lines = []
    reference_csv = out / "reference.csv"
    if reference_csv.exists():
        rows = list(csv.DictReader(open(reference_csv)))
        lines += ["## Whole runs against the reference figures (2 threads)", "",
                  "| method | l0 [m] | density tol. | fluid | steps | wall [s] | particle-steps/s | reference | ratio | mean iter. |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for row in rows:
            spacing = float(row["particle_spacing"])
            tolerance = float(row["density_tolerance"]) if row["density_tolerance"] else None
            code = "MPS-Basic" if row["method"] == "mps" else "SPlisHSPlasH DFSPH" if row["method"] == "dfsph" else None
            reference = REFERENCE.get((code, spacing, tolerance))
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
        for method in METHODS:
            values = {c["fluid_particles"]: c["mean_solver_iterations"] for c in scaling
                      if c["kind"] == "steps" and c["method"] == method and c["threads"] == 2 and c["status"] == "completed"}
            if values:
                lines.append(f"| {method} | " + " | ".join(f"{values[n]:.1f}" if n in values else "" for n in sizes) + " |")
        lines += ["", "Speed-up from 1 to 2 threads:", "", "| method | fluid | speed-up |", "|---|---|---|"]
        for method, fluid, ratio in speedups(scaling):
            lines.append(f"| {method} | {fluid:,} | {ratio:.2f} |")
        lines += ["", "Memory held by the simulation (resident, bytes per particle, 2 threads):", "",
                  "| method | " + " | ".join(f"{n:,}" for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
        for method in METHODS:
            values = {c["fluid_particles"]: c["memory_bytes_per_particle"] for c in scaling
                      if c["kind"] == "steps" and c["method"] == method and c["threads"] == 2 and c["status"] == "completed"}
            if values:
                lines.append(f"| {method} | " + " | ".join(f"{values[n]:.0f}" if n in values else "" for n in sizes) + " |")
        lines.append("")
    return "\n".join(lines)


def figures(out: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {"mps": "tab:blue", "isph": "tab:orange", "dfsph": "tab:green"}
    scaling = load_cases(out / "scaling.json")
    if scaling:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for row in scaling_summary(scaling):
            xs, ys = zip(*row["points"])
            style = "-o" if row["threads"] == 2 else "--s"
            ax.plot(xs, ys, style, color=colours[row["method"]], label=f"{row['method']}, {row['threads']} thread(s)",
                    markersize=4)
            if row["threads"] == 2:
                ax.fill_between([min(xs), max(xs)], 0.7 * row["median"], 1.3 * row["median"],
                                color=colours[row["method"]], alpha=0.08)
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="runs/performance")
    parser.add_argument("--binary")
    parser.add_argument("--only", nargs="+", choices=["reference", "resolutions", "scaling", "figures"])
    parser.add_argument("--max-fluid", type=float, default=1.1e6)
    parser.add_argument("--quick", action="store_true", help="tiny cases, for the tests")
    parser.add_argument("--docs", action="store_true", help="copy the results into docs/data and docs/figures")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    parts = args.only or ["reference", "resolutions", "scaling", "figures"]
    if any(part != "figures" for part in parts):
        binary = binary_path(args.binary)
    if "reference" in parts:
        run_reference(binary, out, args.quick)
    if "resolutions" in parts:
        run_resolutions(binary, out, args.quick)
    if "scaling" in parts:
        run_scaling(binary, out, args.max_fluid, args.quick)
    (out / "performance.md").write_text(markdown(out) + "\n")
    figures(out)
    if args.docs:
        for name in ["reference.csv", "resolutions.json", "scaling.json", "performance.md"]:
            if (out / name).exists():
                shutil.copy(out / name, ROOT / "docs" / "data" / ("performance_" + name if not name.startswith("performance") else name))
        for name in ["performance_scaling.png", "performance_phases.png"]:
            if (out / name).exists():
                shutil.copy(out / name, ROOT / "docs" / "figures" / name)
    print(f"performance.py: results in {out}/performance.md", flush=True)


if __name__ == "__main__":
    main()
