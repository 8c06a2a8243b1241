"""The `threads` part of the performance study (docs/performance.md, "Threads that never hurt"):
what a run's team costs alone and on a shared machine, with one thread, two threads and the
team `mps_lab run` measures for itself (`--threads 0`, core/run/thread_governor.hpp).

  shared  every registered method on the spec dam break (scenes/dambreak.json) to
          `shared_end_time`, alone and beside one CPU-bound process (a Python busy loop),
          with 1, 2 and the measured team; the ratio is each run's wall time over the same
          method's one-thread run alone, in the same round.
  sizes   the spec dam break from rest at l0 = 0.05/k for each k of `sizes_k` (1,176, 3,916
          and 12,561 fluid particles for 5, 9, 16), `sizes_steps` steps of 0.02 s/m x l0, alone,
          with 1, 2 and the measured team (frames and series rows off); the ratio is ns per
          fluid particle-step over the one-thread run's, in the same round.

Every run's row goes to threads.csv (round, part, method, load, team, fluid particles, steps,
wall seconds, ns per fluid particle-step, status, the steps each team ran, the ratio).
"""
from __future__ import annotations

import contextlib
import json
import subprocess
import sys
from pathlib import Path

from .. import SOURCE_ROOT, runner
from .common import read_rows_if_present, write_csv

ROOT = Path(SOURCE_ROOT)
PROC_BIND = "true"
TEAMS = (1, 2, 0)  # --threads: one, two, and 0 = the measured team (the default)
COLUMNS = ["round", "part", "method", "load", "team", "fluid_particles", "steps", "wall_seconds",
           "ns_per_particle_step", "status", "steps_by_team", "ratio"]

# The columns read back as numbers.
NUMERIC = {"round", "fluid_particles", "steps", "wall_seconds", "ns_per_particle_step", "ratio"}


class ThreadsError(Exception):
    """A run of the part left no run.json; the message is one line."""


def team_name(threads: int) -> str:
    return "measured" if threads == 0 else str(threads)


def settings(plan: dict, quick: bool) -> dict:
    """The part's settings: the plan's `threads` block over the defaults (--quick: tiny)."""
    values = dict(rounds=1, shared_end_time=0.3, sizes_k=[5, 9, 16], sizes_steps=400)
    values.update(plan.get("threads", {}))
    if quick:
        values.update(rounds=1, shared_end_time=0.02, sizes_k=[5], sizes_steps=20)
    return values


def timed_run(binary: str, method: str, threads: int, folder: Path, extra: list[str], timeout: float) -> dict:
    """One `mps_lab run` of the spec dam break; its run.json (a stop by the monitor is a result)."""
    arguments = ["run", str(ROOT / "scenes" / "dambreak.json"), f"--method={method}", "--threads", str(threads),
                 "--quiet", "--out", str(folder)] + extra
    result = runner.run_case(binary, arguments, timeout=timeout, proc_bind=PROC_BIND, folder=str(folder))
    try:
        return json.loads((folder / "run.json").read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise ThreadsError(f"{folder}: no run.json ({result.describe()}: {result.last_error_line()})") from error


def row_of(run: dict, **fields) -> dict:
    fluid, steps = run["particles"]["fluid"], run["steps"]
    return dict(fields, fluid_particles=fluid, steps=steps, wall_seconds=run["wall_seconds"],
                ns_per_particle_step=1e9 * run["wall_seconds"] / max(1, fluid * steps), status=run["status"],
                steps_by_team=json.dumps(run.get("threads_used", {}).get("steps_by_team", {}), sort_keys=True))


class BusyProcess:
    """One CPU-bound process for the length of a `with` block."""

    def __enter__(self):
        self.process = subprocess.Popen([sys.executable, "-c", "while True: pass"])
        return self

    def __exit__(self, *exc):
        self.process.kill()
        self.process.wait()


def shared_rows(binary: str, method: str, number: int, end_time: float, out: Path, timeout: float) -> list[dict]:
    """One round of the shared part for one method: alone, then beside the busy process."""
    rows = []
    for load in ("alone", "busy"):
        for threads in TEAMS:
            folder = out / "threads" / f"shared-{method}-{load}-{team_name(threads)}-{number}"
            with BusyProcess() if load == "busy" else contextlib.nullcontext():
                run = timed_run(binary, method, threads, folder, ["--end-time", repr(end_time)], timeout)
            rows.append(row_of(run, round=number, part="shared", method=method, load=load, team=team_name(threads)))
    base = rows[0]["wall_seconds"]  # alone, one thread
    for row in rows:
        row["ratio"] = row["wall_seconds"] / base
    return rows


def size_rows(binary: str, method: str, number: int, k: int, steps: int, out: Path, timeout: float) -> list[dict]:
    """One round of the sizes part for one method and size: alone, 1, 2 and the measured team."""
    spacing = 0.05 / k
    step = 0.02 * spacing  # s
    extra = ["--end-time", repr(steps * step), "--set", f"particle_spacing={spacing!r}", "--set",
             f"time.time_step={step!r}", "--set", "output.frame_every_steps=1000000", "--set",
             "output.series_every_steps=1000000"]
    rows = []
    for threads in TEAMS:
        folder = out / "threads" / f"sizes-{method}-k{k}-{team_name(threads)}-{number}"
        run = timed_run(binary, method, threads, folder, extra, timeout)
        rows.append(row_of(run, round=number, part="sizes", method=method, load="alone", team=team_name(threads)))
    base = rows[0]["ns_per_particle_step"]
    for row in rows:
        row["ratio"] = row["ns_per_particle_step"] / base
    return rows


def run_threads(binary: str, plan: dict, registered: list[str], out: Path, quick: bool, timeout: float) -> None:
    """The part (module docstring) into out/threads.csv; raises ThreadsError."""
    values = settings(plan, quick)
    rows = []
    for number in range(1, int(values["rounds"]) + 1):
        for method in registered:
            rows += shared_rows(binary, method, number, float(values["shared_end_time"]), out, timeout)
            for k in values["sizes_k"]:
                rows += size_rows(binary, method, number, int(k), int(values["sizes_steps"]), out, timeout)
    write_csv(rows, COLUMNS, str(out / "threads.csv"))


def load_rows(out: Path) -> list[dict]:
    """threads.csv with its numbers parsed; [] without one."""
    return read_rows_if_present(str(out / "threads.csv"), NUMERIC)


def threads_table(out: Path) -> list[str]:
    """The markdown of threads.csv: ratio to one thread alone, per method, load and team."""
    rows = load_rows(out)
    if not rows:
        return []
    lines = ["## Threads: alone and beside one CPU-bound process (ratio to one thread alone)", "",
             "| part | method | fluid | load | 1 thread | 2 threads | measured team | round |",
             "|---|---|---|---|---|---|---|---|"]
    groups: dict[tuple, dict] = {}
    for row in rows:
        key = (row["part"], row["method"], row["fluid_particles"], row["load"], row["round"])
        groups.setdefault(key, {})[row["team"]] = row
    for (part, method, fluid, load, number), teams in groups.items():
        one = teams.get("1")
        first = f"{one['wall_seconds']:.2f} s" if part == "shared" and load == "alone" and one else \
            f"{one['ratio']:.2f}" if one else ""
        cells = [first] + [f"{teams[t]['ratio']:.2f}" if t in teams else "" for t in ("2", "measured")]
        lines.append(f"| {part} | {method} | {fluid:,} | {load} | " + " | ".join(cells) + f" | {number} |")
    lines += ["", "(shared: the spec dam break, whole runs, the ratio of wall times; sizes: from rest, ns per "
              "fluid particle-step over the one-thread run's; the first cell of a shared row alone is that "
              "run's wall time.)", ""]
    return lines
