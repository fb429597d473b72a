#!/usr/bin/env bash
# Prints rockfuzz's speed figures: the TM's own overhead and, when built, the
# FE solver's time per impact.  Usage: bench/run.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "== TM overhead (bench_tm) =="
"$build"/bench_tm 7
for script in bench/fem.sh bench/fem3d.sh; do
  if [ -x "$script" ] || [ -f "$script" ]; then
    echo "== $script =="
    bash "$script" "$build"
  fi
done
