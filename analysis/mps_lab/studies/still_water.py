"""Still water at the wall sensors: issue 14's 1 % target, measured the way the test suite does.

    /usr/bin/python3 analysis/still_water.py --out runs/still_water                    # every method and model
    /usr/bin/python3 analysis/still_water.py --methods isph --set methods.isph.kernel='"wendland_c2"'
    /usr/bin/python3 analysis/still_water.py --methods eisph --realisations 6 --end-time 3
    /usr/bin/python3 analysis/still_water.py --defaults --window 0.5 1.5 --end-time 1.5  # the defaults' test
    /usr/bin/python3 analysis/still_water.py --methods mps --models distance_function \
        --model-set distance_function.velocity='"free_slip"' --realisations 12
    /usr/bin/python3 analysis/still_water.py --spacing 0.025 0.0125 0.00625 --out runs/still_water_resolution

scenes/hydrostatic.json (l0 = 0.025 m, water 0.275 m deep between the bed's and the lattice's top
edge) with three sensors on the left wall's surface (x = l0/2) at y = 0.0625, 0.1375 and
0.2125 m, depths h = 0.225, 0.15 and 0.075 m below the lattice's top edge (the top row of
particle centres + l0/2, taken from the run's first frame), and a dry sensor at 0.5 m: the
sensors of tests/test_pressure_sensors.cpp. Each method runs with its load setting
(`--load-setting`, the setting its promise is for; `--defaults`: without it) and with each
boundary model it supports (`--set methods.M.wall_treatments={"MODEL":{}}`, as the test; `--models`
keeps only the models named, `--model-set MODEL.KEY=VALUE` puts an option in that model's block),
then the `--set`s given here. `--spacing L0 [L0 ...]` runs the same tank at these particle spacings,
the scene's time step and the method's `max_time_step` scaled by L0/0.025, the sensors on the
wall surface (x = L0/2); h is then taken below each run's lattice top edge. With two spacings or
more the markdown has a section per spacing and a resolution table, and
<out>/still_water_resolution.png plots each sensor against l0. A realisation k > 0 scales
gravity by 1 + k 1e-10: far below any physical effect, it draws another realisation of water
that never comes to rest (docs/validation.md, "Realisations").

Each sensor's reading is the time-weighted mean over the window of series.csv's rows (a row is
the mean since the row before; it counts with its overlap with the window), divided by
rho |g| h with the run's own density and gravity. Methods and models are read from the binary
(`mps_lab methods --parameters`), so a method or model added later is measured without an edit.

<out>/still_water.csv, one row per case: method, boundary_model, realisation, status, the three
ratios (ratio_h0225, ratio_h0150, ratio_h0075), dry (the dry sensor's mean, Pa: 0 unless
broken), worst (the largest |ratio - 1|), within_1pct (sensors within 1 %) and particle_spacing
(m). A case that failed has its exit and the binary's last error line as its status.
<out>/still_water.md: per method the ratios of every model and realisation, the range, how many
sensors are within 1 %, and the method's promise (its load setting's tolerance).
With two or more realisations, <out>/still_water_expected.csv, its figure
<out>/still_water_expected.png and a second table in the markdown:
each sensor's expected reading over the realisations, mean ± standard error, and its verdict on
the 1 % target (within or outside by more than two standard errors, else undecided). A method whose
water never comes to rest reads differently in each realisation, and one run's miss may be its
noise; a deterministic one reads the same in all (standard error 0) and its misses are its own.
The CSV also has each sensor's single-run standard deviation and the chance that one run reads it
within 1 %, as measured and about an exact expectation (what the noise alone allows); the markdown
gives per method the chance that one run reads every sensor within 1 %."""
from __future__ import annotations

import csv
import json
import math
import os

from .. import SOURCE_ROOT, runner
from ..methods import method_catalogue
from .common import SpecError, check_methods, run_summary, write_csv

SCENE = os.path.join(SOURCE_ROOT, "scenes", "hydrostatic.json")
SENSOR_HEIGHTS = (0.0625, 0.1375, 0.2125)  # m, on the left wall's surface, x = l0/2
DRY_HEIGHT = 0.5  # m, above the water
TARGET = 0.01  # issue 14: within 1 % of rho g h
RATIOS = ["ratio_h0225", "ratio_h0150", "ratio_h0075"]
COLUMNS = ["method", "boundary_model", "realisation", "status", *RATIOS, "dry", "worst", "within_1pct",
           "particle_spacing"]
DEFAULT_TIMEOUT = 600.0  # s per case; a case runs in seconds


def read_scene() -> dict:
    with open(SCENE) as handle:
        return json.load(handle)


def scene_spacing_and_step() -> tuple[float, float]:
    """The tank scene's particle spacing l0 (m) and time step (s)."""
    scene = read_scene()
    return scene["particle_spacing"], scene["time"]["time_step"]


def step_bound(info, method: str) -> float | None:
    """The method's `max_time_step` on the tank (s): the scene's value, else its declared default
    (`mps_lab methods -p`); None if it declares none."""
    scene_value = read_scene().get("methods", {}).get(method, {}).get("max_time_step")
    if scene_value is not None:
        return float(scene_value)
    listed = info.parameter_defaults.get("max_time_step")
    return float(listed) if listed is not None else None


def sensors_override(spacing: float) -> str:
    """The scene key of the test's sensors (tests/test_pressure_sensors.cpp, tank_sensors), on the
    left wall's surface: the fluid lattice starts at x = l0 and the wall's first particle line is
    x = 0, so the surface is x = l0/2 at every spacing."""
    points = [(f"s{k}", y) for k, y in enumerate(SENSOR_HEIGHTS)] + [("dry", DRY_HEIGHT)]
    return "diagnostics.pressure_sensors=[" + ",".join(
        f'{{"name": "{name}", "position": [{0.5 * spacing!r}, {y}]}}' for name, y in points) + "]"


def spacing_overrides(spacing: float | None, method: str, max_step: float | None) -> list[str]:
    """Another particle spacing for the tank: l0, and the scene's time step and the method's
    `max_time_step` (max_step, s) scaled with it: a fixed Courant number for the water's own speed
    scale, the gravity wave's sqrt(g H). (Still water has no speed of its own, so a step rule on
    v_max sits at its upper bound; unscaled, dfsph's 5e-3 s at l0 = 0.00625 m leaves its density
    solver unconverged and the tank diverges.)"""
    if spacing is None:
        return []
    scene_spacing, scene_step = scene_spacing_and_step()
    scale = spacing / scene_spacing
    overrides = ["--set", f"particle_spacing={spacing!r}", "--set", f"time.time_step={scene_step * scale!r}"]
    if max_step is not None:
        overrides += ["--set", f"methods.{method}.max_time_step={max_step * scale!r}"]
    return overrides


def model_block(model: str, model_options: dict | None) -> str:
    """The scene's wall_treatments object of a case: the model with its options (`--model-set`:
    {model: {key: value}}), {} for its defaults."""
    return json.dumps({model: (model_options or {}).get(model, {})}, separators=(",", ":"))


def parse_model_options(settings: list[str]) -> dict:
    """`--model-set MODEL.KEY=VALUE` (VALUE as JSON) -> {MODEL: {KEY: value}}; SpecError on bad input."""
    options: dict = {}
    for setting in settings:
        name, equals, text = setting.partition("=")
        model, dot, key = name.partition(".")
        if not equals or not dot or not model or not key:
            raise SpecError(f"--model-set {setting}: expected MODEL.KEY=VALUE")
        try:
            options.setdefault(model, {})[key] = json.loads(text)
        except json.JSONDecodeError as error:
            raise SpecError(f"--model-set {setting}: VALUE is not JSON ({error.msg})") from None
    return options


def case_arguments(method: str, model: str, realisation: int, folder: str, end_time: float, load_setting: bool,
                   overrides: list[str], spacing: float | None = None, max_step: float | None = None,
                   model_options: dict | None = None) -> list[str]:
    """`mps_lab run` of one case: the tank (at `spacing`, else the scene's; max_step: the method's
    step bound at the scene's spacing, s), the method's load setting, the model with its
    `model_options` ({model: {key: value}}), every step's row."""
    arguments = ["run", SCENE, "--method", method, "--out", folder, "--quiet", "--end-time", f"{end_time:g}",
                 *spacing_overrides(spacing, method, max_step),
                 "--set", sensors_override(spacing or scene_spacing_and_step()[0]),
                 "--set", "output.series_every_steps=1",
                 "--set", "output.frame_every_steps=1000000000", "--set", 'output.formats=["csv"]',
                 "--set", f"methods.{method}.wall_treatments={model_block(model, model_options)}"]
    if load_setting:
        arguments.append("--load-setting")
    if realisation > 0:
        arguments += ["--set", f"physics.gravity=[0, {-9.81 * (1.0 + realisation * 1e-10)!r}]"]
    for override in overrides:
        arguments += ["--set", override]
    return arguments


def requests(out: str, catalogue: dict, methods: list[str], realisations: int, end_time: float,
             load_setting: bool, overrides: list[str], spacings: list[float] | None = None,
             models: list[str] | None = None, model_options: dict | None = None):
    """One CaseRequest per spacing x method x boundary model x realisation (spacings None: the
    scene's; models None: every model the method supports, else those of them named)."""
    scene_spacing = scene_spacing_and_step()[0]
    bounds = {method: step_bound(catalogue[method], method) for method in methods}
    for spacing in spacings or [None]:
        suffix = f"__l0_{spacing:g}" if spacing is not None else ""
        for method in methods:
            for model in catalogue[method].boundary_models:
                if models is not None and model not in models:
                    continue
                for realisation in range(realisations):
                    name = f"{method}__{model}__r{realisation}{suffix}"
                    folder = os.path.join(out, "cases", name)
                    arguments = case_arguments(method, model, realisation, folder, end_time, load_setting,
                                               overrides, spacing, bounds[method], model_options)
                    yield runner.CaseRequest(name, arguments, folder, {
                        "method": method, "boundary_model": model, "realisation": realisation,
                        "particle_spacing": spacing if spacing is not None else scene_spacing})


def window_mean(times: list[float], values: list[float], start: float, end: float) -> float:
    """The time-weighted mean over [start, end] of rows that each hold the mean since the row before:
    row k covers (t_{k-1}, t_k] and counts with its overlap with the window."""
    weighted = weight = 0.0
    for k in range(1, len(times)):
        overlap = min(times[k], end) - max(times[k - 1], start)
        if overlap > 0.0:
            weighted += values[k] * overlap
            weight += overlap
    return weighted / weight if weight > 0.0 else math.nan


def fluid_top(folder: str) -> float:
    """The top row of particle centres in the run's first frame, m."""
    with open(os.path.join(folder, "output_000000.csv"), newline="") as handle:
        return max(float(row["y"]) for row in csv.DictReader(handle) if float(row["type"]) == 0.0)


def sensor_ratios(folder: str, start: float, end: float) -> dict:
    """The case's ratios to rho |g| h, the dry sensor's mean, the worst deviation and the count within 1 %."""
    summary = run_summary(folder)
    shared = summary["shared"]
    rho_g = shared["density"] * math.hypot(*shared["gravity"])  # Pa/m
    surface = fluid_top(folder) + 0.5 * shared["particle_spacing"]  # m, the lattice's top edge
    with open(os.path.join(folder, "series.csv"), newline="") as handle:
        rows = list(csv.DictReader(handle))
    times = [float(row["time"]) for row in rows]

    def mean(name: str) -> float:
        return window_mean(times, [float(row[f"pressure_{name}"]) for row in rows], start, end)

    ratios = {column: mean(f"s{k}") / (rho_g * (surface - y))
              for k, (column, y) in enumerate(zip(RATIOS, SENSOR_HEIGHTS))}
    deviations = [abs(ratio - 1.0) for ratio in ratios.values()]
    return dict(ratios, dry=mean("dry"), worst=max(deviations),
                within_1pct=sum(deviation < TARGET for deviation in deviations))


def failure(result: runner.CaseResult) -> str:
    """A case that wrote no run.json: its exit and the binary's last error line (a bad scene key,
    say), so that the table says why."""
    line = result.last_error_line()
    return result.describe() + (f": {line}" if line else "")


def row_of(request: runner.CaseRequest, result: runner.CaseResult, window: tuple[float, float]) -> dict:
    summary = run_summary(request.folder)
    status = summary.get("status", "unknown") if summary is not None else failure(result)
    row = dict(request.extra, status=status)
    if status == "completed":
        row.update(sensor_ratios(request.folder, *window))
    return row


def method_lines(method: str, rows: list[dict], promise: str) -> list[str]:
    """The markdown of one method: a row per model and realisation, then the method's summary."""
    lines = []
    for row in rows:
        if row["status"] != "completed":
            lines.append(f"| {method} | {row['boundary_model']} | {row['realisation']} | {row['status']} | | | |")
            continue
        ratios = " | ".join(f"{row[column]:.5f}" for column in RATIOS)
        lines.append(f"| {method} | {row['boundary_model']} | {row['realisation']} | {ratios} | {row['within_1pct']} |")
    done = [row for row in rows if row["status"] == "completed"]
    values = [row[column] for row in done for column in RATIOS]
    if values:
        within = sum(row["within_1pct"] for row in done)
        lines.append(f"| **{method}** | **all** | | **{min(values):.5f}–{max(values):.5f}** | | | "
                     f"**{within} of {len(values)}** ({promise}) |")
    return lines


def expected_reading(values: list[float]) -> tuple[float, float, str]:
    """One sensor of one method and model over its realisations: the mean reading, its standard
    error (sample standard deviation / sqrt(N)) and the verdict on the 1 % target: "within" or
    "outside" when |mean - 1| is below or above 1 % by more than two standard errors, else
    "undecided" (the realisations do not tell). Two standard errors are a 95 % interval for about
    20 realisations or more (Student's t: 2.07 for 24); with fewer, t is larger (2.57 for 6, 12.7
    for 2) and a verdict is that much weaker."""
    mean = sum(values) / len(values)
    spread = math.sqrt(sum((value - mean) ** 2 for value in values) / (len(values) - 1))
    error = spread / math.sqrt(len(values))
    deviation = abs(mean - 1.0)
    verdict = ("within" if deviation + 2.0 * error < TARGET else
               "outside" if deviation - 2.0 * error > TARGET else "undecided")
    return mean, error, verdict


def one_run_within(mean: float, spread: float) -> float:
    """The probability that one run reads within 1 % of rho g h, its reading drawn from a normal
    distribution with the realisations' mean and sample standard deviation `spread`:
    Phi((1 + 1 % - mean) / spread) - Phi((1 - 1 % - mean) / spread); a deterministic reading
    (spread 0) is 1 or 0. With mean 1 it is what the noise alone leaves of the target."""
    if spread == 0.0:
        return 1.0 if abs(mean - 1.0) < TARGET else 0.0
    def cumulative(z: float) -> float:
        return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))
    return cumulative((1.0 + TARGET - mean) / spread) - cumulative((1.0 - TARGET - mean) / spread)


def expectations(rows: list[dict]) -> list[dict]:
    """Per method and model with two or more completed realisations: each sensor's expected reading
    (expected_reading) as mean_<ratio>, se_<ratio> and verdict_<ratio>; the single runs' standard
    deviation sd_<ratio>, and the probability that one run reads within 1 % (one_run_within) as
    one_run_<ratio>, and with the same spread about an exact expectation as noise_only_<ratio>."""
    grouped: dict[tuple[str, str, float], list[dict]] = {}
    for row in rows:
        if row["status"] == "completed":
            key = (row["method"], row["boundary_model"], row.get("particle_spacing", 0.0))
            grouped.setdefault(key, []).append(row)
    result = []
    for (method, model, spacing), mine in sorted(grouped.items()):
        if len(mine) < 2:
            continue
        entry = {"method": method, "boundary_model": model, "realisations": len(mine), "particle_spacing": spacing}
        for column in RATIOS:
            mean, error, verdict = expected_reading([row[column] for row in mine])
            spread = error * math.sqrt(len(mine))
            entry.update({f"mean_{column}": mean, f"se_{column}": error, f"verdict_{column}": verdict,
                          f"sd_{column}": spread, f"one_run_{column}": one_run_within(mean, spread),
                          f"noise_only_{column}": one_run_within(1.0, spread)})
        result.append(entry)
    return result


EXPECTED_COLUMNS = ["method", "boundary_model", "realisations", "particle_spacing",
                    *(f"{kind}_{column}" for column in RATIOS
                      for kind in ("mean", "se", "verdict", "sd", "one_run", "noise_only"))]


def all_within(entries: list[dict], kind: str) -> float:
    """The probability that one run of each entry reads every sensor within 1 %: the product of the
    entries' `kind` probabilities (one_run or noise_only), the sensors taken as independent."""
    return math.prod(entry[f"{kind}_{column}"] for entry in entries for column in RATIOS)


def expectation_table(entries: list[dict]) -> str:
    """The markdown of the expected readings, a line per method and model, then per method the
    sensors within, outside and undecided."""
    lines = ["", "Expected reading over the realisations (mean ± standard error) and its verdict on 1 %: "
             "within or outside by more than two standard errors, else undecided", "",
             "| method | boundary model | realisations | h = 0.225 m | 0.15 m | 0.075 m |", "|---|---|---|---|---|---|"]
    for method in sorted({entry["method"] for entry in entries}):
        mine = [entry for entry in entries if entry["method"] == method]
        for entry in mine:
            cells = " | ".join(f"{entry['mean_' + column]:.4f} ± {entry['se_' + column]:.4f} "
                               f"{entry['verdict_' + column]}" for column in RATIOS)
            lines.append(f"| {method} | {entry['boundary_model']} | {entry['realisations']} | {cells} |")
        verdicts = [entry[f"verdict_{column}"] for entry in mine for column in RATIOS]
        counts = ", ".join(f"{verdicts.count(kind)} {kind}" for kind in ("within", "outside", "undecided"))
        lines.append(f"| **{method}** | **all** | | **{counts}** | | |")
    lines += ["", "One run's chance of every sensor within 1 % (a normal draw per sensor with the realisations' "
              "mean and standard deviation; noise alone: the same spread about an exact reading):", ""]
    for method in sorted({entry["method"] for entry in entries}):
        mine = [entry for entry in entries if entry["method"] == method]
        lines.append(f"- {method}: {all_within(mine, 'one_run'):.2f} (noise alone: "
                     f"{all_within(mine, 'noise_only'):.2f}); the single runs' standard deviations "
                     f"{min(entry['sd_' + column] for entry in mine for column in RATIOS):.4f}–"
                     f"{max(entry['sd_' + column] for entry in mine for column in RATIOS):.4f}")
    return "\n".join(lines) + "\n"


SENSOR_MARKERS = {"ratio_h0225": ("o", "h = 0.225 m"), "ratio_h0150": ("s", "h = 0.15 m"),
                  "ratio_h0075": ("^", "h = 0.075 m")}
VERDICT_COLOURS = {"within": "tab:green", "outside": "tab:red", "undecided": "tab:orange"}


def plot_expectations(entries: list[dict], path: str) -> None:
    """still_water_expected.png: each sensor's expected reading per method and model, with two
    standard errors as bars, coloured by its verdict, against the 1 % band."""
    from .. import figures  # noqa: F401  (sets the shared style)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(max(6.4, 0.55 * len(entries) + 2.0), 4.8))
    ax.axhspan(1.0 - TARGET, 1.0 + TARGET, color="0.85", zorder=0, label="within 1 %")
    for slot, entry in enumerate(entries):
        for k, (column, (marker, _)) in enumerate(SENSOR_MARKERS.items()):
            colour = VERDICT_COLOURS[entry[f"verdict_{column}"]]
            ax.errorbar(slot + (k - 1) * 0.22, entry[f"mean_{column}"], yerr=2.0 * entry[f"se_{column}"],
                        marker=marker, color=colour, markersize=5, capsize=2, linestyle="none")
    ax.set_xticks(range(len(entries)))
    ax.set_xticklabels([f"{entry['method']}\n{entry['boundary_model']}" for entry in entries], rotation=90,
                       fontsize=8)
    ax.set_ylabel("mean / ρ g h (bars: ± 2 standard errors)")
    realisations = sorted({entry["realisations"] for entry in entries})
    ax.set_title(f"Still water at the wall sensors: expected readings ({'/'.join(map(str, realisations))} "
                 "realisations)")
    handles = [plt.Line2D([], [], marker=marker, color="k", linestyle="none", label=label)
               for marker, label in SENSOR_MARKERS.values()]
    handles += [plt.Line2D([], [], marker="o", color=colour, linestyle="none", label=verdict)
                for verdict, colour in VERDICT_COLOURS.items()]
    ax.legend(handles=handles, loc="lower left", ncol=2, fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def promise_text(promise: float | None, load_setting: bool) -> str:
    if not load_setting:
        return "the defaults: no promise"
    return f"promise {100 * promise:g} %" if promise is not None else "no promise declared"


def spacing_text(rows: list[dict]) -> str:
    """The particle spacings the completed cases ran at, and what h then is."""
    spacings = sorted({row["particle_spacing"] for row in rows if "particle_spacing" in row})
    if not spacings or spacings == [scene_spacing_and_step()[0]]:
        return "h = 0.225, 0.15, 0.075 m"
    return (f"l0 = {', '.join(f'{value:g}' for value in spacings)} m; h below the lattice's top edge of each run "
            "(0.225, 0.15, 0.075 m at the scene's l0 = 0.025 m; the columns keep those names)")


def table(rows: list[dict], promises: dict, window: tuple[float, float], load_setting: bool) -> str:
    lines = [f"Still water: sensor mean over [{window[0]:g}, {window[1]:g}] s / (rho g h), " + spacing_text(rows), "",
             "| method | boundary model | realisation | h = 0.225 m | 0.15 m | 0.075 m | within 1 % |",
             "|---|---|---|---|---|---|---|"]
    for method in sorted({row["method"] for row in rows}):
        mine = sorted((row for row in rows if row["method"] == method),
                      key=lambda row: (row["boundary_model"], row["realisation"]))
        lines += method_lines(method, mine, promise_text(promises.get(method), load_setting))
    return "\n".join(lines) + "\n"


def check_models(catalogue: dict, methods: list[str], models: list[str] | None, model_options: dict | None) -> None:
    """Every model `--models` or `--model-set` names is a boundary model of one of the methods run."""
    supported = sorted({model for method in methods for model in catalogue[method].boundary_models})
    for where, names in (("--models", models or []), ("--model-set", sorted(model_options or {}))):
        for model in names:
            if model not in supported:
                raise SpecError(f"{where}.{model}: not a boundary model of {', '.join(methods)} "
                                f"(they support: {', '.join(supported)})")


def still_water(out: str, binary: str, methods: list[str] | None, realisations: int, end_time: float,
                window: tuple[float, float], load_setting: bool, overrides: list[str], parallel: int,
                timeout: float = DEFAULT_TIMEOUT, spacings: list[float] | None = None,
                models: list[str] | None = None, model_options: dict | None = None) -> tuple[str, list[dict]]:
    """Run every case, write still_water.csv and still_water.md; returns the markdown and the rows."""
    catalogue = method_catalogue(binary)
    wanted = methods or sorted(catalogue)
    check_methods(wanted, sorted(catalogue), "--methods")
    check_models(catalogue, wanted, models, model_options)
    os.makedirs(out, exist_ok=True)
    rows = []
    for request, result in runner.run_cases(binary, requests(out, catalogue, wanted, realisations, end_time,
                                                             load_setting, overrides, spacings, models,
                                                             model_options),
                                            parallel=parallel, timeout=timeout,
                                            threads=runner.threads_per_case(parallel)):
        row = row_of(request, result, window)
        rows.append(row)
        print(f"{request.name}: {row['status']}" + "".join(
            f" {row[column]:.4f}" for column in RATIOS if column in row), flush=True)
    rows.sort(key=lambda row: (-row["particle_spacing"], row["method"], row["boundary_model"], row["realisation"]))
    write_csv(rows, COLUMNS, os.path.join(out, "still_water.csv"))
    promises = {name: info.still_water_promise for name, info in catalogue.items()}
    markdown = report(out, rows, promises, window, load_setting)
    with open(os.path.join(out, "still_water.md"), "w") as handle:
        handle.write(markdown)
    return markdown, rows


def report(out: str, rows: list[dict], promises: dict, window: tuple[float, float], load_setting: bool) -> str:
    """The markdown, the expected readings' CSV and figures: per spacing (coarsest first) the table
    and, with realisations, the expected readings; with two spacings or more, the resolution table
    and its figure."""
    spacings = sorted({row["particle_spacing"] for row in rows}, reverse=True)
    markdown, expected_all = "", []
    for spacing in spacings:
        mine = [row for row in rows if row["particle_spacing"] == spacing]
        suffix = f"_l0_{spacing:g}" if len(spacings) > 1 else ""
        markdown += (f"\n## l0 = {spacing:g} m\n\n" if len(spacings) > 1 else "")
        markdown += table(mine, promises, window, load_setting)
        expected = expectations(mine)
        if expected:
            expected_all += expected
            plot_expectations(expected, os.path.join(out, f"still_water_expected{suffix}.png"))
            markdown += expectation_table(expected)
    if expected_all:
        write_csv(expected_all, EXPECTED_COLUMNS, os.path.join(out, "still_water_expected.csv"))
    if len(spacings) > 1:
        markdown += resolution_table(rows, spacings, promises, load_setting)
        plot_resolution(rows, spacings, os.path.join(out, "still_water_resolution.png"))
    return markdown


def resolution_table(rows: list[dict], spacings: list[float], promises: dict, load_setting: bool) -> str:
    """Per method and spacing: the range of the completed cases' readings, how many sensors are
    within 1 %, and the cases that did not complete."""
    lines = ["", "Against the particle spacing: the readings' range, sensors within 1 % (and cases that did "
             "not complete)", "", "| method | " + " | ".join(f"l0 = {spacing:g} m" for spacing in spacings) + " | |",
             "|---|" + "---|" * (len(spacings) + 1)]
    for method in sorted({row["method"] for row in rows}):
        cells = []
        for spacing in spacings:
            mine = [row for row in rows if row["method"] == method and row["particle_spacing"] == spacing]
            done = [row for row in mine if row["status"] == "completed"]
            values = [row[column] for row in done for column in RATIOS]
            cell = (f"{min(values):.3f}–{max(values):.3f}, {sum(row['within_1pct'] for row in done)} of {len(values)}"
                    if values else "–")
            failed = len(mine) - len(done)
            cells.append(cell + (f" ({failed} not completed)" if failed else ""))
        lines.append(f"| {method} | " + " | ".join(cells) + f" | {promise_text(promises.get(method), load_setting)} |")
    return "\n".join(lines) + "\n"


def plot_resolution(rows: list[dict], spacings: list[float], path: str) -> None:
    """still_water_resolution.png: per method, each model's readings (the mean over its
    realisations) at each sensor against l0, with the 1 % band."""
    from .. import figures  # noqa: F401  (sets the shared style)
    import matplotlib.pyplot as plt

    done = [row for row in rows if row["status"] == "completed"]
    methods = sorted({row["method"] for row in done})
    fig, axes = plt.subplots(1, max(1, len(methods)), figsize=(3.0 * max(1, len(methods)) + 1.0, 4.2),
                             sharey=True, squeeze=False)
    for ax, method in zip(axes[0], methods):
        ax.axhspan(1.0 - TARGET, 1.0 + TARGET, color="0.85", zorder=0)
        models = sorted({row["boundary_model"] for row in done if row["method"] == method})
        for colour, model in zip(plt.rcParams["axes.prop_cycle"].by_key()["color"], models):
            for column, (marker, _) in SENSOR_MARKERS.items():
                points = [(spacing, [row[column] for row in done if row["method"] == method
                                     and row["boundary_model"] == model and row["particle_spacing"] == spacing])
                          for spacing in spacings]
                points = [(spacing, sum(values) / len(values)) for spacing, values in points if values]
                ax.plot([p[0] for p in points], [p[1] for p in points], marker=marker, color=colour, markersize=4,
                        linewidth=0.8, label=model if column == RATIOS[0] else None)
        ax.set_xscale("log")
        ax.invert_xaxis()  # refining from left to right
        ax.set_xticks(spacings)
        ax.set_xticklabels([f"{spacing:g}" for spacing in spacings], fontsize=7)
        ax.minorticks_off()
        ax.set_title(method)
        ax.set_xlabel("l0 (m), finer →")
        ax.legend(fontsize=6, loc="lower left")
    axes[0][0].set_ylabel("mean / ρ g h (markers: h = 0.225, 0.15, 0.075 m)")
    fig.suptitle("Still water at the wall sensors against the particle spacing (grey: within 1 %)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
