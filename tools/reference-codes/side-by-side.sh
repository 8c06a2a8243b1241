#!/usr/bin/env bash
# The speed targets of issue 17 measured side by side in one sitting: each reference run and the same case run
# by mps_lab (same scene, end time and threads) back to back, repeated, the order flipped every repetition.
# Run it on an otherwise idle machine, after build-mps-basic.sh, build-splishsplash.sh and the mps_lab build.
#
#   tools/reference-codes/side-by-side.sh OUT_DIR [--repetitions 3] [--threads 2] [--mps-end-time 0.3]
#                                          [--dfsph-end-time 1.0] [--work DIR] [--mps-lab PATH] [--radii own|spec]
#                                          [--pairs "mps dfsph-0.1 dfsph-0.01"]
#
# Pairs: mps against MPS-Basic (dt 1e-4 s, to --mps-end-time), dfsph against SPlisHSPlasH's DFSPH at a density
# tolerance of 0.1 % and of 0.01 % (to --dfsph-end-time), all at l0 = 0.005 (scenes/dambreak_fine.json).
# The defaults take about 9 minutes on the 2-core machine class (MPS-Basic's ~40 ms steps dominate: 3 x 3000
# of them; the dam break's front reaches the right wall at about 0.27 s, so 0.3 s includes the impact), and
# stay under 12 minutes with a third of margin.
# Writes OUT_DIR/reference_codes.csv (every run) and OUT_DIR/reference_codes.md (medians, ratios, the load
# before and after); the runs' own files go to WORK/runs/side-by-side. OMP_PROC_BIND=true for every run.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tools/reference-codes/common.sh
. "$here/common.sh"

if [ $# -lt 1 ] || [ "${1#--}" != "$1" ]; then
  refcodes_die "side-by-side.sh: first argument: the output directory (e.g. docs/data)"
fi
out=$1
shift
repetitions=3
threads=2
mps_end_time=0.3
dfsph_end_time=1.0
work=$root/build/reference-codes
mps_lab=$root/build/mps_lab
radii=own
pairs="mps dfsph-0.1 dfsph-0.01"
while [ $# -gt 0 ]; do
  case $1 in
    --repetitions) repetitions=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --mps-end-time) mps_end_time=$2; shift 2 ;;
    --dfsph-end-time) dfsph_end_time=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --mps-lab) mps_lab=$2; shift 2 ;;
    --radii) radii=$2; shift 2 ;;
    --pairs) pairs=$2; shift 2 ;;
    *) refcodes_die "side-by-side.sh: unknown argument '$1'" ;;
  esac
done
[ -x "$mps_lab" ] || refcodes_die "mps_lab not built: $mps_lab missing (tools/build.sh, or --mps-lab PATH)"
scene=$root/scenes/dambreak_fine.json
export OMP_PROC_BIND=true
mkdir -p "$out"
runs=$work/runs/side-by-side
rm -rf "$runs"
mkdir -p "$runs"
lines=$runs/lines.txt

# ours METHOD TOLERANCE END_TIME LABEL: one mps_lab run of the case, its result line.
ours() {
  local dir=$runs/ours-$4
  rm -rf "$dir"
  local settings=()
  [ "$2" = "-" ] || settings=(--set "methods.dfsph.density_tolerance=$2")
  local start stop
  start=$(refcodes_now)
  "$mps_lab" run "$scene" --method "$1" --end-time "$3" --threads "$threads" -q -o "$dir" "${settings[@]}" \
    >"$runs/ours-$4.log" 2>&1 || refcodes_die "mps_lab run failed: see $runs/ours-$4.log"
  stop=$(refcodes_now)
  read -r fluid steps < <(/usr/bin/python3 -c 'import json, sys
run = json.load(open(sys.argv[1]))
print(run["particles"]["fluid"], run["steps"])' "$dir/run.json")
  refcodes_report mps_lab "$4" "$threads" "$3" "$(awk -v a="$start" -v b="$stop" 'BEGIN { printf "%.6f", b - a }')" \
    "$fluid" "$steps"
}

# pair NAME REPETITION: the reference run and ours of one pair, in the order of the repetition.
pair() {
  local name=$1 rep=$2 ref_cmd ours_cmd
  case $name in
    mps)
      ref_cmd=("$here/case-mps-basic.sh" --end-time "$mps_end_time" --threads "$threads" --radii "$radii" --work "$work")
      ours_cmd=(ours mps - "$mps_end_time" mps) ;;
    dfsph-0.1)
      ref_cmd=("$here/case-splishsplash.sh" --end-time "$dfsph_end_time" --threads "$threads" --tolerances 0.1 --work "$work")
      ours_cmd=(ours dfsph 1e-3 "$dfsph_end_time" dfsph-0.1) ;;
    dfsph-0.01)
      ref_cmd=("$here/case-splishsplash.sh" --end-time "$dfsph_end_time" --threads "$threads" --tolerances 0.01 --work "$work")
      ours_cmd=(ours dfsph 1e-4 "$dfsph_end_time" dfsph-0.01) ;;
    *) refcodes_die "side-by-side.sh: unknown pair '$name' (expected mps, dfsph-0.1, dfsph-0.01)" ;;
  esac
  local order=(ref ours)
  if [ $((rep % 2)) -eq 0 ]; then order=(ours ref); fi
  for side in "${order[@]}"; do
    local load line
    load=$(awk '{ print $1 }' /proc/loadavg)
    if [ "$side" = ref ]; then line=$("${ref_cmd[@]}"); else line=$("${ours_cmd[@]}"); fi
    echo "repetition=$rep pair=$name load1=$load $line" | tee -a "$lines"
  done
}

load_before=$(uptime)
echo "side-by-side: load before: $load_before" >&2
for rep in $(seq 1 "$repetitions"); do
  for name in $pairs; do
    pair "$name" "$rep"
  done
done
load_after=$(uptime)
echo "side-by-side: load after: $load_after" >&2
/usr/bin/python3 "$here/side_by_side_table.py" "$lines" "$out" --load-before "$load_before" --load-after "$load_after" \
  --radii "$radii"
