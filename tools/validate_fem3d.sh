#!/usr/bin/env bash
# tools/validate_fem3d.sh - run the 3D FE validation study of docs/validation-3d.md.
# Usage: tools/validate_fem3d.sh [build-dir] [out-dir] [group...]
# Builds tools/validate_fem3d.c against the library in build-dir (Release) and
# appends one line per impact to out-dir/results.txt ("case=<tag> key=value ...");
# tools/validate_fem3d_plot.py turns the results into docs/img/fem3d_*.png.
# Groups: normal oblique sweep conv bc (default: all).
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build-fem3d}
out=${2:-$build/validation3d}
shift 2 2>/dev/null || true
groups=${*:-normal oblique sweep conv bc}
T=${THREADS:-1}
mkdir -p "$out"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target rockfuzz >/dev/null
cc -O2 -std=c17 -Wall -Wextra -D_POSIX_C_SOURCE=200809L -I"$src/include" -I"$src/src" "$src/tools/validate_fem3d.c" \
   "$build/librockfuzz.a" -lm -fopenmp $(pkg-config --libs libfyaml muparser plplot) -lstdc++ \
   -o "$build/validate_fem3d"
V="$build/validate_fem3d"
R="$out/results.txt"
run() { tag=$1; shift; echo "case=$tag $* $("$V" threads=$T "$@" 2>/dev/null)" | tee -a "$R"; }

for g in $groups; do
case $g in
normal) # 3D normal impact against the axisymmetric solver (same a/h), 10 m/s
    for r in 10 20; do run axi v=10 ref=$r axi=1; done
    for r in 3 4 5 6; do run n3d v=10 ref=$r; done
    run axi707 v=7.0710678 ref=10 axi=1
    run n3d707 v=7.0710678 ref=6
    ;;
oblique) # frictionless 45 deg, sliding 60 deg
    run obl v=10 angle=45 f=0 ref=6 hist="$out/hist_45_f0.csv"
    run obl v=10 angle=60 f=0.1 ref=6
    run obl v=10 angle=60 f=0.2 ref=6
    run obl v=10 angle=45 f=0.6 ref=6 hist="$out/hist_45_f06.csv"
    ;;
sweep) # R_t and spin against f for the three slopes
    for a in 30 45 60; do for f in 0 0.05 0.1 0.15 0.2 0.3 0.45 0.6 0.8 1.0 2.0 5.0; do
        run sweep v=10 angle=$a f=$f ref=4; done; done
    ;;
conv) # mesh convergence on the 45 deg slope
    for r in 3 4 5 6 8; do run conv v=10 angle=45 f=0.6 ref=$r; done
    ;;
bc) # boundary: absorbing dashpots, larger domain
    run bc v=10 angle=45 f=0.6 ref=4 bc=absorbing
    run bc v=10 angle=45 f=0.6 ref=4 dom=20
    ;;
esac
done
