#!/usr/bin/env bash
# The main job: install what is missing, build the mps_lab binary (only it: the tests are built
# by tools/test.sh), run every method on the specification's dam break, and write the comparison
# (summary.csv, figures, report.md) into runs/dambreak/. Prints how long each stage took.
set -euo pipefail
cd "$(dirname "$0")/.."
stage_start=$SECONDS
stage() {  # stage NAME: the time since the last stage
  printf 'mps_lab: %-40s %4d s\n' "$1" $((SECONDS - stage_start)) >&2
  stage_start=$SECONDS
}
tools/install-dependencies.sh
stage "packages (apt)"
tools/build.sh mps_lab
stage "configure and build of build/mps_lab"
build/mps_lab compare scenes/dambreak.json --out runs/dambreak
stage "runs, figures and report"
echo "mps_lab: the comparison report is runs/dambreak/report.md (one run folder per method beside it)"
