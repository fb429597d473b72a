#!/bin/bash
# cli_presets.sh - `rockfuzz presets` and the presets in a trajectory file
# (docs/presets.md): the list, one preset's values with units, fuzzy ranges
# and sources (and docs/presets.md's tables the same), a study's parameters
# and bindings (which the study parser takes), an unknown name refused (exit
# 2, the names listed); a trajectory file whose material is a preset with
# overrides bounces with the preset's R_n: the sliding block of cli_traj_ground.sh rebounds from the wall with R_n = 0.53
# (bedrock) and stops at 10 - (R_n v_w)^2 / (2 g tan 5 deg) = 7.31339 m, v_w^2 =
# 25 - 10 g tan 5 deg; an unknown preset in a file is refused with file:line.
# Usage: bash cli_presets.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

out=$("$bin" presets) || fail "presets: exit $?"
for p in bedrock talus colluvium loose_soil; do
    grep -q "^$p " <<< "$out" || fail "presets lists no $p: $out"
done
out=$("$bin" presets talus) || fail "presets talus: exit $?"
grep -Eq "^impact.layer_E +1e\+08 Pa +5e\+07 +2e\+08 +MAT" <<< "$out" || fail "talus layer_E: $out"
grep -Eq "^R_n +0.38 - +0.25 +0.5 +RF3D" <<< "$out" || fail "talus R_n: $out"
grep -Eq "^friction_angle +35 deg" <<< "$out" || fail "talus friction_angle: $out"
"$bin" presets granite > /dev/null 2> "$tmp/err"
rc=$?
[ $rc -eq 2 ] || fail "presets granite: exit $rc, expected 2"
grep -q "unknown preset 'granite'; the presets are bedrock, talus, colluvium, loose_soil" "$tmp/err" ||
    fail "presets granite: $(cat "$tmp/err")"

# docs/presets.md's tables are the program's output (every value, unit and support).
for p in bedrock talus colluvium loose_soil; do
    "$bin" presets $p | tail -n +4 | while read -r key value unit lo hi source; do
        grep -qF "| \`$key\` | $value | $unit | [$lo, $hi] | $source |" "$src/docs/presets.md" ||
            echo "docs/presets.md lacks $p: $key $value $unit [$lo, $hi] $source"
    done
done > "$tmp/docs"
[ -s "$tmp/docs" ] && fail "$(cat "$tmp/docs")"

# The study printed by --study runs (its parameters bound to the file's material).
cp "$src/examples/presets/slope.yaml" "$tmp/slope.yaml"
sed -i 's/^samples: 2000/samples: 20/' "$tmp/slope.yaml"
"$bin" presets talus --study talus > "$tmp/snippet" || fail "presets --study: exit $?"
{
    echo "name: snippet"
    echo "scheme: general"
    echo "levels: 2"
    sed -n '/^parameters:/,/^# under/p' "$tmp/snippet" | grep -v "^#"
    echo "model:"
    echo "  trajectory:"
    echo "    file: slope.yaml"
    sed -n '/^    bind:/,$p' "$tmp/snippet"
    echo "options: {left_right: false}"
} > "$tmp/study.yaml"
grep -q "talus_R_n: materials.talus.R_n" "$tmp/study.yaml" || fail "snippet binds no R_n: $(cat "$tmp/study.yaml")"
"$bin" run "$tmp/study.yaml" --out "$tmp/run" --quiet --no-plots > "$tmp/run.log" 2>&1 ||
    fail "the study of presets --study did not run: $(cat "$tmp/run.log")"

cat > "$tmp/step.yaml" <<'Y'
profile: {points: [[-20, 5], [0, 0], [10, 0], [10, 10], [20, 10]], material: rock}
materials: {rock: {preset: bedrock, friction_angle: 5, roughness: 0, rolling_resistance: 0}}
block: {shape: point, mass: 1000}
release: {x: 5, y: 0, vx: 5}
Y
out=$("$bin" trajectory "$tmp/step.yaml") || fail "step.yaml did not run"
grep -q "x = 7.31339 m, y = 0 m after 1 impact" <<< "$out" || fail "step with bedrock's R_n: $out"

printf 'profile: {points: [[0, 10], [20, 0]], material: rock}\nmaterials:\n  rock: granite\nblock: {shape: point, mass: 1}\nrelease: {x: 1, y: 11}\n' > "$tmp/bad.yaml"
"$bin" trajectory "$tmp/bad.yaml" > /dev/null 2> "$tmp/bad.err"
rc=$?
[ $rc -eq 1 ] || fail "unknown preset in a file: exit $rc, expected 1"
grep -q "bad.yaml:3: materials.rock = granite: unknown preset; the presets are bedrock, talus, colluvium, loose_soil" \
    "$tmp/bad.err" || fail "unknown preset in a file: $(cat "$tmp/bad.err")"

out=$("$bin" trajectory "$src/examples/presets/slope.yaml" --samples 50) || fail "examples/presets/slope.yaml did not run"
grep -q "stopped 50" <<< "$out" || fail "examples/presets/slope.yaml: $out"
exit $((fails > 0))
