"""The `million` part of the performance study (docs/performance.md, "The million-particle
scene"): each registered method runs `scenes/dambreak_large.json` (1,006,071 fluid particles) to
its end time, 0.1 s, on two threads, into out/million/<method>/; or, with --million-runs, runs
made before are summarised instead (their run folders, as kept in docs/data/). Hours per
method: the part runs only when asked for by name (--only million).

million.csv has one row per run: the method, fluid particles, steps, wall time in s and min,
mean solver iterations, the peak memory of the process per particle, the status, the scene's
overrides, the revision and when it started.
"""
from __future__ import annotations

import json
from pathlib import Path

from .. import SOURCE_ROOT, runner
from .common import read_rows_if_present, write_csv

ROOT = Path(SOURCE_ROOT)
SCENE = ROOT / "scenes" / "dambreak_large.json"
PROC_BIND = "true"
COLUMNS = ["method", "fluid_particles", "steps", "wall_seconds", "wall_minutes", "mean_iterations",
           "bytes_per_particle", "status", "overrides", "git_revision", "started_at", "folder"]

# The columns read back as numbers.
NUMERIC = {"fluid_particles", "steps", "wall_seconds", "wall_minutes", "mean_iterations", "bytes_per_particle"}


class MillionError(Exception):
    """A run folder without a readable run.json; the message is one line."""


def read_run(folder: Path) -> dict:
    try:
        return json.loads((folder / "run.json").read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise MillionError(f"{folder}: no readable run.json ({error})") from error


def row_of(run: dict, folder: Path) -> dict:
    return dict(method=run["method"], fluid_particles=run["particles"]["fluid"], steps=run["steps"],
                wall_seconds=run["wall_seconds"], wall_minutes=run["wall_seconds"] / 60.0,
                mean_iterations=run["solver"]["mean_iterations"],
                bytes_per_particle=run["memory"]["bytes_per_particle"], status=run["status"],
                overrides=" ".join(run.get("overrides", [])), git_revision=run.get("git_revision", ""),
                started_at=run.get("started_at", ""), folder=str(folder))


def run_million(binary: str, registered: list[str], out: Path, timeout: float) -> list[Path]:
    """Each registered method on the scene, 2 threads; the run folders (a monitor's stop is a result)."""
    folders = []
    for method in registered:
        folder = out / "million" / method
        arguments = ["run", str(SCENE), f"--method={method}", "--threads", "2", "--quiet", "--out", str(folder)]
        print("performance.py:", " ".join(arguments), flush=True)
        result = runner.run_case(binary, arguments, timeout=timeout, proc_bind=PROC_BIND, folder=str(folder))
        if not (folder / "run.json").exists():
            raise MillionError(f"{folder}: no run.json ({result.describe()}: {result.last_error_line()})")
        folders.append(folder)
    return folders


def write_million(folders: list[Path], out: Path) -> None:
    """million.csv from the run folders; raises MillionError for a folder without run.json."""
    write_csv([row_of(read_run(folder), folder) for folder in folders], COLUMNS, str(out / "million.csv"))


def load_rows(out: Path) -> list[dict]:
    """million.csv with its numbers parsed; [] without one."""
    return read_rows_if_present(str(out / "million.csv"), NUMERIC)


def million_table(out: Path) -> list[str]:
    rows = load_rows(out)
    if not rows:
        return []
    lines = ["## The million-particle scene to 0.1 s (2 threads)", "",
             "| method | fluid | steps | wall time | mean iterations | peak memory, B per particle | status | "
             "overrides | revision, started |",
             "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['method']} | {row['fluid_particles']:,} | {row['steps']} | "
                     f"{row['wall_minutes']:.1f} min | {row['mean_iterations']:.1f} | {row['bytes_per_particle']:.0f} | "
                     f"{row['status']} | {row['overrides'] or '–'} | {row['git_revision'][:7]}, {row['started_at']} |")
    lines.append("")
    return lines
