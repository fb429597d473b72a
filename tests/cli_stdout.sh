#!/usr/bin/env bash
# cli_stdout.sh - a failed write to standard output is an error (issue 31,
# item 12): every command that prints (help, the JSON and readable results
# of trajectory, impact, material, the run summary, status, report) exits
# non-zero with a message on stderr when stdout is /dev/full, and exits 0 with
# the same arguments when stdout is /dev/null (so the failure is the write's).
# Usage: bash cli_stdout.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
[ -w /dev/full ] || { echo "SKIP: no /dev/full"; exit 0; }

# check ARGS...: exit 0 into /dev/null, non-zero with the message into /dev/full
check() {
    "$bin" "$@" > /dev/null 2> "$tmp/err0" || fail "'$*' > /dev/null: exit $? ($(head -c 300 "$tmp/err0"))"
    "$bin" "$@" > /dev/full 2> "$tmp/err"
    local rc=$?
    [ "$rc" -ne 0 ] || fail "'$*' > /dev/full: exit 0"
    grep -q "writing to standard output failed" "$tmp/err" || fail "'$*' > /dev/full: stderr: $(head -c 300 "$tmp/err")"
}

cat > "$tmp/t.yaml" <<EOF2
name: stdout
profile:
  points: [[-10, 20], [0, 20], [0, 0], [100, 0]]
  material: rock
materials:
  rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}
block: {shape: point, mass: 1000}
release: {x: -0.5, y: 20.5, vx: {uniform: [1, 5]}, vy: 2}
collectors: [{name: barrier, x: 6}]
samples: 20
seed: 3
EOF2
cat > "$tmp/s.yaml" <<EOF2
name: stdout
levels: 2
parameters:
  a: {tfn: [2, 1, 1]}
model:
  formula: {y: "a*a"}
EOF2

check --help
check --version
for c in run impact trajectory status report material; do check "$c" --help; done
check impact --solver hertz --json
check impact --solver hertz
check material --model von_mises --E 68.2e9 --poisson 0.25 --yield 150e6 --path uniaxial_strain --strain -0.01 --json
check trajectory "$tmp/t.yaml" --json
check trajectory "$tmp/t.yaml"
check run "$tmp/s.yaml" --out "$tmp/run" --quiet --force
check status "$tmp/run"
check report "$tmp/run"
"$bin" trajectory "$tmp/t.yaml" --out "$tmp/tr" --quiet || fail "trajectory --out"
check report "$tmp/tr"

# a long output (many buffers: the failure happens before the final flush)
check trajectory "$tmp/t.yaml" --json --samples 300 --max-trajectories 300

[ "$fails" -eq 0 ] && echo "cli_stdout: all passed"
exit $((fails > 0))
