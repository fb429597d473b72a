#!/bin/sh
# bench/fem.sh - speed of the FE impact solver on one and two cores.
# Usage: bench/fem.sh [build-dir] [refinement] [domain factor, default 10 as in
# docs/validation.md section 11; 0 = the automatic default domain]
# Builds bench_fem (Release) if needed, then prints wall time per impact and
# ns per element-step at 1, 10, 30 m/s with 1 and 2 OpenMP threads.
set -e
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build-fem}
ref=${2:-10}
dom=${3:-10}
if [ ! -x "$build/bench_fem" ]; then
    cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$build" -j2 --target bench_fem >/dev/null
fi
for t in 1 2; do
    OMP_PROC_BIND=close "$build/bench_fem" "$ref" "$t" 3 "$dom"
done
