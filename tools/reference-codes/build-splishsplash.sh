#!/usr/bin/env bash
# Builds SPlisHSPlasH's SPHSimulator (Release, single precision with AVX, OpenMP, no Python bindings)
# from a git repository already on this machine; downloads nothing. See README.md beside this file.
#
#   tools/reference-codes/build-splishsplash.sh [SOURCE_REPO] [WORK_DIR]
#
# SOURCE_REPO: a clone or bare mirror of github.com/InteractiveComputerGraphics/SPlisHSPlasH
#              (default /work/.mirror/InteractiveComputerGraphics+SPlisHSPlasH/repo)
# WORK_DIR:    where the sources are unpacked and built (default build/reference-codes)
# Environment: SPLISHSPLASH_COMMIT (default 80b7284, 2025-08-12: the newest commit whose four pinned projects are all
#              in the mirrors; the newest, c5a063d, pins a CompactNSearch commit they lack and its `reset()` call
#              does not compile against CompactNSearch's HEAD 99fa1fe), and the repositories of the four projects its CMake
#              fetches with ExternalProject: DISCREGRID_REPO, GENERICPARAMETERS_REPO, PBD_REPO,
#              COMPACTNSEARCH_REPO (default: the mirrors beside SOURCE_REPO); COMPACTNSEARCH_COMMIT, used
#              when the pinned commit is not in COMPACTNSEARCH_REPO (default: its HEAD); REFCODES_JOBS (2).
# Prints the path of SPHSimulator on its last line.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tools/reference-codes/common.sh
. "$here/common.sh"

source_repo=${1:-/work/.mirror/InteractiveComputerGraphics+SPlisHSPlasH/repo}
work=${2:-$root/build/reference-codes}
commit=${SPLISHSPLASH_COMMIT:-80b7284}
mirrors=$(dirname "$(dirname "$source_repo")")
discregrid_repo=${DISCREGRID_REPO:-$mirrors/InteractiveComputerGraphics+Discregrid/repo}
genericparameters_repo=${GENERICPARAMETERS_REPO:-$mirrors/InteractiveComputerGraphics+GenericParameters/repo}
pbd_repo=${PBD_REPO:-$mirrors/InteractiveComputerGraphics+PositionBasedDynamics/repo}
compactnsearch_repo=${COMPACTNSEARCH_REPO:-$mirrors/InteractiveComputerGraphics+CompactNSearch/repo}

refcodes_need_repo "$source_repo" SPlisHSPlasH
refcodes_need_commit "$source_repo" "$commit" SPlisHSPlasH
refcodes_need_repo "$discregrid_repo" Discregrid
refcodes_need_repo "$genericparameters_repo" GenericParameters
refcodes_need_repo "$pbd_repo" PositionBasedDynamics
refcodes_need_repo "$compactnsearch_repo" CompactNSearch

base=$work/splishsplash
src=$base/src
echo "reference-codes: unpacking SPlisHSPlasH $commit into $src" >&2
refcodes_export_tree "$source_repo" "$commit" "$src"

# The commit SPlisHSPlasH pins for NAME (the GIT_TAG after its GIT_REPOSITORY line).
pinned_commit() {
  grep -h -A1 "GIT_REPOSITORY https://github.com/InteractiveComputerGraphics/$1.git" \
    "$src/CMake/SetUpExternalProjects.cmake" "$src/CMake/NeighborhoodSearch.cmake" |
    sed -n 's/.*GIT_TAG *"\([0-9a-f]*\)".*/\1/p' | head -n 1
}

# Unpack NAME at its pinned commit (or FALLBACK when the repository lacks it) and point the
# ExternalProject at that directory: GIT_REPOSITORY + GIT_TAG become SOURCE_DIR.
use_local_project() {
  local name=$1 repo=$2 fallback=${3:-}
  local pin
  pin=$(pinned_commit "$name")
  [ -n "$pin" ] || refcodes_die "no pinned commit of $name found in $src/CMake"
  local use=$pin
  if ! git -C "$repo" cat-file -e "$pin^{commit}" 2>/dev/null; then
    [ -n "$fallback" ] || refcodes_die "$name: pinned commit $pin is not in '$repo'"
    use=$(git -C "$repo" rev-parse "$fallback^{commit}")
    echo "reference-codes: $name: pinned commit $pin is not in '$repo'; using $use instead (may not compile)" >&2
  fi
  refcodes_export_tree "$repo" "$use" "$base/extern-src/$name"
  local file
  for file in "$src/CMake/SetUpExternalProjects.cmake" "$src/CMake/NeighborhoodSearch.cmake"; do
    awk -v name="$name" -v dir="$base/extern-src/$name" '
      index($0, "GIT_REPOSITORY https://github.com/InteractiveComputerGraphics/" name ".git") {
        sub(/GIT_REPOSITORY.*/, "SOURCE_DIR \"" dir "\""); print; skip_tag = 1; next }
      skip_tag && /GIT_TAG/ { skip_tag = 0; next }
      { skip_tag = 0; print }' "$file" >"$file.new"
    mv "$file.new" "$file"
  done
  echo "$name $use" >>"$base/versions.txt"
}

rm -f "$base/versions.txt"
echo "SPlisHSPlasH $(cat "$src/.refcodes-commit")" >>"$base/versions.txt"
use_local_project Discregrid "$discregrid_repo"
use_local_project GenericParameters "$genericparameters_repo"
use_local_project PositionBasedDynamics "$pbd_repo"
use_local_project CompactNSearch "$compactnsearch_repo" "${COMPACTNSEARCH_COMMIT:-HEAD}"
if grep -q 'GIT_REPOSITORY https://github.com/InteractiveComputerGraphics/\(Discregrid\|GenericParameters\|PositionBasedDynamics\|CompactNSearch\)' \
  "$src/CMake/SetUpExternalProjects.cmake" "$src/CMake/NeighborhoodSearch.cmake"; then
  refcodes_die "could not redirect every ExternalProject of $src/CMake to a local source"
fi

echo "reference-codes: configuring SPlisHSPlasH (Release, float + AVX, OpenMP, no Python)" >&2
cmake -S "$src" -B "$base/build" -DCMAKE_BUILD_TYPE=Release -DUSE_DOUBLE_PRECISION=OFF -DUSE_AVX=ON \
  -DUSE_OpenMP=ON -DUSE_PYTHON_BINDINGS=OFF -DUSE_EMBEDDED_PYTHON=OFF >"$base/configure.log" 2>&1 ||
  refcodes_die "SPlisHSPlasH configure failed (see $base/configure.log)"
grep -q 'Using AVX2' "$base/configure.log" ||
  echo "reference-codes: SPlisHSPlasH found no AVX2 on this CPU: built without SIMD" >&2
echo "reference-codes: building SPHSimulator (-j$(refcodes_jobs), nice 19; log $base/build.log)" >&2
nice -n 19 cmake --build "$base/build" --target SPHSimulator -j"$(refcodes_jobs)" >"$base/build.log" 2>&1 ||
  refcodes_die "SPlisHSPlasH build failed (see the end of $base/build.log)"
binary=$src/bin/SPHSimulator
[ -x "$binary" ] || refcodes_die "SPlisHSPlasH built but $binary is missing"
echo "$binary"
