#!/usr/bin/python3
"""Tables of tools/reference-codes/side-by-side.sh: every run in OUT_DIR/reference_codes.csv, the medians and
ratios in OUT_DIR/reference_codes.md.

  side_by_side_table.py LINES OUT_DIR --load-before TEXT --load-after TEXT [--radii own|spec]

LINES holds one line per run, key=value pairs (side-by-side.sh's and the case scripts' result lines).
Ratio per particle-step: median particle-steps/s of mps_lab over that of the reference code. Ratio per
simulated second: median wall time of the reference over that of mps_lab (the same end time). Paired: the
same ratio per particle-step within each repetition (its two runs back to back, so under the same load), as
min–max over the repetitions with the share of repetitions that reach the target: on a shared machine the
medians can pass a target that single pairs miss.
"""
import argparse
import csv
import pathlib
import statistics

COLUMNS = ["repetition", "pair", "code", "case", "threads", "end_time", "wall_s", "particles", "steps",
           "particle_steps_per_s", "step_s", "load1"]
# The targets of issue 17 (item 3): pair -> (reference name, minimum ratio, ratios the target applies to).
TARGETS = {
    "mps": ("MPS-Basic", 10.0, ("per particle-step",)),
    "dfsph-0.1": ("SPlisHSPlasH DFSPH, 0.1 %", 2.0, ("per particle-step", "per simulated second")),
    "dfsph-0.01": ("SPlisHSPlasH DFSPH, 0.01 %", 2.0, ("per particle-step", "per simulated second")),
}


def read_runs(path):
    runs = []
    for line in pathlib.Path(path).read_text().splitlines():
        fields = dict(token.split("=", 1) for token in line.split() if "=" in token)
        if fields:
            runs.append(fields)
    return runs


def write_csv(runs, path):
    with open(path, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for run in runs:
            writer.writerow({key: run.get(key, "") for key in COLUMNS})


def spread(values, digits):
    """Median with min-max of the repetitions, e.g. '12.3 (12.1-12.9)'."""
    fmt = "%%.%df" % digits
    if len(values) == 1:
        return fmt % values[0]
    return (fmt + " (" + fmt + "–" + fmt + ")") % (statistics.median(values), min(values), max(values))


def paired_ratios(name, runs):
    """Per repetition: ours over the reference's particle-steps/s, the two runs of that repetition."""
    ratios = []
    for repetition in sorted({r["repetition"] for r in runs if r["pair"] == name}, key=int):
        both = [r for r in runs if r["pair"] == name and r["repetition"] == repetition]
        ref = [float(r["particle_steps_per_s"]) for r in both if r["code"] != "mps_lab"]
        ours = [float(r["particle_steps_per_s"]) for r in both if r["code"] == "mps_lab"]
        if ref and ours:
            ratios.append(ours[0] / ref[0])
    return ratios


def pair_row(name, runs):
    ref = [r for r in runs if r["pair"] == name and r["code"] != "mps_lab"]
    ours = [r for r in runs if r["pair"] == name and r["code"] == "mps_lab"]
    if not ref or not ours:
        return None
    wall_ref = [float(r["wall_s"]) for r in ref]
    wall_ours = [float(r["wall_s"]) for r in ours]
    pss_ref = [float(r["particle_steps_per_s"]) / 1e6 for r in ref]
    pss_ours = [float(r["particle_steps_per_s"]) / 1e6 for r in ours]
    per_step = statistics.median(pss_ours) / statistics.median(pss_ref)
    per_second = statistics.median(wall_ref) / statistics.median(wall_ours)
    reference, minimum, applies = TARGETS[name]
    ratios = {"per particle-step": per_step, "per simulated second": per_second}
    met = all(ratios[key] >= minimum for key in applies)
    target = "≥ %g× %s: %s" % (minimum, " and ".join(applies), "met" if met else "missed")
    paired = paired_ratios(name, runs)
    paired_text = "%.2f–%.2f× (%d of %d ≥ %g×)" % (min(paired), max(paired), sum(x >= minimum for x in paired),
                                                  len(paired), minimum) if paired else "–"
    return "| %s | %s | %s | %s | %s / %s | %s / %s | %s | %s | %s | %s | **%.2f×** | %s | **%.2f×** | %s |" % (
        name, reference, ref[0]["threads"], ref[0]["end_time"], ref[0]["particles"], ours[0]["particles"],
        ref[0]["steps"], ours[0]["steps"], spread(wall_ref, 2), spread(wall_ours, 2), spread(pss_ref, 3),
        spread(pss_ours, 3), per_step, paired_text, per_second, target)


def write_markdown(runs, path, args):
    repetitions = len({r["repetition"] for r in runs})
    lines = [
        "<!-- written by tools/reference-codes/side-by-side.sh; do not edit by hand -->",
        "",
        "Side by side, %d repetition%s (medians, min–max in brackets), `OMP_PROC_BIND=true`; MPS-Basic with %s radii."
        % (repetitions, "" if repetitions == 1 else "s",
           "its own dam-break (3.1 / 2.1 / 3.1 l0)" if args.radii == "own" else "the spec's (2.1 l0)"),
        "",
        "- load before: `%s`" % args.load_before.strip(),
        "- load after: `%s`" % args.load_after.strip(),
        "",
        "| pair | reference | threads | end time [s] | fluid (ref / ours) | steps (ref / ours) | wall ref [s] "
        "| wall ours [s] | ref [M particle-steps/s] | ours [M particle-steps/s] | ratio per particle-step "
        "| paired per particle-step | ratio per simulated second | target |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in TARGETS:
        row = pair_row(name, runs)
        if row:
            lines.append(row)
    lines.append("")
    pathlib.Path(path).write_text("\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("lines")
    parser.add_argument("out_dir")
    parser.add_argument("--load-before", default="")
    parser.add_argument("--load-after", default="")
    parser.add_argument("--radii", choices=["own", "spec"], default="own")
    args = parser.parse_args()
    runs = read_runs(args.lines)
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(runs, out / "reference_codes.csv")
    write_markdown(runs, out / "reference_codes.md", args)
    print((out / "reference_codes.md").read_text())


if __name__ == "__main__":
    main()
