# shellcheck shell=bash
# Shared helpers of the reference-code scripts (sourced, not run). See README.md beside this file.
# Nothing here downloads anything: sources come from git repositories already on the machine.

refcodes_die() {
  echo "reference-codes: $*" >&2
  exit 1
}

# refcodes_need_repo PATH NAME: fail with one line unless PATH is a git repository (bare or not).
refcodes_need_repo() {
  git -C "$1" rev-parse --git-dir >/dev/null 2>&1 ||
    refcodes_die "$2 source not found: '$1' is not a git repository (see tools/reference-codes/README.md, 'Sources')"
}

# refcodes_need_commit REPO COMMIT NAME: fail with one line unless REPO holds COMMIT.
refcodes_need_commit() {
  git -C "$1" cat-file -e "$2^{commit}" 2>/dev/null ||
    refcodes_die "$3: commit $2 is not in '$1' (fetch it, or give another commit)"
}

# refcodes_export_tree REPO COMMIT DEST: unpack the tree of COMMIT into DEST (emptied first), without a
# clone. Snapshot mirrors may lack their largest blobs (sample meshes, images): those files are left out
# and listed on stderr; none of them is needed to build.
refcodes_export_tree() {
  local repo=$1 commit=$2 dest=$3
  local missing
  missing=$(git -C "$repo" ls-tree -r "$commit" | awk '$2 == "blob" { print $3 }' |
    git -C "$repo" cat-file --batch-check='%(objectname) %(objecttype)' 2>/dev/null |
    awk '$2 == "missing" { print $1 }' | sort -u)
  if [ -n "$missing" ]; then
    missing=$(git -C "$repo" ls-tree -r "$commit" | awk -v m="$missing" '
      BEGIN { n = split(m, h, "\n"); for (i = 1; i <= n; i++) gone[h[i]] = 1 }
      $2 == "blob" && ($3 in gone) { sub(/^[^\t]*\t/, ""); print }')
  fi
  local excludes=()
  if [ -n "$missing" ]; then
    while IFS= read -r path; do
      excludes+=(":(exclude)$path")
      echo "reference-codes: $(basename "$(dirname "$repo")"): blob of '$path' absent from the mirror, left out" >&2
    done <<<"$missing"
  fi
  rm -rf "$dest"
  mkdir -p "$dest"
  # git archive still names an excluded absent blob on stderr (and exits 0): that line is dropped.
  git -C "$repo" archive --format=tar "$commit" -- . "${excludes[@]}" 2> >(grep -v '^error: invalid object' >&2) |
    tar -x -C "$dest"
  git -C "$repo" rev-parse "$commit^{commit}" >"$dest/.refcodes-commit"
}

# refcodes_jobs: parallel build jobs (REFCODES_JOBS, default 2).
refcodes_jobs() {
  echo "${REFCODES_JOBS:-2}"
}

# refcodes_now: wall-clock seconds with nanoseconds.
refcodes_now() {
  date +%s.%N
}

# refcodes_report CODE CASE THREADS END_TIME WALL_S PARTICLES STEPS [EXTRA]: the result line of one run
# (key=value, parsed by side-by-side.sh). Particle-steps per second = fluid particles x steps / wall time
# of the whole process (set-up, output and the steps, as `mps_lab run` reports its own).
refcodes_report() {
  awk -v code="$1" -v case_="$2" -v threads="$3" -v end="$4" -v wall="$5" -v n="$6" -v steps="$7" \
    -v extra="${8:-}" 'BEGIN {
      printf "code=%s case=%s threads=%s end_time=%s wall_s=%.3f particles=%d steps=%d particle_steps_per_s=%.0f%s\n",
        code, case_, threads, end, wall, n, steps, (wall > 0 ? n * steps / wall : 0), (extra == "" ? "" : " " extra) }'
}
