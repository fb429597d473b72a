#!/bin/bash
# cli_s5_studies.sh - guards the study files of S5 (examples/s5_v5/10/20.yaml,
# docs/studies.md) and of S5r (s5r_v*.yaml, S5 with a fuzzy friction): each must load (every input name known to the impact
# model, every support admissible for its material) and plan the documented
# 1 + m * 2^n = 1 + 4 * 2^5 = 129 evaluations.  Nothing is evaluated: the run
# is stopped by --max-evaluations before the first model call, which happens
# only after the study and the model have been loaded and checked.  A
# renamed input is refused (negative control).  One nominal evaluation of
# s5_v5 checks the energy bound R_n^2 + W_p/KE <= 1 (+ the energy error).
# Usage: bash cli_s5_studies.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

for v in 5 10 20; do
    f="$src/examples/s5_v$v.yaml"
    [ -f "$f" ] || { fail "$f missing"; continue; }
    "$bin" run "$f" --out "$tmp/o$v" --quiet --no-plots --max-evaluations 128 > /dev/null 2> "$tmp/e$v"
    rc=$?
    [ $rc -eq 1 ] || fail "s5_v$v: exit $rc, expected 1 (stopped by the cap): $(cat "$tmp/e$v")"
    grep -q "needs 129 distinct model evaluations" "$tmp/e$v" \
        || fail "s5_v$v: did not load and plan 129 evaluations: $(cat "$tmp/e$v")"
    grep -q "velocity: $v\$" "$f" || fail "s5_v$v: the file's crisp velocity is not $v m/s"
    # the soil contact outlasts the P wave's round trip: absorbing (the default auto's choice, pinned)
    grep -q "^    boundary: absorbing\$" "$f" || fail "s5_v$v: the boundary is not pinned absorbing"
    grep -q "^    gravity: 0" "$f" && fail "s5_v$v: pins gravity 0 (the default is auto = 9.81 for the plastic layer)"
    [ -f "$tmp/o$v/result.json" ] && fail "s5_v$v: wrote result.json without evaluating"
done

# S5r (the rough block): the S5 files with a sixth fuzzy input, friction: 1 + 4 * 2^6 = 257
for v in 5 10 20; do
    f="$src/examples/s5r_v$v.yaml"
    [ -f "$f" ] || { fail "$f missing"; continue; }
    "$bin" run "$f" --out "$tmp/r$v" --quiet --no-plots --max-evaluations 256 > /dev/null 2> "$tmp/r$v.err"
    grep -q "needs 257 distinct model evaluations" "$tmp/r$v.err" \
        || fail "s5r_v$v: did not load and plan 257 evaluations: $(cat "$tmp/r$v.err")"
    diff <(grep -v -e '^#' -e '^name:' -e '^  friction:' "$f") \
         <(grep -v -e '^#' -e '^name:' "$src/examples/s5_v$v.yaml") > /dev/null \
        || fail "s5r_v$v: differs from s5_v$v.yaml in more than its friction"
done

# negative control: the same file with one input renamed must be refused at load
sed 's/^  layer_cap_pressure:/  layer_cap_presure:/' "$src/examples/s5_v10.yaml" > "$tmp/bad.yaml"
"$bin" run "$tmp/bad.yaml" --out "$tmp/bad" --quiet --no-plots --max-evaluations 128 > /dev/null 2> "$tmp/bad.err"
grep -q "is not an input of the impact model" "$tmp/bad.err" || fail "renamed input not refused: $(cat "$tmp/bad.err")"

# the nominal point of s5_v5 (~1 s): energy cannot be created (without gravity, whose work
# would add to the bound: test_fem_gravity checks the closure with it); the default boundary
# (auto: absorbing for the layer) sends no reflected wave back into the contact: no warning
"$bin" impact --gravity 0 --boulder-material rigid --radius 0.5 --velocity 5 --layer-thickness 1.0 \
    --layer-material drucker_prager --layer-density 1900 --layer-E 100e6 --layer-poisson 0.3 \
    --layer-cohesion 10e3 --layer-friction-angle 40 --layer-dilatancy-angle 5 \
    --layer-cap-pressure 200e3 --layer-cap-hardening 40e6 --refinement 3 \
    --json > "$tmp/nom.json" 2> "$tmp/nom.err" || fail "nominal s5_v5 impact failed: $(cat "$tmp/nom.err")"
grep -q "reflected" "$tmp/nom.err" && fail "nominal s5_v5, default boundary: reflection warning: $(cat "$tmp/nom.err")"
python3 - "$tmp/nom.json" <<'EOF' || fail "nominal s5_v5 energy bound"
import json, sys
d = json.load(open(sys.argv[1]))
rn, wp, err = d["R_n"], d["plastic_work"], abs(d["energy_error"])
ok = 0 < rn < 1 and 0 < wp < 1 and rn * rn + wp <= 1 + err + 1e-12
if not ok:
    print("R_n = %g, W_p/KE = %g, energy error %g" % (rn, wp, err), file=sys.stderr)
sys.exit(0 if ok else 1)
EOF

[ $fails -eq 0 ] && echo "cli_s5_studies: all passed"
exit $((fails > 0))
