#!/bin/sh
# tools/validate_fem_domain.sh - R_n against Hunter for the boundary kinds and
# domain sizes of docs/validation.md section 8: fixed and absorbing at 10 and
# 40 r0, and the default (automatic, fixed) domain, at 1, 3, 10, 30 m/s,
# a/h = 10.  Writes results_domain.txt in out-dir; then
#   /usr/bin/python3 tools/validate_fem_domain_plot.py out-dir docs/img
# draws docs/img/fem_restitution.png and prints the tables.  ~3 min on one core.
# Usage: tools/validate_fem_domain.sh [build-dir] [out-dir]
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
R="$out/results_domain.txt"
: > "$R"
for v in 1 3 10 30; do
    for bc in fixed absorbing; do
        for dom in 10 40; do
            echo "case=hunter $("$V" v=$v ref=10 bc=$bc dom=$dom hist="$out/hist_${bc}_d${dom}_v$v.csv" 2>&1)" | tee -a "$R"
        done
    done
    echo "case=hunter $("$V" v=$v ref=10 bc=fixed dom=0 hist="$out/hist_fixed_auto_v$v.csv" 2>&1)" | tee -a "$R"
done
echo "results in $R"
