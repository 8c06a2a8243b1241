#!/usr/bin/env bash
# The whole test suite: install what is missing, build, run every test (CTest, 2 jobs).
#   tools/test.sh [ctest arguments]               Release build in build/ (README, CI)
#   tools/test.sh --sanitize [ctest arguments]    AddressSanitizer + UndefinedBehaviorSanitizer
#                                                 build in build-sanitize/ (DEVELOPERS.md)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  shift
  tools/install-dependencies.sh
  cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMPS_LAB_SANITIZE=ON \
        -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
  cmake --build build-sanitize -j"$(nproc)"
  # Stop at the first finding with a stack trace; leaks are findings too. The binary that
  # the CLI tests start inherits these.
  export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  exec ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" "$@"
fi
tools/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
