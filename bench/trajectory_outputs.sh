#!/usr/bin/env bash
# Output cost of a trajectory run against its simulation (issue 31 point 18):
# a rough 4 000-vertex profile (a 1 000 m slope of 0.25 m steps with a random
# relief and vertical steps, generated here), 200 samples with every
# trajectory recorded; the same run with --out (CSV files and envelopes, no
# plots) and without.  Prints both wall times and their ratio; goal: the
# outputs cost no more than the simulation.  Also times the profile check
# on a profile whose vertices share few x values (vertical steps).
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
steps = [(0.0, 0.0)]
for i in range(1, 4001):  # a staircase: 2 vertices per x
    steps += [(float(i), -float(i - 1)), (float(i), -float(i))]
with open(d + "/steps.csv", "w") as f:
    f.write("x,y\n" + "".join("%g,%g\n" % p for p in steps))
for name, csv, samples in (("rough", "profile.csv", 200), ("steps", "steps.csv", 1)):
    with open("%s/%s.yaml" % (d, name), "w") as f:
        f.write("""name: %s
profile: {csv: %s, material: rock}
materials:
  rock: {R_n: {uniform: [0.3, 0.4]}, R_t: 0.8, friction_angle: 32, roughness: 3}
block: {shape: sphere, radius: 0.4, density: 2600}
release: {x: 1, y: 602, vx: 4}
bounce: {law: constant}
collectors: [{name: mid, x: 500}]
samples: %d
record: %d
seed: 3
""" % (name, csv, samples, samples))
PY
t() { local s e; s=$(date +%s.%N); "$@" > /dev/null; e=$(date +%s.%N); echo "$e - $s" | bc; }
sim=$(t "$build"/rockfuzz trajectory "$tmp/rough.yaml" --threads 1 --quiet)
out=$(t "$build"/rockfuzz trajectory "$tmp/rough.yaml" --threads 1 --quiet --no-plots --out "$tmp/o")
echo "rough profile, $(wc -l < "$tmp/profile.csv") lines, 200 samples, 1 thread:"
echo "  simulation only        $sim s"
echo "  with --out (no plots)  $out s   (outputs/simulation = $(echo "scale=2; ($out - $sim) / $sim" | bc))"
echo "  trajectories.csv       $(du -h "$tmp/o/trajectories.csv" | cut -f1)"
chk=$(t "$build"/rockfuzz trajectory "$tmp/steps.yaml" --threads 1 --quiet)
echo "staircase profile, 8001 vertices (2 per x), 1 sample: $chk s (load, profile check, run)"
