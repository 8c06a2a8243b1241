#!/usr/bin/env bash
# Installs the Debian packages mps_lab needs, if any is missing. Safe to run again.
set -euo pipefail
packages=(build-essential cmake git libeigen3-dev libcli11-dev catch2 nlohmann-json3-dev
          python3-numpy python3-matplotlib ffmpeg clang-format
          libhypre-dev openmpi-bin)  # the last two: the solver comparison (lab/solver_comparison/)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "mps_lab: installing ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
  sudo=""
elif command -v sudo >/dev/null 2>&1; then
  sudo="sudo"
else
  echo "mps_lab: missing packages (${missing[*]}); run as root: apt-get install ${missing[*]}" >&2
  exit 1
fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
