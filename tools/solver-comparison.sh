#!/usr/bin/env bash
# The project's smoothed-aggregation AMG (core/linalg/amg.hpp) against hypre's BoomerAMG on the
# pressure systems of mps and isph (every method that solves one), recorded from the spec dam
# break at about 5e3, 1.2e5 and 1e6 unknowns (docs/beyond-one-machine.md).
#   tools/solver-comparison.sh                       the three sizes, 1 and 2 threads / ranks
#   SPACINGS=0.005 tools/solver-comparison.sh        other spacings (m)
# Writes docs/data/solver_comparison_1rank.json (both solvers; the project's with 1 and 2
# OpenMP threads, BoomerAMG on 1 rank) and _2ranks.json (BoomerAMG on 2 MPI ranks: Debian's
# hypre has no OpenMP). Time it on an idle machine; the script prints the load before and after.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh mps_lab_solver_bench
spacings="${SPACINGS:-0.005,0.001,0.00035211267605633805}"  # 0.05/142: 1.0e6 fluid particles
out="${OUT:-docs/data}"
mkdir -p "$out"
export OMP_PROC_BIND=true
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
build/mps_lab_solver_bench scenes/dambreak.json --spacings "$spacings" --threads 1,2 --json "$out/solver_comparison_1rank.json"
mpirun_flags=(-np 2 --bind-to core)
if [ "$(id -u)" -eq 0 ]; then mpirun_flags+=(--allow-run-as-root); fi
OMP_NUM_THREADS=1 mpirun "${mpirun_flags[@]}" build/mps_lab_solver_bench scenes/dambreak.json --spacings "$spacings" \
  --json "$out/solver_comparison_2ranks.json"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/python3 analysis/solver_comparison.py "$out/solver_comparison_1rank.json" "$out/solver_comparison_2ranks.json" \
  --out "$out/solver_comparison.md"
