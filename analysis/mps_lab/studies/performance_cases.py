"""What the performance study's parts read back from `mps_lab bench` JSON (scaling.json,
resolutions.json): the cases, the methods measured, the spread of the scaling around its median
and the speed-ups from 1 to 2 threads. Shared by the tables (performance.py) and the targets
(performance_targets.py)."""
from __future__ import annotations

import json
from pathlib import Path


def load_cases(path: Path) -> list[dict]:
    return json.loads(path.read_text())["cases"] if path.exists() else []


def methods_in(cases: list[dict]) -> list[str]:
    """The methods measured in bench cases, sorted (bench runs every registered method)."""
    return sorted({c["method"] for c in cases if c.get("kind") == "steps" and "method" in c})


def scaling_summary(cases: list[dict]) -> list[dict]:
    """Per method and thread count: ns per particle-step at each size, and the spread around the median."""
    rows = []
    for method in methods_in(cases):
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
