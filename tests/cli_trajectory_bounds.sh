#!/bin/bash
# cli_trajectory_bounds.sh - a fuzzy trajectory study reruns its Monte Carlo
# at the inputs the TM found for the lower and upper bound of the main output
# at membership 0 (DIR/bound_lower/, DIR/bound_upper/, beside DIR/nominal/):
# the reruns give the study's bounds bit for bit and are the same bits as
# `rockfuzz trajectory` on the file with those values; the report's summary
# states them; the three runs' figures share their axes (the widest of the
# three envelopes); a second run into the folder reruns nothing; `main_output:`
# chooses the output, a wrong name is refused with file:line; the page shows
# no "nan" and renders in headless Chromium with no broken image.
# Usage: bash cli_trajectory_bounds.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

study() { # study NAME EXTRA-TOP-LEVEL-LINE
  cat > "$tmp/$1.yaml" <<YAML
name: $1
levels: 2
$2
parameters:
  rock_Rn: {tfn: [0.35, 0.1, 0.1]}
  talus_Rt: {tfn: [0.8, 0.08, 0.08]}
model:
  trajectory:
    file: $src/examples/trajectory/slope.yaml
    samples: 300
    bind: {rock_Rn: materials.rock.R_n.mean, talus_Rt: materials.talus.R_t.mean}
options: {left_right: false}
YAML
}

study bounds "scheme: general"
"$bin" run "$tmp/bounds.yaml" --out "$tmp/run" --quiet > "$tmp/run.txt" 2>&1 || fail "study run: $(tail -3 "$tmp/run.txt")"
for d in nominal bound_lower bound_upper; do
  for f in result.json envelopes.csv crossings.csv report.html trajectory_profile.png rerun.txt; do
    [ -s "$tmp/run/$d/$f" ] || fail "missing $d/$f"
  done
done

# the reruns' main output is the study's bound (the same double), the main output is the p95 barrier energy
python3 - "$tmp/run" > "$tmp/check.txt" 2>&1 <<'EOF' || fail "bounds: $(cat "$tmp/check.txt")"
import json, sys
d = sys.argv[1]
r = json.load(open(d + "/result.json"))
assert r["main_output"] == "barrier_total_energy_p95", r["main_output"]
o = r["outputs"]["barrier_total_energy_p95"]
for side, sub, want in (("lower", "bound_lower", o["lower"][0]), ("upper", "bound_upper", o["upper"][0]),
                        (None, "nominal", o["nominal"])):
    got = json.load(open(f"{d}/{sub}/result.json"))["statistics"]["collectors"]["barrier"]["total_energy"]["p95"]
    assert got == want, (sub, got, want)
    mark = dict(l.split(" ", 1) for l in open(f"{d}/{sub}/rerun.txt").read().splitlines())
    assert float(mark["value"]) == want, (sub, mark["value"], want)
assert o["lower"][0] < o["nominal"] < o["upper"][0], o
# the summary at the top states the bounds and the nominal value in kJ, as printed (%.4g)
h = open(d + "/report.html").read()
line = h[h.index("<p class=headline>"):]
line = line[:line.index("</p>")]
nums = "between <b>%.4g and %.4g kJ</b>" % (o["lower"][0] * 1e-3, o["upper"][0] * 1e-3)
assert nums in line and ("<b>%.4g kJ</b>" % (o["nominal"] * 1e-3)) in line, line
assert h.index("id=summary") < h.index("<h2>Run</h2>") < h.index("id=reruns"), "summary not at the top"
assert 'href="#reruns"' in h[:h.index("<h2>Run</h2>")], "the summary does not point to the reruns"
for alt in ("Nominal point", "Lower bound at membership 0", "Upper bound at membership 0"):
    assert ('alt="trajectories: %s" src="data:image/png;base64,' % alt) in h, alt
# the figures of the three share their axes: the widest envelopes and energy ranges of the three
drawn = [open(f"{d}/{s}/rerun.txt").read().split("\ndrawn ")[1] for s in ("nominal", "bound_lower", "bound_upper")]
assert drawn[0] == drawn[1] == drawn[2], drawn
v = [float(x) for x in drawn[0].split()]
def col(sub, name):
    rows = [l.split(",") for l in open(f"{d}/{sub}/envelopes.csv").read().splitlines()]
    k = rows[0].index(name)
    return max(float(x[k]) for x in rows[1:] if x[k] != "nan")
subs = ("nominal", "bound_lower", "bound_upper")
# (envelopes.csv prints the maxima %.9g: the same digits)
assert float("%.9g" % v[1]) == max(col(s, "height_max_m") for s in subs), (v[1], [col(s, "height_max_m") for s in subs])
assert float("%.9g" % v[2]) == max(col(s, "energy_max_J") for s in subs), (v[2], [col(s, "energy_max_J") for s in subs])
rows = [l.split(",") for s in subs for l in open(f"{d}/{s}/crossings.csv").read().splitlines()[1:]]
e = [float(x[12]) for x in rows if x[3] == "barrier" and x[4] == "1"]
assert (v[4], v[5]) == (min(e), max(e)), (v[4:6], min(e), max(e))  # the barrier's energy histograms
print(sys.argv[1], "ok")
EOF

# no "nan" shown (the page's text without its images); in a real browser (headless Chromium;
# skipped without it) the page renders and no image is broken
python3 - "$tmp/run/report.html" > "$tmp/nan.txt" 2>&1 <<'EOF' || fail "the report shows nan: $(cat "$tmp/nan.txt")"
import re, sys
h = re.sub(r'src="data:image/png;base64,[^"]*"', "", open(sys.argv[1]).read())
t = re.sub(r"<[^>]*>", " ", h)
m = re.search(r".{0,60}\bnan\b.{0,60}", t, re.I | re.S)
assert not m, m.group(0)
EOF
cli_render_check cli_trajectory_bounds "$tmp/run/report.html" 7 # 2 inputs, 3 profiles, histograms

# the lower bound's run is `rockfuzz trajectory` on the file with the bound's inputs written in
read -r rn rt < <(python3 -c "import json,sys; p=json.load(open(sys.argv[1]))['outputs']['barrier_total_energy_p95']['x_lower'][0]; print('%.17g %.17g' % (p['rock_Rn'], p['talus_Rt']))" "$tmp/run/result.json")
sed -e "s/rock:  {R_n: {normal: \[0.35,/rock:  {R_n: {normal: [$rn,/" \
    -e "s/talus: {R_n: {normal: \[0.32, 0.04\], min: 0.2, max: 0.45}, R_t: {normal: \[0.80,/talus: {R_n: {normal: [0.32, 0.04], min: 0.2, max: 0.45}, R_t: {normal: [$rt,/" \
    "$src/examples/trajectory/slope.yaml" > "$tmp/slope_lower.yaml"
[ "$(diff "$src/examples/trajectory/slope.yaml" "$tmp/slope_lower.yaml" | grep -c '^>')" = 2 ] \
  || fail "could not write the bound's inputs into a copy of slope.yaml"
"$bin" trajectory "$tmp/slope_lower.yaml" --samples 300 --out "$tmp/direct" --quiet --no-plots || fail "direct run"
cmp -s "$tmp/run/bound_lower/crossings.csv" "$tmp/direct/crossings.csv" || fail "bound_lower crossings differ from a direct run"
cmp -s "$tmp/run/bound_lower/envelopes.csv" "$tmp/direct/envelopes.csv" || fail "bound_lower envelopes differ from a direct run"

# a second run into the folder: every point from the store, the reruns kept
touch "$tmp/mark"
sleep 1
"$bin" run "$tmp/bounds.yaml" --out "$tmp/run" --quiet > "$tmp/run2.txt" 2>&1 || fail "second run: $(tail -3 "$tmp/run2.txt")"
newer=$(find "$tmp/run/nominal" "$tmp/run/bound_lower" "$tmp/run/bound_upper" -newer "$tmp/mark" | wc -l)
[ "$newer" = 0 ] || fail "a complete rerun was run again ($newer files rewritten)"
grep -q 'id=reruns' "$tmp/run/report.html" || fail "second run: the report lost the reruns"
# `rockfuzz report` on a rerun folder names the study's folder; on the study it keeps the reruns
"$bin" report "$tmp/run/nominal" > /dev/null 2> "$tmp/rep.txt" && fail "report of a rerun folder: exit 0"
grep -q "is a trajectory study's rerun" "$tmp/rep.txt" || fail "report of a rerun folder: $(cat "$tmp/rep.txt")"
cp "$tmp/run/report.html" "$tmp/report_before.html"
"$bin" report "$tmp/run" > /dev/null 2>&1 || fail "report of the study folder"
cmp -s "$tmp/run/report.html" "$tmp/report_before.html" || fail "rockfuzz report changed the study's report"

# main_output: the bound reruns follow it (no plots: no figures, the section is left out)
study chosen "main_output: runout_x_p95"
"$bin" run "$tmp/chosen.yaml" --out "$tmp/chosen" --quiet --no-plots > "$tmp/c.txt" 2>&1 || fail "main_output run: $(tail -3 "$tmp/c.txt")"
python3 - "$tmp/chosen" > "$tmp/check2.txt" 2>&1 <<'EOF' || fail "main_output: $(cat "$tmp/check2.txt")"
import json, sys
d = sys.argv[1]
r = json.load(open(d + "/result.json"))
assert r["main_output"] == "runout_x_p95", r["main_output"]
o = r["outputs"]["runout_x_p95"]
for sub, want in (("bound_lower", o["lower"][0]), ("bound_upper", o["upper"][0])):
    got = json.load(open(f"{d}/{sub}/result.json"))["statistics"]["runout_x"]["p95"]
    assert got == want, (sub, got, want)
h = open(d + "/report.html").read()
assert "<p class=headline><b>runout_x_p95</b>" in h, "headline is not the main output"
EOF

# a name that is not an output: file:line, the key, the value and the outputs there are
study wrong "main_output: barrier_energy_p95"
"$bin" run "$tmp/wrong.yaml" --out "$tmp/wrong" > /dev/null 2> "$tmp/w.err" && fail "an unknown main_output was accepted"
grep -q "wrong.yaml:3.*main_output.*'barrier_energy_p95' is not an output.*barrier_total_energy_p95" "$tmp/w.err" \
  || fail "unknown main_output: message $(cat "$tmp/w.err")"

[ $fails = 0 ] && echo "cli_trajectory_bounds: all checks passed"
