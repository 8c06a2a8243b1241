#!/usr/bin/env bash
# The main job: install what is missing, build, run the specification's dam break with MPS
# and plot it against Martin & Moyce (1952).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
build/mps_lab run --method=mps scenes/dambreak.json --out runs/dambreak/mps
/usr/bin/python3 analysis/plot_run.py runs/dambreak/mps
echo "mps_lab: frames, series.csv, run.json and front.png are in runs/dambreak/mps/"
