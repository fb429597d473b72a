#!/bin/bash
# cli_study_stop.sh - a study answers its folder lock and SIGTERM in every
# phase, not only while it evaluates (issue 31 item 9 and the report phase):
#   the impact table of a trajectory model (bounce law impact_model, FE
#   impacts) is built inside the run, after the folder lock: a second run into
#   the folder is refused at once, SIGTERM ends the run within 2 s with 143
#   and the study side's message, the impacts computed so far stay in the study's
#   store (store.sqlite, side rows; not in a side file);
#   planning a general-form grid (6 inputs, 20 levels) with the cap off answers SIGTERM
#   within 2 s (before: the count ran on, then the grid was built: 9 GB in 16 min);
#   SIGTERM while the report is written: a clean stop within 3 s (the figure
#   in progress is finished) with 143, no result.json,
#   the store intact, and the rerun writes the report from the store.
# Usage: bash cli_study_stop.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
pid=""
cleanup() {
    [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT

# wait_for FILE PATTERN SECONDS: until FILE holds a line matching PATTERN
wait_for() {
    for _ in $(seq $((10 * $3))); do
        grep -Eq -- "$2" "$1" 2>/dev/null && return 0
        kill -0 "$pid" 2>/dev/null || return 1
        sleep 0.1
    done
    return 1
}
# stop_within NAME SECONDS: SIGTERM to $pid; it must end within SECONDS with 143
stop_within() {
    local t0 t1 rc
    t0=$(date +%s%N)
    kill -TERM "$pid"
    for _ in $(seq $((10 * $2))); do kill -0 "$pid" 2>/dev/null || break; sleep 0.05; done
    t1=$(date +%s%N)
    if kill -0 "$pid" 2>/dev/null; then
        fail "$1: still running $2 s after SIGTERM"
        kill -9 "$pid"
    fi
    wait "$pid"; rc=$?
    pid=""
    echo "$1: ended $(( (t1 - t0) / 1000000 )) ms after SIGTERM, exit $rc"
    [ "$rc" -eq 143 ] || fail "$1: exit status $rc after SIGTERM, expected 143"
}

# ---- item 9: the impact table of a trajectory model, inside the run ----
cat > "$tmp/t.yaml" <<'Y'
name: t
profile:
  points: [[0, 30], [20, 10], [60, 0], [100, 0]]
  material: rock
materials:
  rock: {R_n: 0.35, R_t: 0.8, friction_angle: 30}
block: {shape: sphere, radius: 0.5, density: 2600}
release: {x: 1, y: 31, vx: 1, vy: 0}
bounce: {law: impact_model, impact: {solver: fem, refinement: 2, tolerance: 0.01, speeds: [1, 12], max_incidence: 60}}
collectors: [{name: fence, x: 50}]
samples: 20
Y
cat > "$tmp/s.yaml" <<Y
name: table
levels: 1
parameters:
  rn: {tfn: [0.35, 0.05, 0.05]}
model:
  trajectory: {file: $tmp/t.yaml, bind: {rn: materials.rock.R_n}}
Y
"$bin" run "$tmp/s.yaml" --out "$tmp/table" > "$tmp/table.out" 2> "$tmp/table.err" &
pid=$!
# the folder is locked before the table is built: the plan is printed after the lock
wait_for "$tmp/table.out" "^Impact table \(bounce law impact_model" 30 \
    || fail "table: no word of the impact table within 30 s: $(cat "$tmp/table.out" "$tmp/table.err")"
# a second run into the folder is refused at once, naming the holder
t0=$(date +%s%N)
timeout 10 "$bin" run "$tmp/s.yaml" --out "$tmp/table" --quiet > "$tmp/second.out" 2> "$tmp/second.err"; rc=$?
t1=$(date +%s%N)
[ $rc -eq 1 ] || fail "table: the second run into the locked folder ended with $rc, expected 1 (refused)"
grep -q "in use by another rockfuzz run (pid $pid " "$tmp/second.err" \
    || fail "table: second run's message: $(cat "$tmp/second.err")"
[ $(( (t1 - t0) / 1000000 )) -lt 3000 ] || fail "table: the refusal took $(( (t1 - t0) / 1000000 )) ms"
grep -q "Impact table" "$tmp/second.out" && fail "table: the refused run built an impact table"
# let it compute a few impacts, then SIGTERM: answered within 2 s
wait_for "$tmp/table.out" "^Impact table: [1-9][0-9]* impacts* computed" 60 \
    || fail "table: no impact computed within 60 s: $(cat "$tmp/table.out")"
sleep 1
kill -0 "$pid" 2>/dev/null || fail "table: the run ended before SIGTERM: $(cat "$tmp/table.err")"
stop_within table 2
grep -q "^rockfuzz run: $tmp/s.yaml: interrupted while building the impact table after [1-9][0-9]* impact" \
    "$tmp/table.err" || fail "table: message: $(cat "$tmp/table.err")"
grep -q "nothing was evaluated yet: rerun to resume" "$tmp/table.err" || fail "table: no resume hint: $(cat "$tmp/table.err")"
[ -e "$tmp/table/result.json" ] && fail "table: result.json written by an interrupted run"
n=$(python3 -c "import sqlite3,sys; print(sqlite3.connect(sys.argv[1]).execute(\"select count(*) from side_rows where key like 'impact_model %'\").fetchone()[0])" "$tmp/table/store.sqlite")
[ "$n" -ge 1 ] || fail "table: the computed impacts are not in the study's store"
[ -e "$tmp/impacts.txt" ] && fail "table: a study wrote a side file"
echo "table: $n impacts kept in the study's store"

# ---- planning with the cap off answers SIGTERM ----
cat > "$tmp/big.yaml" <<'Y'
name: big
scheme: general
levels: 20
parameters:
  a: {tfn: [1, 0.5, 0.5]}
  b: {tfn: [1, 0.5, 0.5]}
  c: {tfn: [1, 0.5, 0.5]}
  d: {tfn: [1, 0.5, 0.5]}
  e: {tfn: [1, 0.5, 0.5]}
  f: {tfn: [1, 0.5, 0.5]}
model:
  formula: {y: "a + b + c + d + e + f"}
options: {left_right: false}
Y
"$bin" run "$tmp/big.yaml" --out "$tmp/big" --max-evaluations 0 --quiet > "$tmp/big.out" 2> "$tmp/big.err" &
pid=$!
sleep 1
kill -0 "$pid" 2>/dev/null || fail "plan: the run ended within 1 s (the test needs a longer plan): $(cat "$tmp/big.out" "$tmp/big.err")"
stop_within plan 2
grep -q "interrupted while enumerating the TM's grid points" "$tmp/big.err" || fail "plan: message: $(cat "$tmp/big.err")"

# ---- SIGTERM while the report is written ----
{
    echo "name: report"
    echo "levels: 2"
    echo "parameters:"
    echo "  a: {tfn: [2, 1, 1]}"
    echo "  b: {tfn: [3, 1, 2]}"
    echo "model:"
    echo "  formula:"
    for k in $(seq 100); do echo "    y$k: \"a * b + $k * a\""; done
} > "$tmp/r.yaml"
"$bin" run "$tmp/r.yaml" --out "$tmp/report" --quiet > "$tmp/report.out" 2> "$tmp/report.err" &
pid=$!
# the summary is printed after the evaluations, before the report's files
wait_for "$tmp/report.out" "^Inputs:" 30 || fail "report: no summary within 30 s: $(cat "$tmp/report.err")"
kill -0 "$pid" 2>/dev/null || fail "report: the report was written before SIGTERM (the test needs a longer report)"
stop_within report 3 # one figure in progress at most
grep -q "^rockfuzz run: $tmp/r.yaml: interrupted while writing the report (.*); every evaluation is in $tmp/report/store.sqlite: rerun to write the report" \
    "$tmp/report.err" || fail "report: message: $(cat "$tmp/report.err")"
[ -e "$tmp/report/result.json" ] && fail "report: result.json of an interrupted report"
"$bin" status "$tmp/report" > "$tmp/status" 2>&1 || fail "report: status after the stop: $(cat "$tmp/status")"
planned=$(awk '/^Planned points/ {print $3}' "$tmp/status")
grep -q "^Done  *$planned (100.0 %)" "$tmp/status" || fail "report: the store after the stop: $(cat "$tmp/status")"
timeout 120 "$bin" run "$tmp/r.yaml" --out "$tmp/report" --quiet > /dev/null 2> "$tmp/report.err2" \
    || fail "report: the rerun failed: $(cat "$tmp/report.err2")"
stored=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['evaluations']['from_store'])" "$tmp/report/result.json" 2>/dev/null || echo 0)
[ "$stored" = "$planned" ] || fail "report: the rerun took $stored evaluations from the store, expected all $planned"
[ -s "$tmp/report/report.html" ] || fail "report: no report.html after the rerun"

[ $fails -eq 0 ] && echo "cli_study_stop: all checks passed"
exit $((fails > 0))
