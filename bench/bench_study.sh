#!/bin/bash
# bench_study.sh - a whole study at scale: S1 (examples/s1_fem.yaml, seven
# fuzzy inputs, reduced form) with the axisymmetric FE solver, run from an
# empty store with 1 and 2 worker threads, and with 2 MPI ranks (rank 0 with
# one thread + one worker rank) if mpirun is there.  Prints wall time,
# evaluations per second and the speed-up from 1 to 2.
# Usage: bash bench/bench_study.sh [BUILD_DIR] [LEVELS] [REFINEMENT]
#        (defaults: build-store, m = 5 -> 641 evaluations, refinement 4)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build-store}
m=${2:-5}
ref=${3:-4}
bin=$build/rockfuzz
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed -e "s/^levels: .*/levels: $m/" -e "s/refinement: .*/refinement: $ref/" "$here/examples/s1_fem.yaml" > "$tmp/s1.yaml"
echo "S1, reduced form, m = $m, FE refinement $ref; $(nproc) cores; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
run() { # label, command...
    local label=$1; shift
    local t0 t1
    t0=$(date +%s.%N)
    setsid -w /usr/bin/time -f "%U %S" -o "$tmp/$label.cpu" "$@" > "$tmp/out.txt" 2> "$tmp/err.txt" \
        || { echo "$label: FAILED"; tail -3 "$tmp/err.txt"; return 1; }
    t1=$(date +%s.%N)
    local n
    n=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['evaluations']['evaluated'])" "$tmp/$label/result.json")
    python3 - "$label" "$t0" "$t1" "$n" "$(tail -1 "$tmp/$label.cpu")" <<'PY'
import sys
label, t0, t1, n = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
cpu = sum(map(float, sys.argv[5].split()))
w = t1 - t0
print(f"{label:10s} {n:6d} evaluations  {w:8.1f} s wall  {n / w:7.2f} evaluations/s  "
      f"CPU {cpu:7.1f} s = {cpu / w:4.2f} cores  {1e3 * cpu / n:6.1f} ms CPU per evaluation")
PY
    echo "$t0 $t1" > "$tmp/$label.time"
}
run jobs1 "$bin" run "$tmp/s1.yaml" --out "$tmp/jobs1" --jobs 1 --quiet --no-plots
run jobs2 "$bin" run "$tmp/s1.yaml" --out "$tmp/jobs2" --jobs 2 --quiet --no-plots
if command -v mpirun > /dev/null && ldd "$bin" | grep -q libmpi; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    run mpi2 mpirun --allow-run-as-root --oversubscribe -np 2 "$bin" run "$tmp/s1.yaml" --out "$tmp/mpi2" --quiet --no-plots
fi
python3 - "$tmp" <<'PY'
import json, os, sys
d = sys.argv[1]
t = {k: (lambda a: a[1] - a[0])(list(map(float, open(f"{d}/{k}.time").read().split())))
     for k in ("jobs1", "jobs2", "mpi2") if os.path.exists(f"{d}/{k}.time")}
print(f"speed-up 1 -> 2 threads: {t['jobs1'] / t['jobs2']:.2f}")
if "mpi2" in t:
    print(f"speed-up 1 thread -> 2 MPI ranks: {t['jobs1'] / t['mpi2']:.2f}")
ref = json.load(open(f"{d}/jobs1/result.json"))["outputs"]
for k in ("jobs2", "mpi2"):
    if os.path.exists(f"{d}/{k}/result.json"):
        same = json.load(open(f"{d}/{k}/result.json"))["outputs"] == ref
        print(f"{k}: outputs identical to jobs1 bit for bit: {same}")
PY
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
