#!/bin/bash
# cli_mpi.sh - `mpirun -np 2 rockfuzz run`: rank 0 owns the store and hands
# out points, rank 1 evaluates; the fuzzy outputs equal a serial run bit for
# bit, rank 1 really evaluated points, -np 1 behaves as serial, and an MPI run
# resumes from a store written by a serial run.  Skipped (exit 0 with a
# message) when mpirun is absent or the binary was built without MPI.
# Usage: bash cli_mpi.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
if ! command -v mpirun > /dev/null; then
    echo "cli_mpi: SKIPPED: mpirun not found (apt-get install openmpi-bin libopenmpi-dev)"
    exit 0
fi
if ! ldd "$bin" 2>/dev/null | grep -q libmpi; then
    # a build without MPI must refuse to run once per rank into the same store
    printf 'parameters:\n  a: {tfn: [2, 1, 1]}\nmodel:\n  formula: {f: "a"}\n' > "${TMPDIR:-/tmp}/rf_nompi.yaml"
    if OMPI_COMM_WORLD_SIZE=2 "$bin" run "${TMPDIR:-/tmp}/rf_nompi.yaml" --out "${TMPDIR:-/tmp}/rf_nompi" --quiet \
        2> "${TMPDIR:-/tmp}/rf_nompi.err" > /dev/null || ! grep -q "built without MPI" "${TMPDIR:-/tmp}/rf_nompi.err"; then
        echo "FAIL: a build without MPI ran under 2 ranks: $(cat "${TMPDIR:-/tmp}/rf_nompi.err")" >&2
        rm -rf "${TMPDIR:-/tmp}"/rf_nompi*
        exit 1
    fi
    rm -rf "${TMPDIR:-/tmp}"/rf_nompi*
    echo "cli_mpi: SKIPPED: $bin was built without MPI (ROCKFUZZ_MPI=OFF or no MPI found); refuses mpirun: ok"
    exit 0
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_rmaps_base_oversubscribe=1
# sanitizer builds: Open MPI's own allocations at exit are not our leaks
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
mpi() { timeout 120 mpirun --allow-run-as-root --oversubscribe "$@"; }

cat > "$tmp/s.yaml" <<'EOF2'
name: mpi
scheme: general
levels: 4
parameters:
  a: {tfn: [2, 1, 1]}
  b: {tfn: [3, 1, 2]}
  c: {gaussian: [1, 0.2, 0.3], cutoff: 3}
model:
  formula: {f: "a*sin(b) + c^2 / (1 + a*b)", g: "exp(-a/b) * cos(c)"}
options: {left_right: true}
EOF2
"$bin" run "$tmp/s.yaml" --out "$tmp/serial" --jobs 1 --quiet > /dev/null 2> "$tmp/serial.err" || fail "serial: $(cat "$tmp/serial.err")"
mpi -np 2 "$bin" run "$tmp/s.yaml" --out "$tmp/np2" --quiet > "$tmp/np2.out" 2> "$tmp/np2.err" || fail "np 2: $(tail -5 "$tmp/np2.err")"
grep -q "rank 0 + 1 MPI worker rank" "$tmp/np2.out" || fail "np 2: plan line does not mention the worker rank"
mpi -np 1 "$bin" run "$tmp/s.yaml" --out "$tmp/np1" --quiet > /dev/null 2> "$tmp/np1.err" || fail "np 1: $(tail -5 "$tmp/np1.err")"
python3 - "$tmp/serial/result.json" "$tmp/np2/result.json" "$tmp/np1/result.json" <<'EOF2' || fail "MPI results differ from the serial run"
import json, sys
a, b, c = (json.load(open(p)) for p in sys.argv[1:])
for r in (b, c):
    assert r["outputs"] == a["outputs"], "outputs differ"
    assert r["evaluations"]["distinct"] == a["evaluations"]["distinct"]
assert b["mpi_ranks"] == 2 and c["mpi_ranks"] == 1, (b["mpi_ranks"], c["mpi_ranks"])
assert b["evaluations"]["on_worker_ranks"] > 0, b["evaluations"]
assert c["evaluations"]["on_worker_ranks"] == 0, c["evaluations"]
EOF2

# resume under MPI from a serial store: nothing is evaluated again
mpi -np 2 "$bin" run "$tmp/s.yaml" --out "$tmp/serial" --progress=jsonl > /dev/null 2> "$tmp/res.err" || fail "MPI resume: $(tail -5 "$tmp/res.err")"
[ "$(grep -c '"event"' "$tmp/res.err")" -eq 0 ] || fail "MPI resume evaluated stored points again"
python3 -c "import json,sys; r=json.load(open(sys.argv[1])); assert r['evaluations']['from_store'] == r['evaluations']['distinct']" \
    "$tmp/serial/result.json" || fail "MPI resume: from_store != distinct"

# a study error on every rank: one message, non-zero exit, no rank left hanging
printf 'parameters:\n  a: {tfn: [2, 1, 1]}\nmodel:\n  formula: {f: "a*zz"}\n' > "$tmp/bad.yaml"
mpi -np 2 "$bin" run "$tmp/bad.yaml" --out "$tmp/bad" --quiet > /dev/null 2> "$tmp/bad.err" && fail "bad study accepted under MPI"
grep -q "zz" "$tmp/bad.err" || fail "bad study under MPI: message $(cat "$tmp/bad.err")"

[ $fails -eq 0 ] && echo "cli_mpi: all checks passed"
exit $((fails > 0))
