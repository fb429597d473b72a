#!/usr/bin/env bash
# Wall time of the hybrid trajectory study of issue 11: 4 fuzzy inputs,
# general form m = 3, 10 000 trajectories per TM point (examples/trajectory/
# hybrid.yaml), on the given number of jobs (default 2).  Goal: under a minute
# on 2 cores.  Usage: bench/trajectory_study.sh [build-dir] [jobs]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
jobs=${2:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
/usr/bin/time -f "wall %e s, user %U s, system %S s" \
  "$build"/rockfuzz run examples/trajectory/hybrid.yaml --out "$out" --jobs "$jobs" --fresh --quiet
python3 - "$out/result.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
e = d["evaluations"]
print(f"{e['evaluated']} TM points x 10000 trajectories, jobs {d['jobs']}, wall {d['wall_seconds']:.1f} s")
PY
