#!/usr/bin/env bash
# The whole test suite: install what is missing, build, run every test (CTest, 2 jobs).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
