#!/bin/bash
# cli_traj_ground.sh - `rockfuzz trajectory` on the cases of issue 31 items
# 1-3: the block sliding into a vertical step stops on the floor (7.609 m:
# 10 - (R_n v_w)^2 / (2 g tan 5 deg)), the 45 deg V-notch stops at its vertex,
# and a vertex at 3.4e38 m (a DEM's no-data) is refused with file:line, the
# point and its value, exit 1.  Usage: bash cli_traj_ground.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

cat > "$tmp/step.yaml" <<'Y'
profile: {points: [[-20, 5], [0, 0], [10, 0], [10, 10], [20, 10]], material: rock}
materials: {rock: {R_n: 0.5, R_t: 0.8, friction_angle: 5}}
block: {shape: point, mass: 1000}
release: {x: 5, y: 0, vx: 5}
collectors: [{name: a, x: 2}, {name: b, x: -10}]
Y
out=$("$bin" trajectory "$tmp/step.yaml") || fail "step.yaml did not run"
grep -q "stopped at t = 3.46523 s, x = 7.60893 m, y = 0 m after 1 impact" <<< "$out" || fail "step: $out"
grep -q "collector a (x = 2 m): reach probability 0" <<< "$out" || fail "step reached a: $out"

cat > "$tmp/notch.yaml" <<'Y'
profile: {points: [[-10, 10], [0, 0], [10, 10]], material: rock}
materials: {rock: {R_n: 0.3, R_t: 1, friction_angle: 30}}
block: {shape: point, mass: 1000}
release: {x: -9, y: 9}
Y
out=$("$bin" trajectory "$tmp/notch.yaml") || fail "notch.yaml did not run"
grep -q "stopped 1, exited 0, step_limit 0" <<< "$out" || fail "notch: $out"
grep -q "x = 0 m, y = 0 m" <<< "$out" || fail "notch rest: $out"

cat > "$tmp/far.yaml" <<'Y'
profile: {points: [[0, 10], [100, 0], [200, 3.4e38]], material: rock}
materials: {rock: {R_n: 0.3, R_t: 0.8}}
block: {shape: point, mass: 1}
release: {x: 2, y: 12}
Y
"$bin" trajectory "$tmp/far.yaml" > /dev/null 2> "$tmp/far.err"
rc=$?
[ $rc -eq 1 ] || fail "far vertex: exit $rc, expected 1"
grep -q "far.yaml:1: profile.points\[2\] = \[200, 3.4e+38\]: beyond 1e+07 m" "$tmp/far.err" || fail "far: $(cat "$tmp/far.err")"

[ $fails -eq 0 ] && echo "cli_traj_ground: all passed"
exit $fails
