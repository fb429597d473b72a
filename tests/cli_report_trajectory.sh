#!/usr/bin/env bash
# cli_report_trajectory.sh - `rockfuzz report DIR` handles every result
# rockfuzz writes (issue 27, item 7): a `rockfuzz trajectory --out DIR` result
# gets its report.html and plots back byte for byte (the trajectories are run
# again from DIR/invocation.json, with the command line's --samples and
# --seed); a result its trajectory file no longer reproduces is refused with
# the report left as it was; a study result still works; anything else is
# refused by name. The report renders in headless Chromium (figures decode,
# no "nan" in its text); SHOT_TRAJECTORY_RUN=FILE keeps the screenshot.
# Usage: bash cli_report_trajectory.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

mkdir "$tmp/in dir" # a space in the recorded path
t="$tmp/in dir/t.yaml"
cat > "$t" <<EOF2
name: report
profile:
  points: [[-10, 20], [0, 20], [0, 0], [100, 0]]
  material: rock
materials:
  rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30, roughness: 2}
block: {shape: sphere, radius: 0.3, density: 2600}
release: {x: -0.5, y: 20.5, vx: {uniform: [1, 5]}, vy: 2}
collectors: [{name: barrier, x: 6}]
samples: 100
seed: 3
EOF2

out="$tmp/out"
"$bin" trajectory "$t" --samples 150 --seed 7 --threads 2 --out "$out" --quiet 2> "$tmp/e" || fail "trajectory: $(cat "$tmp/e")"
[ -s "$out/invocation.json" ] || fail "no invocation.json"
cp "$out/report.html" "$tmp/report.html"
cp "$out/trajectory_hist_barrier.png" "$tmp/hist.png"
rm "$out/report.html" "$out"/*.png "$out"/*.svg
msg=$("$bin" report "$out" 2> "$tmp/e") || fail "report of a trajectory result: exit $?: $(cat "$tmp/e")"
[ "$msg" = "$out/report.html" ] || fail "report printed '$msg'"
cmp -s "$tmp/report.html" "$out/report.html" || fail "the regenerated report.html differs from the run's"
cmp -s "$tmp/hist.png" "$out/trajectory_hist_barrier.png" || fail "the regenerated histogram differs"
[ -s "$out/trajectory_profile.svg" ] || fail "no profile SVG regenerated"
# the page a person reads: rendered, every figure decodes, no "nan" in its text
cli_render_check cli_report_trajectory "$out/report.html" 2 "${SHOT_TRAJECTORY_RUN:-}"
python3 - "$out/report.html" <<'EOF3' || fail "report text shows nan"
import re, sys
text = re.sub(r"<[^>]*>", " ", re.sub(r"(?s)<(script|style)[^>]*>.*?</\1>", " ", open(sys.argv[1]).read()))
sys.exit(1 if re.search(r"\bnan\b", text, re.I) else 0)
EOF3

# --no-plots: report writes the report the run did not
"$bin" trajectory "$t" --samples 150 --seed 7 --out "$tmp/np" --quiet --no-plots 2> "$tmp/e" || fail "--no-plots: $(cat "$tmp/e")"
[ -e "$tmp/np/report.html" ] && fail "--no-plots wrote report.html"
"$bin" report "$tmp/np" > /dev/null 2> "$tmp/e" || fail "report after --no-plots: $(cat "$tmp/e")"
grep -q 'data:image/png;base64' "$tmp/np/report.html" || fail "report after --no-plots: no figure"

# the file edited since: refused, nothing rewritten
sed -i 's/R_n: 0.4/R_n: 0.5/' "$t"
"$bin" report "$out" > /dev/null 2> "$tmp/e"; rc=$?
[ "$rc" -eq 1 ] || fail "edited file: exit $rc, want 1"
grep -q "result.json is not what .*t.yaml gives now" "$tmp/e" || fail "edited file: message: $(cat "$tmp/e")"
cmp -s "$tmp/report.html" "$out/report.html" || fail "edited file: report.html was changed"
# the file gone
rm "$t"
"$bin" report "$out" > /dev/null 2> "$tmp/e" && fail "missing trajectory file: exit 0"
grep -q "t.yaml" "$tmp/e" || fail "missing trajectory file: message: $(cat "$tmp/e")"

# a study result: as before
cat > "$tmp/s.yaml" <<EOF2
name: report
levels: 2
parameters:
  a: {tfn: [2, 1, 1]}
model:
  formula: {y: "a*a"}
EOF2
"$bin" run "$tmp/s.yaml" --out "$tmp/run" --quiet > /dev/null 2>&1 || fail "study run"
rm "$tmp/run/report.html"
"$bin" report "$tmp/run" > /dev/null 2> "$tmp/e" && [ -s "$tmp/run/report.html" ] || fail "study report: $(cat "$tmp/e")"

# not a result
mkdir "$tmp/none"
echo '{"x": 1}' > "$tmp/none/result.json"
"$bin" report "$tmp/none" > /dev/null 2> "$tmp/e"; rc=$?
[ "$rc" -eq 1 ] && grep -q "not a rockfuzz result" "$tmp/e" || fail "not a result: exit $rc: $(cat "$tmp/e")"

[ "$fails" -eq 0 ] && echo "cli_report_trajectory: all passed"
exit $((fails > 0))
