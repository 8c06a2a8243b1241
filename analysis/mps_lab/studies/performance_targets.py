"""The `targets` part of the performance study: each speed and memory target of the plan
(analysis/sweeps/performance.json, "targets") evaluated against what the study's folder holds,
as met, missed or not measured, with the measured value and its ratio to the limit
(targets.csv and a table in performance.md). Nothing runs here.

A target is {"name", "kind", "limit", "direction" ("at_most" | "at_least"), "why"} and the keys
of its kind; its kind names the file it reads:

  shared_machine   threads.csv: the largest ratio of a measured-team run beside the busy process
                   to the one-thread run alone (any method, any round)
  measured_team    threads.csv: the largest ratio of a measured-team run to the one-thread run,
                   alone, at the sizes part's sizes (any method, any round)
  side_by_side     side_by_side.csv (tools/reference-codes/side-by-side.sh's CSV, copied there by
                   --side-by-side): "pair", "measure" ("particle_steps": mps_lab's median
                   particle-steps per second over the reference code's; "simulated_seconds": the
                   reference code's median wall time over mps_lab's), as side_by_side_table.py
  memory           scaling.json: "method"'s resident bytes per particle at its largest size, 2 threads
  speedup          scaling.json: "method"'s speed-up from 1 to 2 threads at its largest size
  flat             scaling.json: "method"'s largest deviation from its median ns per particle-step
                   over the sizes, 2 threads (a fraction: 0.3 is +-30 %)
  million_minutes  million.csv: "method"'s wall time to 0.1 s, one row per run of the method
"""
from __future__ import annotations

import csv
import statistics
from pathlib import Path

from . import performance_million, performance_threads
from .performance_cases import load_cases, scaling_summary, speedups
from .common import SpecError, write_csv

KINDS = ("shared_machine", "measured_team", "side_by_side", "memory", "speedup", "flat", "million_minutes")
COLUMNS = ["name", "measured", "limit", "direction", "ratio", "status", "source"]


def check_targets(path: str, targets: list) -> None:
    """The plan's targets: an unknown kind or key, or a missing one, is a one-line SpecError."""
    for index, target in enumerate(targets):
        where = f"{path}: targets[{index}]"
        for key in ("name", "kind", "limit", "direction"):
            if key not in target:
                raise SpecError(f"{where}.{key}: missing")
        for key in target:
            if key not in ("name", "kind", "limit", "direction", "why", "pair", "measure", "method"):
                raise SpecError(f"{where}.{key}: unknown key (expected name, kind, limit, direction, why, pair, "
                                f"measure or method)")
        if target["kind"] not in KINDS:
            raise SpecError(f"{where}.kind: got {target['kind']!r}, expected one of: {', '.join(KINDS)}")
        if target["direction"] not in ("at_most", "at_least"):
            raise SpecError(f"{where}.direction: got {target['direction']!r}, expected at_most or at_least")
        needs = {"side_by_side": ("pair", "measure"), "memory": ("method",), "speedup": ("method",),
                 "flat": ("method",), "million_minutes": ("method",)}.get(target["kind"], ())
        for key in needs:
            if key not in target:
                raise SpecError(f"{where}.{key}: missing (kind {target['kind']})")
        if target.get("measure", "particle_steps") not in ("particle_steps", "simulated_seconds"):
            raise SpecError(f"{where}.measure: got {target['measure']!r}, expected particle_steps or simulated_seconds")


def side_by_side_rows(out: Path, pair: str) -> list[dict]:
    """The runs of `pair` in side_by_side.csv ([] without the file)."""
    path = out / "side_by_side.csv"
    if not path.exists():
        return []
    with open(path, newline="") as handle:
        return [row for row in csv.DictReader(handle) if row["pair"] == pair]


def side_by_side_ratio(rows: list[dict], measure: str) -> tuple[float, int] | None:
    """mps_lab over the reference code, as side_by_side_table.py gives it: the median particle-steps
    per second of mps_lab over the reference's ("particle_steps"), or the reference's median wall
    time over mps_lab's ("simulated_seconds"); and how many runs of each code. None without both."""
    ours = [row for row in rows if row["code"] == "mps_lab"]
    theirs = [row for row in rows if row["code"] != "mps_lab"]
    if not ours or not theirs:
        return None
    if measure == "particle_steps":
        ratio = statistics.median(float(r["particle_steps_per_s"]) for r in ours) / \
            statistics.median(float(r["particle_steps_per_s"]) for r in theirs)
    else:
        ratio = statistics.median(float(r["wall_s"]) for r in theirs) / statistics.median(float(r["wall_s"]) for r in ours)
    return ratio, min(len(ours), len(theirs))


def measured_values(target: dict, out: Path) -> list[tuple[float, str]]:
    """(value, where it comes from) of a target: one for most kinds, one per run for million_minutes."""
    kind = target["kind"]
    if kind in ("shared_machine", "measured_team"):
        part, load = ("shared", "busy") if kind == "shared_machine" else ("sizes", "alone")
        rows = [r for r in performance_threads.load_rows(out)
                if r["part"] == part and r["load"] == load and r["team"] == "measured"]
        if not rows:
            return []
        worst = max(rows, key=lambda r: r["ratio"])
        return [(worst["ratio"], f"threads.csv: {len(rows)} runs; largest {worst['method']}, "
                                 f"{worst['fluid_particles']:,} fluid, round {worst['round']}")]
    if kind == "side_by_side":
        found = side_by_side_ratio(side_by_side_rows(out, target["pair"]), target["measure"])
        return [(found[0], f"side_by_side.csv: medians of {found[1]} runs each")] if found else []
    if kind == "million_minutes":
        return [(row["wall_minutes"], f"million.csv: {row['git_revision'][:7]}, {row['started_at']}"
                 + (f", {row['overrides']}" if row["overrides"] else ""))
                for row in performance_million.load_rows(out)
                if row["method"] == target["method"] and row["status"] == "completed"]
    return scaling_value(target, out)


def scaling_value(target: dict, out: Path) -> list[tuple[float, str]]:
    """memory, speedup and flat, from scaling.json (the tables' own summaries, performance_cases.py)."""
    cases = load_cases(out / "scaling.json")
    method = target["method"]
    two = sorted((c for c in cases if c.get("kind") == "steps" and c.get("method") == method
                  and c.get("threads") == 2 and c.get("status") == "completed"), key=lambda c: c["fluid_particles"])
    if not two:
        return []
    largest = two[-1]
    where = f"scaling.json: {largest['fluid_particles']:,} fluid"
    if target["kind"] == "memory":
        return [(largest["memory_bytes_per_particle"], where)]
    if target["kind"] == "speedup":
        return [(ratio, where) for m, fluid, ratio in speedups(cases)
                if m == method and fluid == largest["fluid_particles"]]
    row = next(r for r in scaling_summary(cases) if r["method"] == method and r["threads"] == 2)
    return [(max(abs(row["low"]), abs(row["high"])),
             f"scaling.json: {two[0]['fluid_particles']:,}–{largest['fluid_particles']:,} fluid, "
             f"{100 * row['low']:+.0f} … {100 * row['high']:+.0f} %")]


def evaluate(targets: list[dict], out: Path) -> list[dict]:
    """One row per target (per run for million_minutes): measured, ratio to the limit, status."""
    rows = []
    for target in targets:
        limit = float(target["limit"])
        values = measured_values(target, out)
        if not values:
            rows.append(dict(name=target["name"], measured="", limit=limit, direction=target["direction"], ratio="",
                             status="not measured", source=""))
        for value, source in values:
            met = value <= limit if target["direction"] == "at_most" else value >= limit
            rows.append(dict(name=target["name"], measured=value, limit=limit, direction=target["direction"],
                             ratio=value / limit, status="met" if met else "missed", source=source))
    return rows


def write_targets(targets: list[dict], out: Path) -> None:
    write_csv(evaluate(targets, out), COLUMNS, str(out / "targets.csv"))


def targets_table(targets: list[dict], out: Path) -> list[str]:
    rows = evaluate(targets, out)
    if not rows:
        return []
    lines = ["## The targets (analysis/sweeps/performance.json), evaluated on this folder's data", "",
             "| target | measured | limit | measured / limit | status | from |", "|---|---|---|---|---|---|"]
    for row in rows:
        sign = "≤" if row["direction"] == "at_most" else "≥"
        measured = f"{row['measured']:.3g}" if row["measured"] != "" else "–"
        ratio = f"{row['ratio']:.2f}" if row["ratio"] != "" else "–"
        lines.append(f"| {row['name']} | {measured} | {sign} {row['limit']:g} | {ratio} | **{row['status']}** | "
                     f"{row['source'] or '–'} |")
    lines.append("")
    return lines
