#!/usr/bin/env bash
# The main job: install what is missing, build, run every method on the specification's dam
# break, and write the comparison (summary.csv, figures, report.md) into runs/dambreak/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
build/mps_lab compare scenes/dambreak.json --out runs/dambreak
echo "mps_lab: the comparison report is runs/dambreak/report.md (one run folder per method beside it)"
