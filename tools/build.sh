#!/usr/bin/env bash
# Configures (Release) and builds mps_lab into build/. Safe to run again.
#   tools/build.sh              everything: the mps_lab binary and the test suite
#   tools/build.sh mps_lab      only the named targets (the main job needs only mps_lab)
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-dependencies.sh"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 "${launcher[@]}" >/dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build build -j"$(nproc)" "${targets[@]}"
