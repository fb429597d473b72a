#!/bin/bash
# cli_trajectory.sh - `rockfuzz trajectory`: the minimal file of issue 11
# runs, --json has the documented shape (checked with python3), --out writes
# the CSV files, plots and a self-contained report.html, a bad file exits 1
# with file:line: field = value, a bad option exits 2; the hybrid example
# study loads.  Usage: bash cli_trajectory.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$src/tests/cli_run.lsan.supp"
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }

"$bin" trajectory "$src/examples/trajectory/cliff.yaml" > "$tmp/summary.txt" || fail "cliff.yaml did not run"
grep -q "stopped at t = " "$tmp/summary.txt" || fail "no rest point in the summary"
"$bin" trajectory "$src/examples/trajectory/cliff.yaml" --json > "$tmp/cliff.json" || fail "--json failed"
python3 - "$tmp/cliff.json" <<'PY' || fail "JSON shape"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["samples"] == 1
t = d["trajectories"][0]
assert t["state"] in ("stopped", "exited", "step_limit")
i = t["impacts"][0]
for k in ("t", "x", "y", "segment", "vx_in", "vy_in", "vx_out", "vy_out", "omega_out"):
    assert k in i, k
assert i["segment"] == 2 and abs(i["x"] - 10.791871594517408) < 1e-9
assert set(t["rest"]) >= {"t", "x", "y"}
c = t["collectors"]["barrier"]
for k in ("t", "height", "normal_height", "speed", "kinetic_energy", "rotational_energy"):
    assert k in c, k
s = d["statistics"]
assert set(s["runout_x"]) >= {"p50", "p95", "p99", "max"}
b = s["collectors"]["barrier"]
assert b["reach_probability"] == 1 and set(b["kinetic_energy"]) >= {"p50", "p95", "p99", "max"} and "height" in b
PY
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --samples 300 --threads 2 --out "$tmp/out" --quiet \
  || fail "slope.yaml --out"
for f in result.json trajectories.csv crossings.csv statistics.csv envelopes.csv report.html trajectory_profile.png \
         trajectory_profile.svg trajectory_hist_barrier.png trajectory_hist_road.svg; do
  [ -s "$tmp/out/$f" ] || fail "missing $f"
done
grep -q "data:image/png;base64" "$tmp/out/report.html" || fail "report.html does not embed its figures"
[ "$(grep -c ',barrier,' "$tmp/out/crossings.csv")" = 300 ] || fail "crossings.csv rows"
# envelopes from all 300 trajectories: at the barrier's x (95 m, an edge) as many reach as cross it
head -1 "$tmp/out/envelopes.csv" | grep -q '^x_m,reached,fraction_reaching,height_p50_m,.*,energy_max_J$' \
  || fail "envelopes.csv header"
[ "$(grep -c . "$tmp/out/envelopes.csv")" = 162 ] || fail "envelopes.csv rows"
n_cross=$(awk -F, '$4 == "barrier" && $5 == 1' "$tmp/out/crossings.csv" | wc -l)
[ "$(awk -F, '$1 == 95 {print $2}' "$tmp/out/envelopes.csv")" = "$n_cross" ] || fail "envelope reach at the barrier"
grep -q "envelopes use all 300" "$tmp/out/report.html" || fail "report: envelopes from all trajectories"

printf 'profile: {points: [[0, 0], [10, -1]], material: m}\nmaterials: {m: {R_n: 2, R_t: 0.5}}\nblock: {mass: 1}\nrelease: {x: 1, y: 1}\n' > "$tmp/bad.yaml"
"$bin" trajectory "$tmp/bad.yaml" 2> "$tmp/err.txt"
[ $? = 1 ] || fail "bad file: exit status"
grep -q "bad.yaml:2: materials.m.R_n = 2: must lie in \[0, 1\]" "$tmp/err.txt" || fail "bad file message: $(cat "$tmp/err.txt")"
"$bin" trajectory "$src/examples/trajectory/cliff.yaml" --samples x 2> /dev/null
[ $? = 2 ] || fail "bad option: exit status"
"$bin" trajectory --help | grep -q "Usage: rockfuzz trajectory" || fail "--help"
"$bin" --help | grep -q "trajectory FILE.yaml" || fail "rockfuzz --help lists trajectory"

# the hybrid study loads and plans (no evaluation: a cap of 1 refuses to start)
"$bin" run "$src/examples/trajectory/hybrid.yaml" --out "$tmp/h" --max-evaluations 1 > /dev/null 2> "$tmp/h.txt"
grep -q "general" "$tmp/h.txt" || grep -q "evaluations" "$tmp/h.txt" || fail "hybrid study: $(cat "$tmp/h.txt")"

[ $fails = 0 ] && echo "cli_trajectory: all checks passed"
exit $fails
