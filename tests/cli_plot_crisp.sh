#!/bin/bash
# cli_plot_crisp.sh - a study whose output is crisp to the last bits (every
# block leaves a 40 m profile at its end: runout p99 cut [40, 40 + 7e-15])
# writes its report and ends: PLplot's tick search looped for ever on such an
# axis and the study never ended (plot/figure.h, rf_plot_axis_range).
# Usage: bash cli_plot_crisp.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
cat > "$tmp/two.yaml" <<'YAML'
name: two
profile:
  points: [[0, 20], [10, 10], [20, 5], [40, 0]]
  materials: [rock, talus, talus]
materials:
  rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}
  talus: {R_n: 0.3, R_t: 0.75, friction_angle: 32, rolling_resistance: 0.2}
block: {shape: point, mass: 100}
release: {x: 1, y: 30, vx: {uniform: [2, 5]}}
collectors: [{name: c, x: 15}]
samples: 200
seed: 5
YAML
cat > "$tmp/s.yaml" <<'YAML'
levels: 1
options: {left_right: false}
parameters:
  d: {tfn: [0.758, 0.1, 0.1]}
model: {trajectory: {file: two.yaml, bind: {d: materials.talus.R_n}}}
YAML
timeout -s KILL 120 "$bin" run "$tmp/s.yaml" --out "$tmp/out" --quiet > "$tmp/log" 2>&1
rc=$?
[ $rc -eq 0 ] || fail "run exit $rc (137: killed after 120 s, the plot hang): $(tail -3 "$tmp/log")"
grep -q '^0,40,40.000000000000007$' "$tmp/out/cuts_runout_x_p99.csv" ||
    fail "the case changed: runout p99 cut is not [40, 40 + 1 ulp]: $(cat "$tmp/out/cuts_runout_x_p99.csv")"
[ -s "$tmp/out/output_runout_x_p99.png" ] || fail "output_runout_x_p99.png not written"
grep -q "PLPLOT ERROR" "$tmp/log" && fail "PLplot refused an axis: $(grep -m1 -A1 'PLPLOT ERROR' "$tmp/log")"
[ -s "$tmp/out/report.html" ] || fail "no report.html"
[ $fails -eq 0 ] && echo "cli_plot_crisp: ok"
exit $((fails > 0))
