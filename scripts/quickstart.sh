#!/usr/bin/env bash
# Installs the Debian packages, builds rockfuzz and runs the default study
# (examples/default.yaml: a fuzzy p95 barrier energy at the foot of a talus)
# into out/default.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
./build/rockfuzz run examples/default.yaml --out out/default
echo "the answer first: out/default/report.html; everything: out/default/result.json, CSV and plots in out/default/"
