#!/usr/bin/env bash
# cli_threads.sh - one thread option on every command that runs threads
# (issue 27, item 7): `--threads N` on run, impact and trajectory, in
# [0, 1024] with 0 the automatic default; `run --jobs N` stays an alias that
# gives the same run as --threads; out-of-range counts are refused with the
# option and value named (exit 2); --help says so.
# Usage: bash cli_threads.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

cat > "$tmp/s.yaml" <<EOF2
name: threads
levels: 3
parameters:
  a: {tfn: [2, 1, 1]}
  b: {tfn: [3, 1, 2]}
model:
  formula: {y: "a*b + b"}
options: {left_right: false}
EOF2
cat > "$tmp/t.yaml" <<EOF2
name: threads
profile:
  points: [[-10, 20], [0, 20], [0, 0], [100, 0]]
  material: rock
materials:
  rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}
block: {shape: point, mass: 1000}
release: {x: -0.5, y: 20.5, vx: {uniform: [1, 5]}, vy: 2}
collectors: [{name: barrier, x: 6}]
samples: 50
seed: 3
EOF2

for c in run impact trajectory; do
    "$bin" "$c" --help | grep -q -- "--threads N.*0\.\.1024" || fail "$c --help: no '--threads N ... 0..1024'"
done
"$bin" run --help | grep -q -- "--jobs N is the same option" || fail "run --help does not name --jobs as the alias"

# run: --threads and --jobs are the same option (same cuts)
"$bin" run "$tmp/s.yaml" --out "$tmp/t2" --threads 2 --quiet --no-plots > /dev/null 2> "$tmp/e" || fail "run --threads 2: $(cat "$tmp/e")"
"$bin" run "$tmp/s.yaml" --out "$tmp/j2" --jobs 2 --quiet --no-plots > /dev/null 2> "$tmp/e" || fail "run --jobs 2: $(cat "$tmp/e")"
"$bin" run "$tmp/s.yaml" --out "$tmp/t0" --threads 0 --quiet --no-plots > /dev/null 2> "$tmp/e" || fail "run --threads 0: $(cat "$tmp/e")"
for d in j2 t0; do
    cmp -s "$tmp/t2/cuts_y.csv" "$tmp/$d/cuts_y.csv" || fail "run: cuts of $d differ from --threads 2"
done
grep -q '"jobs": 2' "$tmp/t2/result.json" || fail "run --threads 2: result.json does not record 2 threads"

# trajectory and impact: 0 is the default, the same result as an explicit count
"$bin" trajectory "$tmp/t.yaml" --json --threads 0 | sed 's/"wall_seconds".*//' > "$tmp/a" || fail "trajectory --threads 0"
"$bin" trajectory "$tmp/t.yaml" --json --threads 2 | sed 's/"wall_seconds".*//' > "$tmp/b" || fail "trajectory --threads 2"
cmp -s "$tmp/a" "$tmp/b" || fail "trajectory: --threads 0 and 2 differ"
"$bin" impact --solver hertz --json --threads 0 > /dev/null || fail "impact --threads 0 refused"

# out of range: refused with the option and value
for c in "run $tmp/s.yaml --out $tmp/x --threads" "run $tmp/s.yaml --out $tmp/x --jobs" "impact --threads" \
         "trajectory $tmp/t.yaml --threads"; do
    opt=${c##* }
    for v in 1025 -1 2x 99999999999999999999; do
        # shellcheck disable=SC2086
        "$bin" $c "$v" > /dev/null 2> "$tmp/e"; rc=$?
        [ "$rc" -eq 2 ] || fail "'$c $v': exit $rc, want 2"
        grep -q -- "$opt.*$v" "$tmp/e" || fail "'$c $v': message lacks the option and value: $(cat "$tmp/e")"
    done
done
[ -e "$tmp/x" ] && fail "a refused run created its folder"

[ "$fails" -eq 0 ] && echo "cli_threads: all passed"
exit $((fails > 0))
