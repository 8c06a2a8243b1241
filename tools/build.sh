#!/usr/bin/env bash
# Configures (Release) and builds mps_lab into build/. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/install-dependencies.sh"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build -j"$(nproc)"
