#!/bin/bash
# cli_trajectory_mpi.sh - a trajectory study gives the same fuzzy outputs,
# bit for bit, with 1 thread, 2 threads and under `mpirun -np 2` (each TM
# point's Monte Carlo ensemble depends only on its inputs and the seed).
# The MPI part is skipped when mpirun is absent or the build has no MPI.
# Usage: bash cli_trajectory_mpi.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

cat > "$tmp/t.yaml" <<'EOF'
profile: {points: [[0, 30], [20, 18], [30, 17], [50, 5], [90, 0]], materials: [rock, rock, soil, soil]}
materials:
  rock: {R_n: {normal: [0.35, 0.05], min: 0.2, max: 0.5}, R_t: 0.85, friction_angle: 30, roughness: 5}
  soil: {R_n: 0.25, R_t: 0.7, friction_angle: 35, roughness: 3}
block: {shape: sphere, radius: 0.4, density: 2600}
release: {x: {uniform: [0.5, 1.5]}, y: 31, vx: {uniform: [0, 2]}}
collectors: [{name: fence, x: 45}]
samples: 200
seed: 9
EOF
cat > "$tmp/s.yaml" <<'EOF'
levels: 2
parameters:
  rt: {tfn: [0.85, 0.1, 0.1]}
  soil_rn: {tfn: [0.25, 0.1, 0.1]}
model: {trajectory: {file: t.yaml, bind: {rt: materials.rock.R_t, soil_rn: materials.soil.R_n}}}
EOF
"$bin" run "$tmp/s.yaml" --out "$tmp/j1" --jobs 1 --quiet > /dev/null 2> "$tmp/j1.err" || fail "jobs 1: $(cat "$tmp/j1.err")"
"$bin" run "$tmp/s.yaml" --out "$tmp/j2" --jobs 2 --quiet > /dev/null 2> "$tmp/j2.err" || fail "jobs 2: $(cat "$tmp/j2.err")"
runs=("$tmp/j1/result.json" "$tmp/j2/result.json")
if command -v mpirun > /dev/null && ldd "$bin" 2>/dev/null | grep -q libmpi; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_rmaps_base_oversubscribe=1
    export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
    timeout 300 mpirun --allow-run-as-root --oversubscribe -np 2 "$bin" run "$tmp/s.yaml" --out "$tmp/np2" --jobs 1 \
        --quiet > /dev/null 2> "$tmp/np2.err" || fail "np 2: $(tail -5 "$tmp/np2.err")"
    runs+=("$tmp/np2/result.json")
else
    echo "cli_trajectory_mpi: MPI part SKIPPED (no mpirun or no MPI in the build)"
fi
python3 - "${runs[@]}" <<'EOF' || fail "results differ between thread counts / MPI"
import json, sys
r = [json.load(open(p)) for p in sys.argv[1:]]
for x in r[1:]:
    assert x["outputs"] == r[0]["outputs"], "outputs differ"
o = r[0]["outputs"]["fence_total_energy_p95"]
assert o["lower"][0] < o["upper"][0], o
if len(r) > 2:
    assert r[2]["mpi_ranks"] == 2 and r[2]["evaluations"]["on_worker_ranks"] > 0, r[2]["evaluations"]
EOF
[ $fails = 0 ] && echo "cli_trajectory_mpi: all checks passed"
exit $fails
