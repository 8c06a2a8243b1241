#!/usr/bin/env bash
# Threads that never hurt, at the small end of the scaling (docs/performance.md): the spec dam
# break from rest at l0 = 0.05/5, 0.05/9 and 0.05/16 m (1,176, 3,916 and 12,561 fluid
# particles), 400 steps of 0.02 s/m x l0 (dfsph: its CFL rule), with 1 thread, 2 threads and the
# measured team (--threads 0, the default), each size and method twice. Prints ns per fluid
# particle-step of the whole run (set-up included; no frames, no series rows) and the steps each
# team ran. Run it on an otherwise idle machine.
#   tools/bench-governor-sizes.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh mps_lab >/dev/null
out="${1:-$(mktemp -d)}"
mkdir -p "$out"
export OMP_PROC_BIND=true
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for rep in 1 2; do
  for k in 5 9 16; do
    l0=$(/usr/bin/python3 -c "print(0.05 / $k)")
    dt=$(/usr/bin/python3 -c "print(0.02 * $l0)")
    end_time=$(/usr/bin/python3 -c "print(400 * 0.02 * $l0)")
    for method in mps isph dfsph; do
      line="round $rep $method l0=0.05/$k"
      for threads in 1 2 0; do
        run="$out/$method-$k-$threads"
        rm -rf "$run"
        build/mps_lab run scenes/dambreak.json --method "$method" --threads "$threads" --end-time "$end_time" \
          --quiet --out "$run" --set particle_spacing="$l0" --set time.time_step="$dt" \
          --set output.frame_every_steps=1000000 --set output.series_every_steps=1000000 >/dev/null 2>&1 || true
        line="$line threads=$threads:$(/usr/bin/python3 -c "
import json, sys
r = json.load(open(sys.argv[1] + '/run.json'))
fluid, steps = r['particles']['fluid'], r['steps']
print(f\"{1e9 * r['wall_seconds'] / (fluid * steps):.0f}ns,fluid={fluid},steps={steps},{r['status']},teams={r['threads_used']['steps_by_team']}\".replace(' ', ''))" "$run")"
      done
      echo "$line"
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
