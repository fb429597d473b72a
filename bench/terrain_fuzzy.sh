#!/usr/bin/env bash
# The fuzzy hazard map of issue 28 ("Speed"): 3 fuzzy inputs, general form,
# m = 2 (27 TM points; left_right: false, the default's three-point grid
# of the monotonicity check would add 26 more), each point a Monte Carlo of SAMPLES trajectories on
# examples/terrain/valley.yaml (all five raster statistics, the fuzzy bands
# reach_probability, energy_p95, height_p95), on JOBS jobs.  Goal: 10^5
# trajectories per point on 2 cores in under 2 minutes.  Prints the wall and
# CPU time, trajectories per second per core, and the wall time scaled to
# 10^5 trajectories per point (the trajectories dominate: the TM and the
# per-cell retransformation are also printed, as the time at SAMPLES = 0+).
# Usage: bench/terrain_fuzzy.sh [build-dir] [samples per point (default 100000)] [jobs (default 2)]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
samples=${2:-100000}
jobs=${3:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cat > "$out/study.yaml" <<YAML
name: valley-fuzzy-bench
scheme: general
levels: 2
options: {left_right: false}
parameters:
  rock_Rn: {tfn: [0.5, 0.1, 0.1]}
  talus_rolling: {tfn: [0.2, 0.1, 0.1]}
  soil_friction: {tfn: [38, 4, 4]}
model:
  trajectory:
    file: $PWD/examples/terrain/valley.yaml
    samples: $samples
    bind: {rock_Rn: materials.rock.R_n, talus_rolling: materials.talus.rolling_resistance,
           soil_friction: materials.soil.friction_angle}
    rasters: {fuzzy: [reach_probability, energy_p95, height_p95]}
YAML
/usr/bin/time -f "%e %U %S" -o "$out/time" \
  "$build"/rockfuzz run "$out/study.yaml" --out "$out/run" --jobs "$jobs" --fresh --quiet --no-plots > /dev/null
python3 - "$out/run/result.json" "$out/time" "$samples" "$jobs" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
wall, user, sys_ = map(float, open(sys.argv[2]).read().split()[-3:])
n, jobs = int(sys.argv[3]), int(sys.argv[4])
pts = d["evaluations"]["evaluated"]
traj = pts * n
print(f"{pts} TM points x {n} trajectories = {traj} on {jobs} jobs: wall {wall:.1f} s, CPU {user + sys_:.1f} s "
      f"({traj / (user + sys_):.0f} trajectories per CPU second)")
print(f"scaled to 10^5 per point: {wall * 1e5 / n:.0f} s wall (goal 120 s)")
PY
