"""The stability map: where each method breaks on the dam break, and how.

    /usr/bin/python3 analysis/stability_map.py analysis/sweeps/stability.json --out runs/stability_map
    /usr/bin/python3 analysis/stability_map.py SPEC.json --out DIR --parallel 2 --binary build/mps_lab
    /usr/bin/python3 analysis/stability_map.py SPEC.json --out DIR --collect      # only collect and plot

Every map's method must be registered in the binary (`mps_lab methods`); cases run through
the case runner (mps_lab/runner.py: arguments, --timeout per case, one retry after a crash).

For every map of SPEC (a method with a time-step axis; format in docs/stability.md, example
analysis/sweeps/stability.json) the grid time step x particle spacing l0 is run, each case an
ordinary `mps_lab run` to SPEC's end_time. The time step is a Courant number C = U dt / l0
with U = reference_speed = sqrt(2 g H) (the sweep's "courant" rule, studies/sweep.py, whose
grid, run and resume machinery this study reuses), or, for a method with an adaptive rule,
its cfl_number (methods.<method>.cfl_number: dt = cfl l0 / v_max). A case whose run.json says
completed, diverged, solver_failed or failed is finished and is not run again, so an
interrupted map resumes (an "interrupted" or unfinished case runs again from t = 0). Cases run --parallel at
a time, longest first, with OMP_NUM_THREADS = cores / parallel. SPEC's min_courant leaves
out the fixed steps below C at a spacing (the dearest cases, far below every limit).
--maps A,B runs only those maps' cases; --merge CSV takes every case without a finished run
in <out> from an earlier stability.csv (e.g. docs/data/stability_map.csv), so new maps join
the old ones in the CSVs and the figure without running the old ones again.

<out>/stability.csv, one row per case:
  map, method, rule           the map, the method, the time-step rule: "courant" (fixed dt) or "cfl"
  l0, courant, dt             spacing [m]; C (or the cfl_number); dt [s] (cfl rule: the mean step)
  status                      run.json status: completed | diverged | solver_failed | failed | ...
  stop_event, stop_time       the monitor event that stopped the run and the time it happened [s]
  first_event, first_event_time   the earliest monitor event of any kind, also in a completed run
  steps, simulated_time, wall_seconds, fluid_particles, mean_solver_iterations, max_courant
                              cost; max_courant = the largest max|u| dt / l0 in series.csv
                              (its sampled rows: a one-step peak may fall between them)
  front_rms, front_rms_shifted, front_best_shift
                              surge front Z against Martin & Moyce (completed cases only)
  message, name               run.json's message; the case folder under <out>/cases/
<out>/stability_summary.csv, one row per map and l0 (largest_stable_courant):
  largest_stable_courant      the largest C such that every C of the grid up to it completed
                              (empty when the smallest C did not complete)
  dt_at_limit, front_rms_at_limit, front_rms_shifted_at_limit   of that case
  first_unstable_courant, first_unstable_status, first_unstable_event   the next C of the grid
                              (empty: every C completed, the limit lies beyond the grid)
  completed_above_limit       completed cases at C beyond the first failure (a ragged edge)
  stable_band_from, stable_band_to   the first run of consecutive completed C: the upper limit
                              also where the smallest steps fail (e.g. DFSPH's splash at tiny dt)
<out>/stability.png: one panel per map, x = C (log), y = l0 (log); completed cases coloured by
front RMS; diverged / solver failed / failed cases coloured by outcome, their marker the event
that stopped them; a dashed line at the upper edge of the stable band.
"""
from __future__ import annotations

import math
import os
import sys

from .. import methods, runner
from . import sweep
from .common import (FINISHED, SpecError, case_folder, check_methods, check_spec_keys, load_json, merge_rows, read_rows,
                     status_of, write_csv)

DEFAULT_TIMEOUT = 3 * 3600.0  # s per case: far above any case of analysis/sweeps/stability.json; it stops a hung case
COLUMNS = ["map", "method", "rule", "l0", "courant", "dt", "status", "stop_event", "stop_time", "first_event",
           "first_event_time", "steps", "simulated_time", "wall_seconds", "fluid_particles", "mean_solver_iterations",
           "max_courant", "front_rms", "front_rms_shifted", "front_best_shift", "message", "name"]
NUMERIC_COLUMNS = {"l0", "courant", "dt", "stop_time", "first_event_time", "steps", "simulated_time", "wall_seconds",
                   "fluid_particles", "mean_solver_iterations", "max_courant", "front_rms", "front_rms_shifted",
                   "front_best_shift"}
SUMMARY_COLUMNS = ["map", "method", "rule", "l0", "largest_stable_courant", "dt_at_limit", "front_rms_at_limit",
                   "front_rms_shifted_at_limit", "first_unstable_courant", "first_unstable_status",
                   "first_unstable_event", "completed_above_limit", "stable_band_from", "stable_band_to"]
MAP_KEYS = {"method", "courant", "cfl_number", "spacings", "set", "title"}
# Words of the monitor's reasons (core/run/stability.cpp), for a stop event missing from a
# truncated event log.
REASON_WORDS = [("non-finite", "non_finite"), ("Courant number", "courant"), ("capped the speed", "speed_limited"),
                ("mechanical energy", "energy_growth"), ("left the domain", "escaped"), ("beyond a wall", "penetration"),
                ("density error", "density"), ("pressure solver", "solver")]


# --- the grid ------------------------------------------------------------------------------

def load_spec(path: str) -> dict:
    """The map specification, checked; raises SpecError with one line."""
    spec = load_json(path)
    check_spec_keys(path, spec, {"description", "scene", "end_time", "spacings", "reference_speed", "set", "min_courant", "maps"}, ("scene", "spacings", "maps"))
    try:
        floors = {float(l0): float(c) for l0, c in spec.get("min_courant", {}).items()}
    except (AttributeError, TypeError, ValueError) as error:
        raise SpecError(f"{path}: min_courant: expected an object {{\"l0\": C}} ({error})") from error
    if any(c <= 0 for c in floors.values()):
        raise SpecError(f"{path}: min_courant: expected numbers > 0")
    for name, entry in spec["maps"].items():
        where = f"{path}: maps.{name}"
        for key in entry:
            if key not in MAP_KEYS:
                raise SpecError(f"{where}.{key}: unknown key (expected one of: {', '.join(sorted(MAP_KEYS))})")
        if "method" not in entry:
            raise SpecError(f"{where}.method: missing")
        if ("courant" in entry) == ("cfl_number" in entry):
            raise SpecError(f"{where}: expected exactly one of courant, cfl_number (the time-step axis)")
        axis = entry.get("courant", entry.get("cfl_number"))
        if not axis or any(not isinstance(c, (int, float)) or c <= 0 for c in axis):
            raise SpecError(f"{where}: expected a non-empty array of numbers > 0 as the time-step axis")
    return spec


def sweep_spec_of(spec: dict, name: str) -> dict:
    """One map as a sweep.py specification: one time-step rule per value of its axis."""
    entry = spec["maps"][name]
    overrides = {**spec.get("set", {}), **entry.get("set", {})}
    if "courant" in entry:
        rules = [{"name": f"C_{c:g}", "courant": c, "set": overrides} for c in entry["courant"]]
    else:
        rules = [{"name": f"cfl_{c:g}", "set": {**overrides, f"methods.{entry['method']}.cfl_number": c}}
                 for c in entry["cfl_number"]]
    result = {key: spec[key] for key in ("scene", "end_time", "reference_speed") if key in spec}
    result["spacings"] = entry.get("spacings", spec["spacings"])
    # The map's name takes the tolerance slot of sweep.py's case name: two maps of one
    # method (DFSPH's fixed step and its CFL rule) never share a case folder.
    result["methods"] = {entry["method"]: {"time_step": rules, "tolerance": [{"name": name}]}}
    return result


def cases_of(spec: dict) -> list[dict]:
    """Every case of every map (sweep.py's cases, with map, rule and courant added), without
    the fixed steps below min_courant at a spacing (far below every limit, and the dearest)."""
    floors = {float(l0): float(c) for l0, c in spec.get("min_courant", {}).items()}
    cases = []
    for name, entry in spec["maps"].items():
        rule = "courant" if "courant" in entry else "cfl"
        axis = entry.get("courant", entry.get("cfl_number"))
        for case in sweep.cases_of(sweep_spec_of(spec, name)):
            index = [f"{'C' if rule == 'courant' else 'cfl'}_{c:g}" for c in axis].index(case["time_step_rule"])
            case.update({"map": name, "rule": rule, "courant": axis[index]})
            if rule == "courant" and case["courant"] < floors.get(float(case["l0"]), 0.0):
                continue
            cases.append(case)
    return cases


def estimated_cost(case: dict) -> float:
    """Particles x steps ~ l0^-2 x (C l0)^-1: run the longest cases first, for load balance."""
    return 1.0 / (case["courant"] * case["l0"] ** 3)


# --- one case ------------------------------------------------------------------------------

def stop_event_of(summary: dict) -> str:
    """The monitor event that stopped a diverged or solver-failed run ("" otherwise)."""
    if summary.get("status") not in ("diverged", "solver_failed"):
        return ""
    stability = summary.get("stability", {})
    events = stability.get("events", [])
    if events and stability.get("events_total", len(events)) == len(events):
        return events[-1]["kind"]  # the monitor records the event, then stops
    message = summary.get("message", "")
    reason = message.split("because", 1)[-1]
    return next((kind for words, kind in REASON_WORDS if words in reason), "unknown")


def first_event_of(summary: dict) -> tuple[str, float]:
    """(kind, time) of the earliest monitor event, ("", nan) when there was none."""
    firsts = summary.get("stability", {}).get("first_event", {})
    if not firsts:
        return "", math.nan
    event = min(firsts.values(), key=lambda e: (e["step"], e["time"]))
    return event["kind"], float(event["time"])


def row_of(case: dict, out: str) -> dict:
    """One row of stability.csv."""
    folder = case_folder(out, case["name"])
    row = {key: case[key] for key in ("map", "method", "rule", "l0", "courant", "name")}
    row["dt"] = case["overrides"].get("time.time_step", math.nan)
    row["status"] = status_of(out, case)
    if row["status"] not in FINISHED:
        return row
    run, measured = sweep.measure(folder, row["status"])
    row.update(measured)
    if run is None:
        return row
    summary = run.summary
    row["simulated_time"] = float(summary.get("simulated_time", math.nan))
    row["message"] = summary.get("message", "")
    row["stop_event"] = stop_event_of(summary)
    row["stop_time"] = row["simulated_time"] if row["stop_event"] else math.nan
    row["first_event"], row["first_event_time"] = first_event_of(summary)
    courant = run.series.get("courant_number")
    row["max_courant"] = float(courant.max()) if courant is not None and len(courant) else math.nan
    if case["rule"] == "cfl" and row["steps"]:
        row["dt"] = row["simulated_time"] / row["steps"]
    return row


# --- the limit -----------------------------------------------------------------------------

def stable_band(rows: list[dict]) -> list[dict]:
    """The first run of consecutive completed cases in C order (rows sorted by C): the stable
    band even where the smallest steps fail too."""
    band = []
    for row in rows:
        if row["status"] == "completed":
            band.append(row)
        elif band:
            break
    return band


def largest_stable(rows: list[dict]) -> list[dict]:
    """Per map and l0: the largest C such that every C of the grid up to it completed."""
    groups: dict[tuple, list[dict]] = {}
    for row in rows:
        groups.setdefault((row["map"], row["l0"]), []).append(row)
    summary = []
    for (name, l0), mine in groups.items():
        mine = sorted(mine, key=lambda r: r["courant"])
        stable = None
        for row in mine:
            if row["status"] != "completed":
                break
            stable = row
        unstable = next((r for r in mine if r["status"] != "completed"), None)
        above = [r for r in mine if unstable is not None and r["courant"] > unstable["courant"]
                 and r["status"] == "completed"]
        band = stable_band(mine)
        summary.append({
            "map": name, "method": mine[0]["method"], "rule": mine[0]["rule"], "l0": l0,
            "largest_stable_courant": stable["courant"] if stable else math.nan,
            "dt_at_limit": stable.get("dt", math.nan) if stable else math.nan,
            "front_rms_at_limit": stable.get("front_rms", math.nan) if stable else math.nan,
            "front_rms_shifted_at_limit": stable.get("front_rms_shifted", math.nan) if stable else math.nan,
            "first_unstable_courant": unstable["courant"] if unstable else math.nan,
            "first_unstable_status": unstable["status"] if unstable else "",
            "first_unstable_event": unstable.get("stop_event", "") if unstable else "",
            "completed_above_limit": len(above),
            "stable_band_from": band[0]["courant"] if band else math.nan,
            "stable_band_to": band[-1]["courant"] if band else math.nan,
        })
    order = {name: k for k, name in enumerate(dict.fromkeys(r["map"] for r in rows))}
    return sorted(summary, key=lambda s: (order[s["map"]], -s["l0"]))


# --- the figure ----------------------------------------------------------------------------

OUTCOMES = {"diverged": ("tab:red", "diverged"), "solver_failed": ("tab:orange", "solver failed"),
            "failed": ("black", "failed")}  # status: colour, legend
EVENTS = {  # the stopping event: marker, legend
    "courant": ("X", "Courant number"), "speed_limited": ("P", "speed clamp binding"),
    "energy_growth": ("D", "energy growth"), "penetration": ("v", "wall penetration"), "escaped": ("*", "escaped"),
    "density": ("h", "density error"), "non_finite": ("8", "NaN/Inf"), "solver": ("^", "solver"),
}


def stopped_marker(row: dict) -> str:
    return EVENTS.get(row.get("stop_event", ""), ("s", ""))[0]


def upper_edge(rows: list[dict]) -> float | None:
    """C between the top of the stable band and the next C of the grid (None: no such edge)."""
    mine = sorted(rows, key=lambda r: r["courant"])
    band = stable_band(mine)
    beyond = [r for r in mine if band and r["courant"] > band[-1]["courant"]]
    return math.sqrt(band[-1]["courant"] * beyond[0]["courant"]) if beyond else None


def plot_map(ax, rows: list[dict], norm, cmap) -> None:
    """One map: completed cases coloured by front RMS, the others coloured by outcome with the
    stopping event as marker, the upper edge of the stable band dashed."""
    done = [r for r in rows if r["status"] == "completed"]
    ax.scatter([r["courant"] for r in done], [r["l0"] for r in done], s=110, marker="o", edgecolors="k",
               c=[r.get("front_rms", math.nan) for r in done], cmap=cmap, norm=norm, plotnonfinite=True, zorder=3)
    for r in done:
        if math.isfinite(r.get("front_rms", math.nan)):
            ax.annotate(f"{r['front_rms']:.2f}", (r["courant"], r["l0"]), xytext=(0, 8), textcoords="offset points",
                        ha="center", fontsize=6.5)
    for r in rows:
        if r["status"] in OUTCOMES:
            ax.scatter([r["courant"]], [r["l0"]], s=80, marker=stopped_marker(r), color=OUTCOMES[r["status"]][0],
                       zorder=3)
        elif r["status"] != "completed":
            ax.scatter([r["courant"]], [r["l0"]], s=60, marker="$?$", color="grey", zorder=3)
    spacings = sorted({r["l0"] for r in rows})
    edge = [(upper_edge([r for r in rows if r["l0"] == l0]), l0) for l0 in spacings]
    edge = [(c, l0) for c, l0 in edge if c is not None]
    if edge:
        ax.plot([c for c, _ in edge], [l0 for _, l0 in edge], "k--", lw=1.0, zorder=2)
    courants = sorted({r["courant"] for r in rows})
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(courants[0] / 1.5, courants[-1] * 1.5)
    ax.set_ylim(spacings[0] / 1.5, spacings[-1] * 1.5)
    ax.set_xticks(courants)
    ax.set_xticklabels([f"{c:g}" for c in courants], fontsize=8)
    ax.set_yticks(spacings)
    ax.set_yticklabels([f"{l:g}" for l in spacings])
    ax.minorticks_off()


def legend_handles(rows: list[dict]) -> list:
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], marker="o", color="w", markerfacecolor="tab:green", markeredgecolor="k", markersize=9,
                      label="completed (colour and number: front RMS)")]
    for status, (colour, label) in OUTCOMES.items():
        if any(r["status"] == status for r in rows):
            handles.append(Line2D([], [], marker="s", color="w", markerfacecolor=colour, markeredgecolor=colour,
                                  markersize=8, label=f"{label} (colour)"))
    for kind, (marker, label) in EVENTS.items():
        if any(r.get("stop_event") == kind for r in rows):
            handles.append(Line2D([], [], marker=marker, color="w", markerfacecolor="grey", markeredgecolor="grey",
                                  markersize=8, label=f"stopped by: {label}"))
    handles.append(Line2D([], [], color="k", linestyle="--", label="upper edge of the stable band"))
    return handles


def plot(rows: list[dict], path: str, titles: dict[str, str]) -> None:
    """stability.png: one panel per map (the module's docstring)."""
    from .. import figures  # noqa: F401  (sets the shared style)
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    names = list(dict.fromkeys(r["map"] for r in rows))
    errors = [r["front_rms"] for r in rows if r["status"] == "completed"
              and math.isfinite(r.get("front_rms", math.nan)) and r["front_rms"] > 0]
    norm = LogNorm(vmin=min(errors + [0.05]), vmax=max(errors + [1.0]))
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("white")
    columns = 2 if len(names) > 2 else len(names)
    lines = math.ceil(len(names) / columns)
    height = 3.6 * lines + 1.6
    fig, axes = plt.subplots(lines, columns, figsize=(7.0 * columns + 1.2, height), squeeze=False)
    for ax, name in zip(axes.flat, names):
        mine = [r for r in rows if r["map"] == name]
        plot_map(ax, mine, norm, cmap)
        fixed = mine[0]["rule"] == "courant"
        ax.set_title(titles.get(name) or f"{mine[0]['method']}" + (" (fixed dt)" if fixed else " (own CFL rule)"))
        ax.set_xlabel("C = U dt / l0, U = sqrt(2 g H) = 3.13 m/s" if fixed else "cfl_number (dt = cfl l0 / v_max)")
        ax.set_ylabel("l0 [m]")
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    fig.subplots_adjust(left=0.07, right=0.9, bottom=1.3 / height, top=1 - 0.85 / height, wspace=0.18, hspace=0.5)
    bar = fig.add_axes([0.92, 0.25, 0.012, 0.6])
    bar.grid(False)
    colorbar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), cax=bar)
    ticks = [t for t in (0.05, 0.1, 0.2, 0.5, 1.0, 2.0) if norm.vmin <= t <= norm.vmax]
    colorbar.set_ticks(ticks)
    colorbar.set_ticklabels([f"{t:g}" for t in ticks])
    colorbar.set_label("front RMS in Z against Martin & Moyce (completed cases)")
    fig.legend(handles=legend_handles(rows), loc="lower center", ncol=4, fontsize=8.5, frameon=False)
    fig.suptitle("Stability map of the dam break to t = 0.5 s", fontsize=12)
    fig.savefig(path)
    plt.close(fig)


# --- main ----------------------------------------------------------------------------------

def print_limits(rows: list[dict], limits: list[dict], out: str) -> None:
    counts = {status: sum(r["status"] == status for r in rows) for status in dict.fromkeys(r["status"] for r in rows)}
    print(f"stability_map: {len(rows)} cases ({', '.join(f'{n} {s}' for s, n in counts.items())}) -> "
          f"{os.path.join(out, 'stability.csv')}")
    for s in limits:
        limit = "none" if math.isnan(s["largest_stable_courant"]) else f"{s['largest_stable_courant']:g}"
        beyond = (f", then {s['first_unstable_status']} ({s['first_unstable_event'] or '-'}) at "
                  f"{s['first_unstable_courant']:g}" if s["first_unstable_status"] else ", every case completed")
        band = ("" if not math.isnan(s["largest_stable_courant"]) or math.isnan(s["stable_band_from"])
                else f"; stable band {s['stable_band_from']:g} to {s['stable_band_to']:g}")
        print(f"stability_map: {s['map']} l0 = {s['l0']:g}: largest stable {s['rule']} {limit}{beyond}{band}")


def stability_map(spec_path: str, out: str, binary: str | None = None, parallel: int = 1,
                  timeout: float = DEFAULT_TIMEOUT, collect_only: bool = False, plots: bool = True,
                  only_maps: list[str] | None = None, merge: str | None = None) -> int:
    """The whole map (module docstring); 0, or 2 with one line on stderr for a bad spec or no binary."""
    try:
        spec = load_spec(spec_path)
        found = None if collect_only else runner.find_binary(binary)
        if found is not None:
            check_methods(list(dict.fromkeys(entry["method"] for entry in spec["maps"].values())),
                          methods.registered_methods(found), f"{spec_path}: maps.*.method")
        unknown = [name for name in only_maps or [] if name not in spec["maps"]]
        if unknown:
            raise SpecError(f"--maps: {unknown[0]}: not a map of {spec_path} (it has: {', '.join(spec['maps'])})")
        earlier = read_rows(merge, NUMERIC_COLUMNS) if merge else []
    except (SpecError, runner.BinaryNotFound, methods.MethodListError, OSError, KeyError, ValueError) as error:
        print(f"stability_map.py: {error}", file=sys.stderr)
        return 2
    cases = cases_of(spec)
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    parallel = max(1, parallel)
    if not collect_only:
        ordered = sorted([c for c in cases if not only_maps or c["map"] in only_maps], key=estimated_cost, reverse=True)
        sweep.run_cases(ordered, spec, out, found, parallel, runner.threads_per_case(parallel), timeout,
                        label="stability_map")
    rows = [row_of(case, out) for case in cases]
    if merge:
        rows, taken = merge_rows(rows, earlier)
        print(f"stability_map: {taken} case(s) taken from {merge}")
    limits = largest_stable(rows)
    write_csv(rows, COLUMNS, os.path.join(out, "stability.csv"))
    write_csv(limits, SUMMARY_COLUMNS, os.path.join(out, "stability_summary.csv"))
    print_limits(rows, limits, out)
    if plots and rows:
        titles = {name: entry.get("title", "") for name, entry in spec["maps"].items()}
        plot(rows, os.path.join(out, "stability.png"), titles)
    return 0
