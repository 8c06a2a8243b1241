#!/usr/bin/env bash
# Threads that never hurt (docs/performance.md): every method on the spec dam break, alone and
# beside one CPU-bound process, with one thread, two threads and the measured choice (the
# default, core/run/thread_governor.hpp). Prints seconds and the ratio to "alone, 1 thread".
#   tools/bench-shared-machine.sh [end time in s, default 0.5]
# Run it on an otherwise idle machine; it prints the load before and after.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh mps_lab >/dev/null
end_time="${1:-0.5}"
out="$(mktemp -d)"
trap 'rm -rf "$out"; [ -n "${busy:-}" ] && kill "$busy" 2>/dev/null || true' EXIT
export OMP_PROC_BIND=true
seconds() {  # method, threads (0: measured), label
  local json="$out/$1-$2-$3"
  build/mps_lab run scenes/dambreak.json --method "$1" --threads "$2" --end-time "$end_time" --out "$json" --quiet
  /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]+'/run.json'))['wall_seconds'])" "$json"
}
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf "%-8s %-28s %9s %9s\n" method case seconds ratio
for method in $(build/mps_lab methods | awk '{print $1}'); do
  alone1=$(seconds "$method" 1 alone)
  printf "%-8s %-28s %9.2f %9.2f\n" "$method" "alone, 1 thread" "$alone1" 1
  for threads in 2 0; do
    t=$(seconds "$method" "$threads" alone)
    printf "%-8s %-28s %9.2f %9.2f\n" "$method" "alone, $([ "$threads" = 0 ] && echo measured || echo "$threads threads")" "$t" \
      "$(/usr/bin/python3 -c "print($t/$alone1)")"
  done
  /usr/bin/python3 -c 'while True: pass' &
  busy=$!
  for threads in 1 2 0; do
    t=$(seconds "$method" "$threads" busy)
    printf "%-8s %-28s %9.2f %9.2f\n" "$method" "beside busy, $([ "$threads" = 0 ] && echo measured || echo "$threads thread(s)")" \
      "$t" "$(/usr/bin/python3 -c "print($t/$alone1)")"
  done
  kill "$busy"; wait "$busy" 2>/dev/null || true; busy=""
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
