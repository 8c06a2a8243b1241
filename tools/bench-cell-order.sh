#!/usr/bin/env bash
# Cell-ordered particles (docs/performance.md): neighbour search and solve time per step of mps,
# isph and dfsph on the spec dam break at l0 = 0.005 m (scenes/dambreak_fine.json), with the
# particles never reordered (run.sort_period = 0) and reordered every 10, 50 and 200 steps.
# The four runs of a method are interleaved, round after round, so that they share the load;
# the table gives each run's per-step times and their ratio to the unsorted run of the same
# round (the median over the rounds). Prints the load before and after.
#   tools/bench-cell-order.sh [end time in s, default 1.0] [rounds, default 1] [threads, default 1]
#   METHODS="mps dfsph" PERIODS="0 25 100" tools/bench-cell-order.sh 0.5
#   SKIP_BUILD=1 MPS_LAB=/path/to/mps_lab tools/bench-cell-order.sh   (another binary, not rebuilt)
#   EXTRA_SETS="--set stability.max_escaped_fraction=0.2" ...            (more settings for every run)
# A run that the stability monitor stops is reported and its steps are still measured (the
# table's "t end" column says how far it came).
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${SKIP_BUILD:-0}" = 1 ] || tools/build.sh mps_lab >/dev/null  # SKIP_BUILD=1: use build/mps_lab as it is
end_time="${1:-1.0}"
rounds="${2:-1}"
threads="${3:-1}"
methods="${METHODS:-mps isph dfsph}"
periods="${PERIODS:-0 10 50 200}"
binary="${MPS_LAB:-build/mps_lab}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export OMP_PROC_BIND=true
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg); end time $end_time s, $rounds round(s), $threads thread(s)"
for method in $methods; do
  for round in $(seq "$rounds"); do
    for period in $periods; do
      "$binary" run scenes/dambreak_fine.json --method "$method" --threads "$threads" --end-time "$end_time" \
        --set "run.sort_period=$period" ${EXTRA_SETS:-} --out "$out/$method-$period-$round" --quiet ||
        echo "($method, period $period, round $round: not completed, exit $?; its steps are still measured)"
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/python3 - "$out" "$rounds" "$methods" "$periods" <<'PY'
import json, statistics, sys
out, rounds, methods, periods = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4].split()
def per_step(run):  # ms per step: search, solve (every *_solve phase), the sort, the whole step
    profile = json.load(open(run + "/run.json"))["profile"]
    phases, steps = profile["phases"], profile["steps"]
    ms = lambda names: 1e3 * sum(phases[n]["seconds"] for n in names if n in phases) / steps
    solve = [n for n in phases if n.endswith("_solve")]
    end = json.load(open(run + "/run.json")).get("simulated_time", 0.0)
    return {"search": ms(["neighbour_search"]), "solve": ms(solve), "sort": ms(["cell_order"]),
            "step": 1e3 * profile["wall_seconds"] / steps, "end": end}
print(f"{'method':8} {'period':>6} {'t end s':>7} {'search ms':>10} {'solve ms':>9} {'sort ms':>8} {'step ms':>8}"
      f" {'search/off':>10} {'solve/off':>9} {'step/off':>8}")
for method in methods:
    runs = {p: [per_step(f"{out}/{method}-{p}-{r}") for r in range(1, rounds + 1)] for p in periods}
    for p in periods:
        med = lambda key: statistics.median(run[key] for run in runs[p])
        ratio = lambda key: statistics.median(a[key] / b[key] for a, b in zip(runs[p], runs[periods[0]]))
        print(f"{method:8} {p:>6} {med('end'):7.3f} {med('search'):10.3f} {med('solve'):9.3f} {med('sort'):8.4f} {med('step'):8.3f}"
              f" {ratio('search'):10.3f} {ratio('solve'):9.3f} {ratio('step'):8.3f}")
PY
