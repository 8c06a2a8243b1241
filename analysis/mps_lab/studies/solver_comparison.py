"""The project's AMG against hypre's BoomerAMG (tools/solver-comparison.sh): the table.

Reads the JSON files that build/mps_lab_solver_bench writes (one rank: both solvers, the
project's with each thread count; more ranks: BoomerAMG alone) and writes a Markdown table per
pressure system with set-up, solve and total time, iterations, heap per unknown, and the ratio
of BoomerAMG's total time to the project's at equal parallelism (1 thread = 1 rank, 2 threads =
2 ranks): above 1, the project's AMG is faster.
"""
from __future__ import annotations

import json
from pathlib import Path


def _rows(results: list[dict]) -> dict[tuple, dict]:
    """(method, spacing) -> {"unknowns", "solves": {(solver, parallelism): measure}}."""
    table: dict[tuple, dict] = {}
    for result in results:
        for case in result["cases"]:
            key = (case["method"], case["particle_spacing"])
            entry = table.setdefault(key, {"unknowns": case["unknowns"], "nonzeros": case["nonzeros"],
                                           "krylov": case["krylov"], "solves": {}})
            for solve in case["solves"]:
                parallelism = solve["ranks"] if solve["solver"] == "boomeramg" else solve["threads"]
                entry["solves"][(solve["solver"], parallelism)] = solve["measure"]
    return table


def _total(measure: dict) -> float:
    return measure["setup_seconds"] + measure["solve_seconds"]


def markdown(results: list[dict]) -> str:
    lines = ["| method | unknowns | Krylov | solver | threads/ranks | set-up [s] | solve [s] | total [s] "
             "| iterations | heap [B/unknown] | BoomerAMG / ours (total) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (method, _), entry in sorted(_rows(results).items(), key=lambda item: (item[0][0], item[1]["unknowns"])):
        solves = entry["solves"]
        for (solver, parallelism), m in sorted(solves.items()):
            ratio = ""
            ours = solves.get(("core_amg", parallelism))
            if solver == "boomeramg" and ours is not None:
                ratio = f"{_total(m) / _total(ours):.2f}"
            lines.append(f"| {method} | {entry['unknowns']:,} | {entry['krylov']} | {solver} | {parallelism} "
                         f"| {m['setup_seconds']:.4f} | {m['solve_seconds']:.4f} | {_total(m):.4f} "
                         f"| {m['iterations']} | {m['memory_bytes'] / entry['unknowns']:.0f} | {ratio} |")
    return "\n".join(lines) + "\n"


def write_table(inputs: list[Path], output: Path) -> str:
    results = [json.loads(path.read_text()) for path in inputs if path.exists()]
    text = markdown(results)
    output.write_text(text)
    return text
