#!/bin/bash
# cli_bind.sh - `bind:` and the scheme through `rockfuzz run`: a program
# parameter bound to a list with an affine entry gives the closed-form cuts
# (y = p, w = 2 p + 1), the console and result.json say which scheme ran and
# why (general by default for a program, reduced when the file says so), the
# report's run table shows it, and an input bound twice is refused at load
# (exit 1, file:line, nothing written).
# Usage: bash cli_bind.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

body='levels: 2
parameters:
  p: {tfn: [1, 0.5, 0.5]}
model:
  program:
    argv: [printf, "y = %s\nw = %s\n", "{A}", "{C}"]
    outputs: {y: {}, w: {}}
    bind: {p: [A, {to: C, scale: 2, offset: 1}]}'
printf '%s\n' "$body" > "$tmp/g.yaml"
printf 'scheme: reduced\n%s\n' "$body" > "$tmp/r.yaml"

"$bin" run "$tmp/g.yaml" --out "$tmp/g" --quiet > "$tmp/g.out" 2> "$tmp/g.err" || fail "program run: $(cat "$tmp/g.err")"
grep -q "^Scheme: general, default for a program model" "$tmp/g.out" || fail "no default-scheme line: $(cat "$tmp/g.out")"
python3 - "$tmp/g/result.json" <<'EOF2' || fail "program result.json"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["scheme"] == "general", r["scheme"]
assert "default for a program model" in r["scheme_reason"], r["scheme_reason"]
w, y = r["outputs"]["w"], r["outputs"]["y"]
assert w["lower"] == [2, 2.5, 3] and w["upper"] == [4, 3.5, 3], w
assert y["lower"] == [0.5, 0.75, 1] and y["upper"] == [1.5, 1.25, 1], y
EOF2
grep -q "why this scheme" "$tmp/g/report.html" || fail "report.html does not say why the scheme ran"
grep -q "default for a program model" "$tmp/g/report.html" || fail "report.html lacks the scheme's reason"

"$bin" run "$tmp/r.yaml" --out "$tmp/r" --quiet > "$tmp/r.out" 2> "$tmp/r.err" || fail "reduced run: $(cat "$tmp/r.err")"
grep -q "^Scheme: reduced, set in the study file" "$tmp/r.out" || fail "explicit scheme line: $(cat "$tmp/r.out")"
python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert r["scheme"] == "reduced", r' \
    "$tmp/r/result.json" || fail "explicit reduced scheme not run"

cat > "$tmp/d.yaml" <<'EOF2'
parameters:
  p: {tfn: [1, 0.5, 0.5]}
  q: {tfn: [1, 0.5, 0.5]}
model:
  program:
    argv: [printf, "y = %s\n", "{A}"]
    outputs: {y: {}}
    bind: {p: A, q: [A]}
EOF2
"$bin" run "$tmp/d.yaml" --out "$tmp/d" --quiet > /dev/null 2> "$tmp/d.err"
rc=$?
[ "$rc" -eq 1 ] || fail "input bound twice: exit $rc, expected 1"
grep -q "d.yaml:8: model.program.bind.q\[0\] = A: A is already driven by parameter p" "$tmp/d.err" ||
    fail "input bound twice: $(cat "$tmp/d.err")"
[ ! -e "$tmp/d/result.json" ] || fail "a refused study wrote result.json"

# ---- a trajectory study's nominal rerun drives the bound inputs: rock R_n = 0.35, talus R_n = 0.35 * 0.5 ----
two='profile:
  points: [[0, 20], [10, 10], [20, 5], [40, 0]]
  materials: [rock, talus, talus]
block: {shape: point, mass: 100}
release: {x: 1, y: 30, vx: {uniform: [2, 5]}}
collectors: [{name: c, x: 15}]
samples: 100
seed: 5'
printf 'name: two\n%s\nmaterials:\n  rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}\n  talus: {R_n: 0.3, R_t: 0.75, friction_angle: 32}\n' \
    "$two" > "$tmp/two.yaml"
printf 'name: two\n%s\nmaterials:\n  rock: {R_n: 0.35, R_t: 0.8, friction_angle: 30}\n  talus: {R_n: 0.175, R_t: 0.75, friction_angle: 32}\n' \
    "$two" > "$tmp/direct.yaml"
cat > "$tmp/t.yaml" <<'EOF2'
levels: 1
parameters:
  Rn: {tfn: [0.35, 0.05, 0.05]}
model:
  trajectory:
    file: two.yaml
    bind: {Rn: [materials.rock.R_n, {to: materials.talus.R_n, scale: 0.5}]}
options: {left_right: false}
EOF2
"$bin" run "$tmp/t.yaml" --out "$tmp/t" --quiet --no-plots > "$tmp/t.out" 2>&1 || fail "trajectory study: $(tail -3 "$tmp/t.out")"
"$bin" trajectory "$tmp/direct.yaml" --out "$tmp/direct" --quiet > /dev/null 2>&1 || fail "direct trajectory run"
for f in samples.csv crossings.csv; do
    cmp -s "$tmp/t/nominal/$f" "$tmp/direct/$f" || fail "nominal $f differs from the inputs set directly"
done

[ "$fails" -eq 0 ] && echo "cli_bind: all checks passed"
exit $((fails > 0))
