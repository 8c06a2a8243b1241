#!/usr/bin/env bash
# The spec dam break (tank 1.0 x 0.6 m, column 0.25 x 0.5 m; scenes/dambreak_fine.json) run by SPlisHSPlasH's
# DFSPH in 2-D at l0 = 0.005 m (particleRadius 0.0025), once per tolerance and thread count, headless.
# Build it first: build-splishsplash.sh. See README.md.
#
#   tools/reference-codes/case-splishsplash.sh [--end-time T] [--threads "1 2"] [--tolerances "0.1 0.01"] [--work DIR]
#
# --end-time T      simulated seconds (default 1.0)
# --threads LIST    OpenMP thread counts (default "1 2")
# --tolerances LIST DFSPH density error maxError in % (default "0.1 0.01"; the divergence error stays 0.1 %)
# --work DIR        build-splishsplash.sh's WORK_DIR (default build/reference-codes); cases and runs go to DIR/runs
# Before the measured runs of a tolerance, one unmeasured run to 0.001 s builds the wall's volume map, which
# SPlisHSPlasH caches beside the scene: the measured runs then load it as a second run of a user would.
# Prints one line per run: code, case, threads, end time, wall seconds, fluid particles, steps, particle-steps/s,
# and SPlisHSPlasH's own sum of its step timer (step_s).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tools/reference-codes/common.sh
. "$here/common.sh"
# Pinned threads, as `mps_lab bench` and side-by-side.sh: unpinned OpenMP threads slow down many-fold beside
# any other busy process on this machine class (docs/performance.md).
export OMP_PROC_BIND=${OMP_PROC_BIND:-true}

end_time=1.0
threads_list="1 2"
tolerances="0.1 0.01"
work=$root/build/reference-codes
while [ $# -gt 0 ]; do
  case $1 in
    --end-time) end_time=$2; shift 2 ;;
    --threads) threads_list=$2; shift 2 ;;
    --tolerances) tolerances=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) refcodes_die "case-splishsplash.sh: unknown argument '$1' (expected --end-time, --threads, --tolerances, --work)" ;;
  esac
done
binary=$work/splishsplash/src/bin/SPHSimulator
box=$work/splishsplash/src/data/models/UnitBox.obj
[ -x "$binary" ] || refcodes_die "SPlisHSPlasH not built: $binary missing (run tools/reference-codes/build-splishsplash.sh)"
[ -f "$box" ] || refcodes_die "SPlisHSPlasH source missing: $box (run tools/reference-codes/build-splishsplash.sh)"

# run_once SCENE_DIR THREADS STOP_AT OUT_DIR: one headless run; its exit status.
run_once() {
  rm -rf "$4"
  mkdir -p "$4"
  OMP_NUM_THREADS=$2 "$binary" --no-gui --no-initial-pause --stopAt "$3" --output-dir "$4" "$1/scene.json" \
    >"$4/stdout.log" 2>"$4/stderr.log"
}

for tolerance in $tolerances; do
  scene_dir=$work/runs/splishsplash-case-tol$tolerance
  mkdir -p "$scene_dir"
  fluid=$(/usr/bin/python3 "$here/make_case.py" splishsplash "$box" "$scene_dir" --end-time "$end_time" \
    --tolerance "$tolerance")
  run_once "$scene_dir" 1 0.001 "$scene_dir/warm-up" ||
    refcodes_die "SPlisHSPlasH warm-up run failed: see $scene_dir/warm-up/stdout.log and stderr.log"
  for threads in $threads_list; do
    run=$work/runs/splishsplash-tol$tolerance-t$threads-$end_time
    start=$(refcodes_now)
    status=0
    run_once "$scene_dir" "$threads" "$end_time" "$run" || status=$?
    stop=$(refcodes_now)
    [ "$status" -eq 0 ] || refcodes_die "SPlisHSPlasH run failed (exit $status): see $run/stdout.log and stderr.log"
    # Its timer "SimStep" wraps every step: steps = time sum / average time.
    read -r steps step_ms < <(awk '/Average time: SimStep:/ { avg = $(NF - 1) } /Time sum: SimStep:/ { sum = $(NF - 1) }
      END { if (avg > 0) printf "%d %.3f\n", sum / avg + 0.5, sum; else print "0 0" }' "$run/stdout.log")
    [ "$steps" -gt 0 ] || refcodes_die "SPlisHSPlasH printed no step timing: see $run/stdout.log"
    wall=$(awk -v a="$start" -v b="$stop" 'BEGIN { printf "%.6f", b - a }')
    refcodes_report splishsplash "dambreak-l0.005-dfsph-tol$tolerance%" "$threads" "$end_time" "$wall" "$fluid" \
      "$steps" "step_s=$(awk -v ms="$step_ms" 'BEGIN { printf "%.3f", ms / 1000 }')"
  done
done
