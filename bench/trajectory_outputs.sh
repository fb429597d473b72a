#!/usr/bin/env bash
# Output cost of a trajectory run against its simulation (issue 31 point 18):
# a rough 4 000-vertex profile (a 1 000 m slope of 0.25 m steps with a random
# relief and vertical steps, generated here), 200 samples with every
# trajectory recorded; the same run with --out (CSV files and envelopes, no
# plots) and without.  Prints both wall times and their ratio; goal: the
# outputs cost no more than the simulation.  Also times the profile check
# on a profile with 20 001 vertices on one x (a wall).
# Usage: bench/trajectory_outputs.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp" <<'PY'
import math, random, sys
d = sys.argv[1]
random.seed(1)
pts, x, y = [], 0.0, 600.0
for i in range(4000):
    pts.append((x, y))
    if i % 97 == 50:
        y -= 1.5  # a vertical step down
        pts.append((x, y))
    x += 0.25
    y -= 0.25 * (0.7 + 0.3 * math.sin(i / 40)) + random.uniform(-0.05, 0.05)
with open(d + "/profile.csv", "w") as f:
    f.write("x,y\n" + "".join("%.6f,%.6f\n" % p for p in pts))
steps = [(-10.0, 0.0)] + [(0.0, k / 1000.0) for k in range(20001)] + [(10.0, 20.0)]  # a wall of 20 001 vertices on x = 0
with open(d + "/steps.csv", "w") as f:
    f.write("x,y\n" + "".join("%g,%g\n" % p for p in steps))
for name, csv, samples in (("rough", "profile.csv", 200), ("steps", "steps.csv", 1)):
    with open("%s/%s.yaml" % (d, name), "w") as f:
        f.write("""name: %s
profile: {csv: %s, material: rock}
materials:
  rock: {R_n: {uniform: [0.3, 0.4]}, R_t: 0.8, friction_angle: 32, roughness: 3}
block: {shape: sphere, radius: 0.4, density: 2600}
release: {x: %s, y: %s, vx: 4}
bounce: {law: constant}
collectors: [{name: mid, x: %s}]
samples: %d
record: %d
seed: 3
""" % (name, csv, 1 if name == "rough" else 5, 602 if name == "rough" else 21, 500 if name == "rough" else 8, samples, samples))
PY
t() { local s e; s=$(date +%s.%N); "$@" > /dev/null; e=$(date +%s.%N); echo "$e - $s" | bc; }
sim=$(t "$build"/rockfuzz trajectory "$tmp/rough.yaml" --threads 1 --quiet)
out=$(t "$build"/rockfuzz trajectory "$tmp/rough.yaml" --threads 1 --quiet --no-plots --out "$tmp/o")
echo "rough profile, $(wc -l < "$tmp/profile.csv") lines, 200 samples, 1 thread:"
echo "  simulation only        $sim s"
echo "  with --out (no plots)  $out s   (outputs/simulation = $(echo "scale=2; ($out - $sim) / $sim" | bc))"
echo "  trajectories.csv       $(du -h "$tmp/o/trajectories.csv" | cut -f1)"
chk=$(t "$build"/rockfuzz trajectory "$tmp/steps.yaml" --threads 1 --quiet)
echo "wall profile, 20 003 vertices (20 001 on one x), 1 sample: $chk s (load, profile check, run)"
