#!/usr/bin/env bash
# Builds MPS-Basic's `mps` (Release, OpenMP) from a git repository already on this machine; downloads
# nothing. See README.md beside this file.
#
#   tools/reference-codes/build-mps-basic.sh [SOURCE_REPO] [WORK_DIR]
#
# SOURCE_REPO: a clone or bare mirror of github.com/MPS-Basic/MPS-Basic
#              (default /work/.mirror/MPS-Basic+MPS-Basic/repo)
# WORK_DIR:    where the sources are unpacked and built (default build/reference-codes)
# Environment: MPS_BASIC_COMMIT (default 334886f); ARGPARSE_REPO, a clone or mirror of
#              github.com/p-ranav/argparse (default /work/.mirror/p-ranav+argparse/repo) and ARGPARSE_COMMIT
#              (default v3.0, MPS-Basic's pin); REFCODES_JOBS (2).
# Its other FetchContent dependencies come from Debian packages (tools/install-dependencies.sh
# --reference-codes): Eigen 3.4 (it pins 5.0.0), yaml-cpp 0.7, fast-cpp-csv-parser (libfccp-dev), GoogleTest.
# Prints the path of the `mps` executable on its last line.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tools/reference-codes/common.sh
. "$here/common.sh"

source_repo=${1:-/work/.mirror/MPS-Basic+MPS-Basic/repo}
work=${2:-$root/build/reference-codes}
commit=${MPS_BASIC_COMMIT:-334886f}
argparse_repo=${ARGPARSE_REPO:-/work/.mirror/p-ranav+argparse/repo}
argparse_commit=${ARGPARSE_COMMIT:-v3.0}

refcodes_need_repo "$source_repo" MPS-Basic
refcodes_need_commit "$source_repo" "$commit" MPS-Basic
refcodes_need_repo "$argparse_repo" argparse
refcodes_need_commit "$argparse_repo" "$argparse_commit" argparse
[ -f /usr/include/eigen3/Eigen/Dense ] || refcodes_die "Eigen headers missing: tools/install-dependencies.sh --reference-codes"
[ -f /usr/include/yaml-cpp/yaml.h ] || refcodes_die "yaml-cpp missing: tools/install-dependencies.sh --reference-codes"
[ -f /usr/include/libfccp/csv.h ] || refcodes_die "fast-cpp-csv-parser (libfccp-dev) missing: tools/install-dependencies.sh --reference-codes"
[ -f /usr/src/googletest/CMakeLists.txt ] || refcodes_die "GoogleTest sources missing (package googletest): tools/install-dependencies.sh --reference-codes"

base=$work/mps-basic
src=$base/src
echo "reference-codes: unpacking MPS-Basic $commit into $src" >&2
refcodes_export_tree "$source_repo" "$commit" "$src"
refcodes_export_tree "$argparse_repo" "$argparse_commit" "$base/deps/argparse"
{
  echo "MPS-Basic $(cat "$src/.refcodes-commit")"
  echo "argparse $(cat "$base/deps/argparse/.refcodes-commit")"
} >"$base/versions.txt"

# yaml-cpp 0.7 (Debian) exports the target `yaml-cpp`; MPS-Basic links `yaml-cpp::yaml-cpp` (0.8's name).
# This stub, given to FetchContent as yaml-cpp's source directory, finds the installed library under that name.
mkdir -p "$base/deps/yaml-cpp"
cat >"$base/deps/yaml-cpp/CMakeLists.txt" <<'CMAKE'
find_package(yaml-cpp REQUIRED)
if(NOT TARGET yaml-cpp::yaml-cpp)
  add_library(yaml-cpp::yaml-cpp INTERFACE IMPORTED GLOBAL)
  target_link_libraries(yaml-cpp::yaml-cpp INTERFACE yaml-cpp)
endif()
CMAKE

# MPS-Basic asks for OpenMP >= 5.0; g++ 12 reports 4.5 (_OPENMP 201511) although it compiles all MPS-Basic
# uses (15 plain `#pragma omp parallel for`): without this edit it builds single-threaded.
sed -i 's/find_package(OpenMP 5.0)/find_package(OpenMP REQUIRED)/' "$src/CMakeLists.txt"
grep -q 'find_package(OpenMP REQUIRED)' "$src/CMakeLists.txt" ||
  refcodes_die "MPS-Basic: no 'find_package(OpenMP 5.0)' line to relax in $src/CMakeLists.txt"

echo "reference-codes: configuring MPS-Basic (Release, OpenMP)" >&2
cmake -S "$src" -B "$base/build" -DCMAKE_BUILD_TYPE=Release -DFETCHCONTENT_FULLY_DISCONNECTED=ON \
  -DFETCHCONTENT_SOURCE_DIR_EIGEN=/usr/include/eigen3 \
  -DFETCHCONTENT_SOURCE_DIR_GOOGLETEST=/usr/src/googletest \
  -DFETCHCONTENT_SOURCE_DIR_YAML-CPP="$base/deps/yaml-cpp" \
  -DFETCHCONTENT_SOURCE_DIR_FAST-CPP-CSV-PARSER=/usr/include/libfccp \
  -DFETCHCONTENT_SOURCE_DIR_ARGPARSE="$base/deps/argparse" >"$base/configure.log" 2>&1 ||
  refcodes_die "MPS-Basic configure failed (see $base/configure.log)"
grep -q 'OpenMP not found' "$base/configure.log" && refcodes_die "MPS-Basic found no OpenMP (see $base/configure.log)"
echo "reference-codes: building mps (-j$(refcodes_jobs), nice 19; log $base/build.log)" >&2
nice -n 19 cmake --build "$base/build" --target mps -j"$(refcodes_jobs)" >"$base/build.log" 2>&1 ||
  refcodes_die "MPS-Basic build failed (see the end of $base/build.log)"
binary=$base/build/mps
[ -x "$binary" ] || refcodes_die "MPS-Basic built but $binary is missing"
echo "$binary"
