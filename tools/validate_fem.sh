#!/bin/sh
# tools/validate_fem.sh - run the FE validation study of docs/validation.md.
# Usage: tools/validate_fem.sh [build-dir] [out-dir]
# Builds tools/validate_fem.c against the library in build-dir (Release),
# runs every case (one impact per line of results.txt, key=value fields) and
# writes time histories as CSV; tools/validate_fem_plot.py turns them into
# docs/img/fem_*.png and prints the tables.  Takes ~15 min on one core.
set -e
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build-fem}
out=${2:-$build/validation}
mkdir -p "$out"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target rockfuzz >/dev/null
cc -O2 -std=c17 -D_POSIX_C_SOURCE=200809L -I"$src/include" -I"$src/src" "$src/tools/validate_fem.c" \
   "$build/librockfuzz.a" -lm -fopenmp -o "$build/validate_fem"
V="$build/validate_fem"
R="$out/results.txt"
: > "$R"
run() { tag=$1; shift; echo "case=$tag $("$V" "$@" 2>&1)" | tee -a "$R"; }

# Hertz comparison over a/R (absorbing boundary = closest to a half-space)
for v in 0.1 0.3 1 3 10 30; do
    run hertz v=$v ref=10 bc=absorbing hist="$out/hist_hertz_v$v.csv"
done
# mesh convergence, matching and non-matching (boulder 0.7 x slope size)
for v in 1 10 30; do
    for r in 5 10 20 40; do
        run conv v=$v ref=$r bc=absorbing
        run convnm v=$v ref=$r bc=absorbing ratio=0.7
    done
done
# R_n against Hunter: boundary kind and domain size (also the automatic default)
sh "$src/tools/validate_fem_domain.sh" "$build" "$out"
# spheroid: c = d is the sphere; c != d local Hertz with R = c^2/d
run spheroid v=10 ref=10 bc=absorbing c=1 d=1
for c in 0.9 1.1; do run spheroid v=10 ref=10 bc=absorbing c=$c; done
# scale: every length doubled
run scale v=10 ref=10 bc=absorbing r0=1
run scale v=10 ref=10 bc=absorbing r0=2
# time-step bound against the measured instability (a/h = 3 and 10)
for s in 1.0 1.2 1.25 1.3 1.35; do run dtscan v=10 ref=3 dtsafety=$s; done
for s in 1.0 1.2 1.25 1.3 1.35; do run dtscan v=10 ref=10 dtsafety=$s; done
# mesh picture
mkdir -p "$out/vtk"
"$V" v=10 ref=5 vtk="$out/vtk" >/dev/null
echo "results in $R"
