#!/usr/bin/env bash
# The spec dam break (tank 1.0 x 0.6 m, column 0.25 x 0.5 m; scenes/dambreak_fine.json) run by MPS-Basic
# at l0 = 0.005 m, dt = 1e-4 s, once per thread count. Build it first: build-mps-basic.sh. See README.md.
#
#   tools/reference-codes/case-mps-basic.sh [--end-time T] [--threads "1 2"] [--radii own|spec] [--work DIR]
#
# --end-time T   simulated seconds (default 1.0)
# --threads LIST OpenMP thread counts, one run each (default "1 2")
# --radii        own: MPS-Basic's dam-break radii (3.1 / 2.1 / 3.1 l0, default); spec: 2.1 l0 for all three
# --work DIR     build-mps-basic.sh's WORK_DIR (default build/reference-codes); cases and runs go to DIR/runs
# Prints one line per run: code, case, threads, end time, wall seconds, fluid particles, steps, particle-steps/s.
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
radii=own
work=$root/build/reference-codes
while [ $# -gt 0 ]; do
  case $1 in
    --end-time) end_time=$2; shift 2 ;;
    --threads) threads_list=$2; shift 2 ;;
    --radii) radii=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) refcodes_die "case-mps-basic.sh: unknown argument '$1' (expected --end-time, --threads, --radii, --work)" ;;
  esac
done
binary=$work/mps-basic/build/mps
template=$work/mps-basic/src/input/dambreak/settings.yml
[ -x "$binary" ] || refcodes_die "MPS-Basic not built: $binary missing (run tools/reference-codes/build-mps-basic.sh)"
[ -f "$template" ] || refcodes_die "MPS-Basic source missing: $template (run tools/reference-codes/build-mps-basic.sh)"

for threads in $threads_list; do
  run=$work/runs/mps-basic-$radii-t$threads-$end_time
  rm -rf "$run"
  mkdir -p "$run/output"
  fluid=$(/usr/bin/python3 "$here/make_case.py" mps-basic "$template" "$run" --end-time "$end_time" \
    --threads "$threads" --radii "$radii")
  start=$(refcodes_now)
  status=0
  OMP_NUM_THREADS=$threads "$binary" --setting "$run/settings.yml" --output "$run/output" \
    >"$run/stdout.log" 2>"$run/stderr.log" || status=$?
  stop=$(refcodes_now)
  if [ "$status" -ne 0 ] || ! grep -q 'END SIMULATION' "$run/stdout.log"; then
    refcodes_die "MPS-Basic run failed (exit $status): see $run/stdout.log and $run/stderr.log"
  fi
  steps=$(sed -n 's/^\([0-9][0-9]*\): dt=.*/\1/p' "$run/stdout.log" | tail -n 1)
  wall=$(awk -v a="$start" -v b="$stop" 'BEGIN { printf "%.6f", b - a }')
  refcodes_report mps-basic "dambreak-l0.005-radii-$radii" "$threads" "$end_time" "$wall" "$fluid" "$steps"
done
