#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then the installed binary on its own:
#   tests/install/test_install.sh BUILD_DIR
# It checks the files a user gets (bin/mps_lab, share/mps_lab/{scenes,analysis}), that
# `mps_lab --version` names the version and the git revision, and that the installed binary runs
# a comparison from the installed scene with the installed experimental data (the front error
# against Martin & Moyce needs analysis/validation/ from share/mps_lab, found beside bin/).
set -euo pipefail
build=$1
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/mps_lab share/mps_lab/scenes/dambreak.json share/mps_lab/analysis/compare.py \
         share/mps_lab/analysis/validation/martin_moyce_1952_n2_front.csv; do
  [ -e "$prefix/$f" ] || { echo "missing after install: $f"; exit 1; }
done
version=$("$prefix/bin/mps_lab" --version)
echo "$version" | grep -Eq '^mps_lab [0-9]+\.[0-9]+\.[0-9]+ \(git [0-9a-f]{12}(-dirty)?\)$|^mps_lab [0-9]+\.[0-9]+\.[0-9]+ \(git unknown\)$' \
  || { echo "unexpected --version: $version"; exit 1; }
# Run from an empty folder so that nothing relative to the source tree can be found.
cd "$prefix"
"$prefix/bin/mps_lab" compare "$prefix/share/mps_lab/scenes/dambreak.json" --methods mps --end-time 0.2 \
  --out "$prefix/run" --no-analysis --quiet
header=$(head -1 "$prefix/run/summary.csv")
row=$(sed -n 2p "$prefix/run/summary.csv")
echo "$header" | grep -q front_rms || { echo "summary.csv without front_rms: $header"; exit 1; }
# The front error needs the experimental data: a value, not nan, proves the installed data was read.
column=$(echo "$header" | tr ',' '\n' | grep -n '^front_rms$' | cut -d: -f1)
value=$(echo "$row" | cut -d, -f"$column")
case "$value" in ""|nan|NaN|-nan) echo "front_rms not computed: '$value'"; exit 1;; esac
# Proof that the installed copy of the data is the one read (the source tree is also on this
# machine): shift the installed experimental front by +1 in Z = z/a; the unshifted front RMS
# against it must grow by about 1 (at least 0.5).
data="$prefix/share/mps_lab/analysis/validation/martin_moyce_1952_n2_front.csv"
awk -F, 'BEGIN{OFS=","} /^#/ || NR==0 {print; next} $1 ~ /^[0-9.]+$/ {$2 = $2 + 1.0} {print}' "$data" > "$data.new"
mv "$data.new" "$data"
"$prefix/bin/mps_lab" compare "$prefix/share/mps_lab/scenes/dambreak.json" --methods mps --end-time 0.2 \
  --out "$prefix/run2" --no-analysis --quiet
shifted=$(sed -n 2p "$prefix/run2/summary.csv" | cut -d, -f"$column")
awk -v a="$value" -v b="$shifted" 'BEGIN { exit !(b - a > 0.5) }' \
  || { echo "the installed binary did not read the installed data: front_rms $value, then $shifted"; exit 1; }
# The installed analysis package finds the installed binary (no MPS_LAB_BINARY, empty PATH).
found=$(env -u MPS_LAB_BINARY PATH=/nonexistent /usr/bin/python3 -c \
  "import sys; sys.path.insert(0, '$prefix/share/mps_lab/analysis'); from mps_lab.runner import find_binary; print(find_binary(environment={}))")
[ "$found" = "$prefix/bin/mps_lab" ] || { echo "installed analysis found '$found', expected $prefix/bin/mps_lab"; exit 1; }
echo "install test: $version; front_rms to 0.2 s = $value, against the shifted installed data $shifted"
