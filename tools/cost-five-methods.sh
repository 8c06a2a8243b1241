#!/bin/sh
# Cost per simulated second of every registered method, side by side, for docs/data/cost_per_method.{csv,md}
# (docs/speed-vs-accuracy.md, "Cost per simulated second"). Run it on an otherwise idle machine:
#
#   tools/cost-five-methods.sh                 # build/mps_lab, 3 repetitions, writes docs/data/
#   tools/cost-five-methods.sh --repetitions 1 --out /tmp/cost   # any option of analysis/cost_per_method.py
#
# Every method at its defaults on scenes/dambreak.json to 0.5 s at l0 = 0.025, 0.0125 and
# 0.00625 m, one thread (OMP_PROC_BIND=true), the method order rotated per repetition, the
# median kept (analysis/mps_lab/studies/cost.py). Writes docs/data/cost_per_method.{csv,md}.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-/usr/bin/python3}
exec "$python" "$here/analysis/cost_per_method.py" --out "${COST_OUT:-$here/runs/cost_per_method}" --reference mps --docs "$@"
