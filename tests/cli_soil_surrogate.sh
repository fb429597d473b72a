#!/bin/bash
# cli_soil_surrogate.sh - a study that binds a material's impact-model inputs
# (examples/trajectory_soil_fuzzy_mdr.yaml, 200 trajectories a point): the
# run builds the impact surrogate once, reports its error in a field of its
# own of result.json ("impact_surrogate_error", not a warning), in report.html
# and on the console; a second run into the same folder computes no
# impact (every impact and check run from the store) and still reports the
# error.  Usage: bash cli_soil_surrogate.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

mkdir -p "$tmp/trajectory"
cp "$src/examples/trajectory/soil_fuzzy_mdr.yaml" "$tmp/trajectory/"
sed 's/samples: 2000/samples: 200/' "$src/examples/trajectory_soil_fuzzy_mdr.yaml" > "$tmp/study.yaml"
grep -q "samples: 200$" "$tmp/study.yaml" || fail "the study's samples were not reduced"

"$bin" run "$tmp/study.yaml" --out "$tmp/out" > "$tmp/run1.txt" 2>&1 || fail "first run: $(tail -3 "$tmp/run1.txt")"
grep -q '"impact_surrogate_error": "impact surrogate error R_n [0-9.e-]*, R_t [0-9.e-]* (largest miss at 16 independent' \
    "$tmp/out/result.json" || fail "result.json lacks the surrogate's error"
grep -q '"model: impact surrogate error' "$tmp/out/result.json" && fail "the surrogate's error is still a warning"
grep -q "<b>Impact surrogate.</b> impact surrogate error R_n" "$tmp/out/report.html" || fail "report.html lacks the error"
grep -q "Impact surrogate: impact surrogate error R_n" "$tmp/run1.txt" || fail "console lacks the error"
grep -Eq "grid [0-9]+ x [0-9]+ nodes, [0-9]+ tables, [1-9][0-9]* impacts computed" "$tmp/run1.txt" ||
    fail "first run computed no impact: $(grep 'surrogate error' "$tmp/run1.txt")"

"$bin" run "$tmp/study.yaml" --out "$tmp/out" > "$tmp/run2.txt" 2>&1 || fail "second run: $(tail -3 "$tmp/run2.txt")"
grep -q "tables, 0 impacts computed" "$tmp/run2.txt" ||
    fail "second run computed impacts: $(grep 'surrogate error' "$tmp/run2.txt")"
grep -q "(0 evaluated" "$tmp/run2.txt" || fail "second run evaluated points: $(grep Wall "$tmp/run2.txt")"
grep -q '"impact_surrogate_error": "impact surrogate error R_n' "$tmp/out/result.json" ||
    fail "second result.json lacks the error"

[ "$fails" -eq 0 ] && echo "cli_soil_surrogate: OK"
exit $((fails > 0))
