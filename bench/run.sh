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
echo "== axisymmetric FE (bench/fem.sh, a/h = 10) =="
bash bench/fem.sh "$build" 10
echo "== 3D FE, 10 m/s on 45 deg, f = 0.6 (bench_fem3d: 1 and 2 threads alternated, 3 rounds; a/h = 6 and the default 3) =="
echo "(issue 9: 1 -> 2 threads >= 1.7 at a/h = 6 on an idle machine; load now: $(cut -d' ' -f1-3 /proc/loadavg))"
GOMP_SPINCOUNT=10000 "$build"/bench_fem3d 6 2 0 3  # the wait rockfuzz impact uses (src/cli/main.c)
GOMP_SPINCOUNT=10000 "$build"/bench_fem3d 3 2 0 3
echo "== material point updates and energy closure (bench_material) =="
"$build"/bench_material
echo "== memory bandwidth (bench_stream: triad, 3 / 24 / 192 MB) =="
"$build"/bench_stream 3 24 192
echo "== 3D mesh zones, element time steps and force kernels (bench_hex8, a/h = 6; docs/fem-speed.md) =="
OMP_WAIT_POLICY=passive "$build"/bench_hex8 6 100 2
echo "== axisymmetric force kernel (bench_quad4, a/h = 10) =="
"$build"/bench_quad4 10 300
echo "== time to accuracy, 10 m/s (bench_tta; converged values and curves: docs/fem-speed.md) =="
for t in 1 2; do OMP_WAIT_POLICY=passive "$build"/bench_tta axi "$t" 6 8 10; done
for t in 1 2; do OMP_WAIT_POLICY=passive "$build"/bench_tta 3d "$t" 3 4 6; done  # 3 = the 3D default
echo "(whole studies: bench/bench_study.sh; it takes minutes)"
echo "== trajectories: 30-segment profile, constant law (bench_trajectory; goal >= 200 000 /s/core) =="
"$build"/bench_trajectory 200000 1
echo "== the impact_model law against constant on the same profile (bench_impact_law; issue 29: within 2x) =="
"$build"/bench_impact_law 100000
echo "== trajectories on terrain: 1 km^2 DEM at 2 m, spheres, constant law, rasters on (bench_terrain; goal >= 50 000 /s/core) =="
"$build"/bench_terrain 100000
echo "(hybrid trajectory study: bench/trajectory_study.sh)"
