#!/bin/bash
# cli_terrain_mpi.sh - `rockfuzz trajectory` on a terrain file writes the
# same bytes in every output file (result.json, samples.csv, crossings.csv,
# statistics.csv, hazard.tif, paths.gpkg, every map PNG, report.html) at 1,
# 2 and 3 threads and under `mpirun -np 2` and `-np 3` (issue 28 items 5-7:
# samples shared by the ranks, rasters merged exactly).  The file has random
# inputs, Latin hypercube sampling and records more trajectories than rank 0
# runs, so every rank's draws, recorded trajectories and rasters are joined.
# Two things are not results and are set aside: the wall time (a line of
# result.json and of report.html) and the GeoPackage's last-change stamp
# (fixed here by GDAL's OGR_CURRENT_DATE).  An error on one rank only (its
# file missing; another seed) ends every rank with that rank's message and
# writes nothing.  The MPI part is skipped when mpirun is absent or the build
# has no MPI.
# Usage: bash cli_terrain_mpi.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
export OGR_CURRENT_DATE=2000-01-01T00:00:00.000Z

python3 - "$tmp" <<'PY' || fail "cannot write the grids"
import math, sys
d = sys.argv[1]
n, cell = 81, 2.0
def z(x, y):
    base = 40 + 0.7 * (y - 100) if y > 100 else 20 + 0.2 * y
    return base + 0.5 * math.sin(x / 7) * math.cos(y / 9)
for name, val in (("dem.asc", lambda x, y: "%.4f" % z(x, y)), ("classes.asc", lambda x, y: "1" if y > 100 else "2")):
    with open(f"{d}/{name}", "w") as f:
        f.write(f"ncols {n}\nnrows {n}\nxllcenter 0\nyllcenter 0\ncellsize {cell}\nNODATA_value -9999\n")
        for j in reversed(range(n)):
            f.write(" ".join(val(i * cell, j * cell) for i in range(n)) + "\n")
PY
cat > "$tmp/slope.yaml" <<EOF
name: slope
terrain: {dem: $tmp/dem.asc, materials: {raster: $tmp/classes.asc, classes: {1: rock, 2: talus}}}
materials:
  rock:  {R_n: {normal: [0.5, 0.05], min: 0.3, max: 0.7}, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, roughness: 5}
  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: {uniform: [0.15, 0.3]}, roughness: 10}
block: {shape: sphere, radius: {uniform: [0.3, 0.6]}, density: 2600}
release: {lines: [[[60, 150], [100, 150]], [[30, 140], [50, 150], [60, 145]]], height: 1.0, velocity: [0, 0, 0]}
bounce: {law: constant}
barriers: [{name: fence, line: [[10, 60], [150, 60]], height: 2, capacity: 1.0e5}]
rasters: {cell: 4, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}
samples: 301
record: 250
sampling: lhs
seed: 7
EOF

# same A B: every file of run A byte for byte in run B (wall time set aside)
same() {
    local a=$tmp/$1 b=$tmp/$2 f n=0
    for f in "$a"/*; do
        f=${f##*/}
        n=$((n + 1))
        case $f in
        result.json | report.html)
            cmp -s <(sed -E 's/"wall_seconds": [^}]*//; s/seed [0-9]+, [0-9.e+-]+ s</seed, s</' "$a/$f") \
                   <(sed -E 's/"wall_seconds": [^}]*//; s/seed [0-9]+, [0-9.e+-]+ s</seed, s</' "$b/$f") \
                || fail "$2: $f differs from $1's";;
        *) cmp -s "$a/$f" "$b/$f" || fail "$2: $f differs from $1's";;
        esac
    done
    [ "$(ls "$a" | wc -l)" = "$(ls "$b" | wc -l)" ] || fail "$2 has not the files of $1"
    echo "cli_terrain_mpi: $2 = $1 ($n files)"
}

"$bin" trajectory "$tmp/slope.yaml" --threads 1 --out "$tmp/t1" --quiet 2> "$tmp/t1.err" || fail "1 thread: $(cat "$tmp/t1.err")"
"$bin" trajectory "$tmp/slope.yaml" --threads 2 --out "$tmp/t2" --quiet 2> "$tmp/t2.err" || fail "2 threads: $(cat "$tmp/t2.err")"
"$bin" trajectory "$tmp/slope.yaml" --threads 3 --out "$tmp/t3" --quiet 2> "$tmp/t3.err" || fail "3 threads: $(cat "$tmp/t3.err")"
for f in result.json samples.csv crossings.csv statistics.csv hazard.tif paths.gpkg report.html terrain_map_passages.png; do
    [ -s "$tmp/t1/$f" ] || fail "the one-process run wrote no $f"
done
# the wall-time filter removes the wall time and nothing else
[ "$(diff <(sed -E 's/"wall_seconds": [^}]*//' "$tmp/t1/result.json") "$tmp/t1/result.json" | grep -c '^[<>]')" = 2 ] \
    || fail "the wall-time filter changed more than the wall-time line of result.json"
grep -q '"trajectories_shown": 100' "$tmp/t1/result.json" || fail "result.json does not show 100 trajectories"
same t1 t2
same t1 t3

if command -v mpirun > /dev/null && ldd "$bin" 2>/dev/null | grep -q libmpi; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_rmaps_base_oversubscribe=1
    export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
    mpi=(mpirun --allow-run-as-root --oversubscribe)
    timeout 300 "${mpi[@]}" -np 2 "$bin" trajectory "$tmp/slope.yaml" --threads 1 --out "$tmp/np2" --quiet \
        > /dev/null 2> "$tmp/np2.err" || fail "np 2: $(tail -3 "$tmp/np2.err")"
    timeout 300 "${mpi[@]}" -np 3 "$bin" trajectory "$tmp/slope.yaml" --threads 1 --out "$tmp/np3" --quiet \
        > /dev/null 2> "$tmp/np3.err" || fail "np 3: $(tail -3 "$tmp/np3.err")"
    same t1 np2
    same t1 np3
    # an error on rank 1 only: every rank ends (no hang), rank 1's message, nothing written
    timeout 120 "${mpi[@]}" -np 1 "$bin" trajectory "$tmp/slope.yaml" --out "$tmp/e1" --quiet : \
        -np 1 "$bin" trajectory "$tmp/nosuch.yaml" --out "$tmp/e1" --quiet > /dev/null 2> "$tmp/e1.err"
    rc=$?
    [ $rc != 0 ] && [ $rc != 124 ] || fail "a missing file on rank 1: exit $rc (124: a hang)"
    grep -q 'MPI rank 1: .*nosuch.yaml' "$tmp/e1.err" || fail "rank 1's error not reported: $(head -3 "$tmp/e1.err")"
    [ ! -e "$tmp/e1" ] || fail "a failed MPI run wrote $tmp/e1"
    timeout 120 "${mpi[@]}" -np 1 "$bin" trajectory "$tmp/slope.yaml" --out "$tmp/e2" --quiet : \
        -np 1 "$bin" trajectory "$tmp/slope.yaml" --seed 8 --out "$tmp/e2" --quiet > /dev/null 2> "$tmp/e2.err"
    rc=$?
    [ $rc != 0 ] && [ $rc != 124 ] || fail "another seed on rank 1: exit $rc"
    grep -q 'MPI rank 1 read different inputs' "$tmp/e2.err" || fail "different inputs not reported: $(head -3 "$tmp/e2.err")"
else
    echo "cli_terrain_mpi: MPI part SKIPPED (no mpirun or no MPI in the build)"
fi
[ $fails = 0 ] && echo "cli_terrain_mpi: all checks passed"
exit $((fails > 0))
