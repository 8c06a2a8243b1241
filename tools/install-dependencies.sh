#!/usr/bin/env bash
# Installs the Debian packages mps_lab needs, if any is missing. Safe to run again.
set -euo pipefail
packages=(build-essential cmake git libeigen3-dev libcli11-dev catch2 nlohmann-json3-dev
          python3-numpy python3-matplotlib ffmpeg clang-format
          libhypre-dev openmpi-bin)  # the last two: the solver comparison (lab/solver_comparison/)
# Opt-in: `tools/install-dependencies.sh --reference-codes` adds what building MPS-Basic and SPlisHSPlasH needs
# (tools/reference-codes/README.md): MPS-Basic's yaml-cpp, CSV parser and GoogleTest; the X11, OpenGL and D-Bus
# headers of the GLFW window and file dialog that SPlisHSPlasH's simulator always compiles (runs stay headless).
if [ "${1:-}" = "--reference-codes" ]; then
  packages+=(libyaml-cpp-dev libfccp-dev googletest pkg-config libgl-dev libx11-dev libxrandr-dev
             libxinerama-dev libxcursor-dev libxi-dev libdbus-1-dev)
elif [ $# -gt 0 ]; then
  echo "mps_lab: install-dependencies.sh: unknown argument '$1' (expected nothing or --reference-codes)" >&2
  exit 1
fi
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
