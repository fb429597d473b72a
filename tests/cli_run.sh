#!/bin/bash
# cli_run.sh - `rockfuzz run` end to end: the tm_spec test vectors 6.1 and 6.4
# through the command line (result.json read with python3's json module), the
# output files, and bad inputs (non-zero exit, file:line on stderr, no result.json).
# Usage: bash cli_run.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

# ---- 6.1: product, reduced form, no left/right grid: 17 evaluations ----
cat > "$tmp/a.yaml" <<'EOF'
name: vector-A
scheme: reduced
levels: 4
parameters:
  x1: {tfn: [2, 1, 1]}
  x2: {tfn: [3, 1, 2]}
  x3: {crisp: 7}
model:
  formula: {f: "x1*x2"}
options: {left_right: false, jobs: 2}
EOF
"$bin" run "$tmp/a.yaml" --out "$tmp/a" --quiet > "$tmp/a.out" 2> "$tmp/a.err" || fail "vector A run: $(cat "$tmp/a.err")"
grep -q "17 requested" "$tmp/a.out" || fail "vector A: plan line without '17 requested'"
grep -q "not checked" "$tmp/a.out" || fail "vector A: monotonicity should be 'not checked' without left_right"
python3 - "$tmp/a/result.json" <<'EOF' || fail "vector A result.json"
import json, sys
r = json.load(open(sys.argv[1]))
def close(a, b, rtol=1e-12):
    return abs(a - b) <= rtol * max(abs(a), abs(b), 1e-300)
f = r["outputs"]["f"]
lo = [2, 2.8125, 3.75, 4.8125, 6]; hi = [15, 12.375, 10, 7.875, 6]
assert f["mu"] == [0, 0.25, 0.5, 0.75, 1], f["mu"]
assert all(close(a, b) for a, b in zip(f["lower"], lo)), f["lower"]
assert all(close(a, b) for a, b in zip(f["upper"], hi)), f["upper"]
assert close(f["nominal"], 6)
inf = f["influence"]
assert close(inf["x1"]["rho"], 0.52, 1e-9) and close(inf["x2"]["rho"], 0.48, 1e-9), inf
assert inf["x3"]["rho"] is None, "crisp input: rho must be null (NaN)"
assert inf["x1"]["rho_left"] is None, "no left/right grid: rho_left must be null"
assert r["evaluations"]["requested"] == 17, r["evaluations"]
assert r["evaluations"]["distinct"] <= 17
assert r["scheme"] == "reduced" and r["levels"] == 4 and r["name"] == "vector-A"
assert "version" in r and "wall_seconds" in r
assert r["inputs"]["x2"]["lower"][0] == 2 and r["inputs"]["x2"]["upper"][0] == 5
EOF
for f in result.json cuts_f.csv influence_f.csv inputs.csv input_x1.png input_x1.svg input_x2.png output_f.png \
         output_f.svg influence_f.png influence_f.svg; do
    [ -s "$tmp/a/$f" ] || fail "vector A: $f missing or empty"
done
# without the left/right grid the left/right influence plot would be empty: not drawn
[ -e "$tmp/a/influence_lr_f.png" ] && fail "vector A: an empty influence_lr_f.png was drawn"
[ -e "$tmp/a/result.json.tmp" ] && fail "vector A: result.json.tmp left behind"
head -1 "$tmp/a/cuts_f.csv" | grep -qx "mu,lower,upper" || fail "cuts_f.csv header"

# ---- 6.1 with the left/right grid: LR measures; counts include the three-point grid ----
sed 's/left_right: false/left_right: true/' "$tmp/a.yaml" > "$tmp/alr.yaml"
"$bin" run "$tmp/alr.yaml" --out "$tmp/alr" --quiet --no-plots > "$tmp/alr.out" 2>&1 || fail "vector A (LR) run"
ls "$tmp/alr"/*.png > /dev/null 2>&1 && fail "--no-plots still wrote PNG files"
python3 - "$tmp/alr/result.json" <<'EOF' || fail "vector A (LR) result.json"
import json, sys
r = json.load(open(sys.argv[1]))
def close(a, b, rtol):
    return abs(a - b) <= rtol * max(abs(a), abs(b))
f = r["outputs"]["f"]; inf = f["influence"]
assert close(inf["x1"]["rho_left"], 0.259197, 1e-5) and close(inf["x2"]["rho_left"], 0.160535, 1e-5), inf
assert close(inf["x1"]["rho_right"], 0.259197, 1e-5) and close(inf["x2"]["rho_right"], 0.321070, 1e-5), inf
assert close(f["degree_of_uncertainty"], 1.057292, 1e-5), f["degree_of_uncertainty"]
assert r["evaluations"]["requested"] > 17, r["evaluations"]
assert r["evaluations"]["left_right"] > 0, r["evaluations"]
EOF

# ---- 6.4: linear model ----
cat > "$tmp/l.yaml" <<'EOF'
scheme: general
levels: 4
parameters:
  x1: {tfn: [1, 0.5, 0.5]}
  x2: {tfn: [2, 0.2, 0.4]}
model:
  formula: {f: "2*x1 - 3*x2"}
EOF
"$bin" run "$tmp/l.yaml" --out "$tmp/l" --jobs 1 --quiet --no-plots > /dev/null 2>&1 || fail "vector L run"
python3 - "$tmp/l/result.json" <<'EOF' || fail "vector L result.json"
import json, sys
r = json.load(open(sys.argv[1]))
def close(a, b, rtol):
    return abs(a - b) <= rtol * max(abs(a), abs(b))
f = r["outputs"]["f"]; inf = f["influence"]
lo = [-6.2, -5.65, -5.1, -4.55, -4]; hi = [-2.4, -2.8, -3.2, -3.6, -4]
assert all(close(a, b, 1e-12) for a, b in zip(f["lower"], lo)), f["lower"]
assert all(close(a, b, 1e-12) for a, b in zip(f["upper"], hi)), f["upper"]
assert close(inf["x1"]["rho"], 0.526316, 1e-5) and close(inf["x2"]["rho"], 0.473684, 1e-5), inf
assert close(inf["x1"]["rho_left"], 0.263158, 1e-5) and close(inf["x2"]["rho_left"], 0.315789, 1e-5), inf
assert close(inf["x1"]["rho_right"], 0.263158, 1e-5) and close(inf["x2"]["rho_right"], 0.157895, 1e-5), inf
assert close(f["degree_of_uncertainty"], 0.475, 1e-9), f["degree_of_uncertainty"]
assert r["scheme"] == "general"
EOF

# ---- same result whatever the thread count ----
"$bin" run "$tmp/l.yaml" --out "$tmp/l2" --jobs 2 --quiet --no-plots > /dev/null 2>&1 || fail "vector L, 2 jobs"
python3 - "$tmp/l/result.json" "$tmp/l2/result.json" <<'EOF' || fail "results differ between 1 and 2 jobs"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["outputs"] == b["outputs"]
EOF

# ---- the shipped examples run ----
# default.yaml is the quick-start trajectory study (395 TM points): here only that it loads,
# builds its model and is stopped by the evaluation cap before any run
"$bin" run "$src/examples/default.yaml" --out "$tmp/ex_default" --quiet --max-evaluations 1 > /dev/null 2> "$tmp/ex.err" \
    && fail "examples/default.yaml ran past --max-evaluations 1"
grep -q "more than the cap of 1" "$tmp/ex.err" || fail "examples/default.yaml: $(cat "$tmp/ex.err")"
# an output folder whose parents do not exist yet is created (mkdir -p)
"$bin" run "$src/examples/product.yaml" --out "$tmp/nested/a/b" --quiet --no-plots > /dev/null 2> "$tmp/ex.err" \
    || fail "nested --out: $(cat "$tmp/ex.err")"
[ -s "$tmp/nested/a/b/result.json" ] || fail "nested --out: no result.json"
for ex in product s1_hunter; do
    "$bin" run "$src/examples/$ex.yaml" --out "$tmp/ex_$ex" --quiet --no-plots > /dev/null 2> "$tmp/ex.err" \
        || fail "examples/$ex.yaml: $(cat "$tmp/ex.err")"
done

# ---- bad inputs: non-zero exit, file:line, no result.json ----
expect_error() { # name pattern yaml
    local name=$1 pattern=$2
    printf '%s' "$3" > "$tmp/$name.yaml"
    if "$bin" run "$tmp/$name.yaml" --out "$tmp/$name" --quiet > /dev/null 2> "$tmp/$name.err"; then
        fail "$name: exit status 0"
    fi
    grep -q -- "$pattern" "$tmp/$name.err" || fail "$name: stderr lacks '$pattern': $(cat "$tmp/$name.err")"
    [ -e "$tmp/$name/result.json" ] && fail "$name: result.json written"
    return 0
}
expect_error bad_key "bad_key.yaml:5: colour" $'levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {f: "x1"}}\ncolour: red\n'
expect_error bad_dev "bad_dev.yaml:3: parameters.x1.tfn\[1\] = -1" $'levels: 4\nparameters:\n  x1: {tfn: [2, -1, 1]}\nmodel: {formula: {f: "x1"}}\n'
expect_error bad_formula "bad_formula.yaml:5: model.formula.f" $'levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  formula: {f: "x1 + nope"}\n'
expect_error bad_levels "bad_levels.yaml:1: levels = 0" $'levels: 0\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {f: "x1"}}\n'

# the cap stops the run before any evaluation
if "$bin" run "$tmp/l.yaml" --out "$tmp/capped" --max-evaluations 5 --quiet > /dev/null 2> "$tmp/cap.err"; then
    fail "cap: exit status 0"
fi
grep -q "cap" "$tmp/cap.err" || fail "cap: message lacks 'cap': $(cat "$tmp/cap.err")"
[ -e "$tmp/capped/result.json" ] && fail "cap: result.json written"

# a failing model: non-zero exit; the result.json of the last complete run stays until a new
# complete run replaces it (issue 12: a failed rerun must not lose the previous result)
mkdir -p "$tmp/failing" && echo '{"stale": true}' > "$tmp/failing/result.json"
cat > "$tmp/failing.yaml" <<'EOF'
levels: 2
parameters:
  x1: {tfn: [2, 1, 1]}
model:
  program: {argv: [sh, -c, "exit 3"], outputs: {f: {}}, timeout: 10}
EOF
if "$bin" run "$tmp/failing.yaml" --out "$tmp/failing" --quiet > /dev/null 2> "$tmp/failing.err"; then
    fail "failing model: exit status 0"
fi
[ -s "$tmp/failing.err" ] || fail "failing model: no message"
grep -q '"stale": true' "$tmp/failing/result.json" || fail "failing model: the previous result.json was lost"

# usage errors
"$bin" run > /dev/null 2>&1 && fail "run without arguments: exit status 0"
"$bin" run "$tmp/l.yaml" > /dev/null 2>&1 && fail "run without --out: exit status 0"
"$bin" run "$tmp/l.yaml" --out "$tmp/x" --bogus > /dev/null 2>&1 && fail "unknown option: exit status 0"
"$bin" run "$tmp/missing.yaml" --out "$tmp/x" > /dev/null 2> "$tmp/missing.err" && fail "missing file: exit status 0"
grep -q "missing.yaml" "$tmp/missing.err" || fail "missing file: message lacks the file name"

# help documents every option, the file format and the outputs
"$bin" run --help > "$tmp/help" || fail "run --help exit status"
for word in --out --threads --jobs --max-evaluations --quiet --progress --no-plots scheme levels parameters tfn trapezoid \
            interval gaussian crisp points cuts formula program impact result.json cuts_ influence_ Units; do
    grep -q -- "$word" "$tmp/help" || fail "run --help lacks '$word'"
done

if [ "$fails" -ne 0 ]; then
    echo "$fails check(s) failed" >&2
    exit 1
fi
echo "cli_run: all checks passed"
