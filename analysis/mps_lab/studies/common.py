"""What the studies share: the statuses that end a case, the case folders, CSV output and
the check of a specification's methods against the registered ones."""
from __future__ import annotations

import csv
import json
import math
import os

from .. import SOURCE_ROOT

# Statuses of run.json that end a case for good (docs/scene-format.md, `stability`): a
# diverged or solver-failed run is an outcome to record, not an interruption to resume.
FINISHED = ("completed", "diverged", "solver_failed", "failed")


class SpecError(Exception):
    """A bad study specification or option; the message is one line naming the key."""


def load_json(path: str) -> dict:
    try:
        with open(path) as handle:
            return json.load(handle)
    except (OSError, json.JSONDecodeError) as error:
        raise SpecError(f"{path}: {error}") from error


def check_spec_keys(path: str, spec: dict, known: set[str], required: tuple[str, ...]) -> None:
    """A study file's keys: an unknown or a missing one is a one-line SpecError naming it."""
    for key in spec:
        if key not in known:
            raise SpecError(f"{path}: {key}: unknown key (expected one of: {', '.join(sorted(known))})")
    for key in required:
        if key not in spec:
            raise SpecError(f"{path}: {key}: missing")


def source_path(path: str) -> str:
    """A path of a specification (a scene): absolute as given, else relative to the source tree."""
    return path if os.path.isabs(path) else os.path.join(SOURCE_ROOT, path)


def case_folder(out: str, name: str) -> str:
    return os.path.join(out, "cases", name)


def run_summary(folder: str) -> dict | None:
    """run.json of a run folder, None when there is none (or it is unreadable)."""
    try:
        with open(os.path.join(folder, "run.json")) as handle:
            return json.load(handle)
    except (OSError, json.JSONDecodeError):
        return None


def status_of(out: str, case: dict) -> str:
    """run.json's status of a case, "missing" without one."""
    summary = run_summary(case_folder(out, case["name"]))
    return summary.get("status", "unknown") if summary is not None else "missing"


def check_methods(wanted: list[str], registered: list[str], where: str) -> None:
    """Every method a specification names is registered in the binary."""
    for method in wanted:
        if method not in registered:
            raise SpecError(f"{where}.{method}: not a registered method (mps_lab methods lists: "
                            f"{', '.join(registered)})")


def formatted(value, digits: int = 3) -> str:
    """A table cell: a float to `digits` decimals (NaN as empty), anything else as it is."""
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.{digits}f}"
    return str(value)


def write_study_tables(target: str, name: str, rows: list[dict], columns: list[str], table: str) -> str:
    """TARGET/data/NAME.csv and TARGET/data/NAME.md (the markdown `table`); returns the path of
    the study's figure, TARGET/figures/NAME.png (its folder made)."""
    os.makedirs(os.path.join(target, "data"), exist_ok=True)
    os.makedirs(os.path.join(target, "figures"), exist_ok=True)
    write_csv(rows, columns, os.path.join(target, "data", f"{name}.csv"))
    with open(os.path.join(target, "data", f"{name}.md"), "w") as handle:
        handle.write(table)
    return os.path.join(target, "figures", f"{name}.png")


def write_csv(rows: list[dict], columns: list[str], path: str, nan_as_empty: bool = True) -> None:
    """Atomically (a temporary file renamed); NaN as an empty cell, or as "nan" (sweep.csv)."""
    def cell(value):
        return "" if nan_as_empty and isinstance(value, float) and math.isnan(value) else value

    temporary = path + ".tmp"
    with open(temporary, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({key: cell(row.get(key, "")) for key in columns})
    os.replace(temporary, path)


def read_rows(path: str, numeric: set[str]) -> list[dict]:
    """The rows of an earlier study CSV (sweep.csv, stability.csv, wall_study.csv); the `numeric`
    columns as numbers (an integer's text as int, so it is written back the same; a missing
    or empty cell, or "nan": NaN), the others as text."""
    def number(text: str) -> float | int:
        text = text.strip()
        if not text:
            return math.nan
        try:
            return int(text)
        except ValueError:
            return float(text)

    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        for key in numeric:
            row[key] = number(row.get(key) or "")
    return rows


def read_rows_if_present(path: str, numeric: set[str]) -> list[dict]:
    """read_rows of a study CSV that a part may not have written yet: [] without the file."""
    return read_rows(path, numeric) if os.path.exists(path) else []


def merge_rows(rows: list[dict], earlier: list[dict]) -> tuple[list[dict], int]:
    """Each row without a finished run here replaced by the earlier row of the same case (same
    "name"), when there is one; earlier rows of cases not in this grid are dropped. Returns the
    rows and how many were taken from `earlier` (the --merge of sweep.py and stability_map.py)."""
    by_name = {row["name"]: row for row in earlier}
    merged, taken = [], 0
    for row in rows:
        if row["status"] not in FINISHED and row["name"] in by_name:
            merged.append(by_name[row["name"]])
            taken += 1
        else:
            merged.append(row)
    return merged, taken
