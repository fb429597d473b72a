#!/usr/bin/env bash
# Installs every Debian 12 package rockfuzz needs to build, test and run its
# examples.  Run as root (or with sudo).  Safe to re-run.
set -euo pipefail
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
PACKAGES=(
  build-essential cmake pkg-config git
  libfyaml-dev          # study files (YAML, with line/column marks for errors)
  libmuparser-dev       # formula models (parsed once, evaluated per point)
  libplplot-dev plplot-driver-cairo   # PNG/SVG plots
  libcmocka-dev         # C unit-test framework
  libsqlite3-dev        # result store
  libgdal-dev gdal-bin  # trajectory profiles cut from DEMs (GeoTIFF, ASCII grid); gdal_translate in tests
  libopenmpi-dev openmpi-bin  # optional: studies distributed over MPI ranks (ROCKFUZZ_MPI)
  chromium              # tests: the HTML report is rendered headless and checked
  calculix-ccx          # external FE program used by the cantilever example
  clang libclang-rt-14-dev  # libFuzzer targets
  python3               # validation plotting helpers read JSON only
  python3-matplotlib    # doc plots of the trajectory validation (tools/, not the library)
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
echo "rockfuzz: all build dependencies are installed"
