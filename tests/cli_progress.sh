#!/usr/bin/env bash
# cli_progress.sh - the progress line of `rockfuzz impact` FE runs (issue 27,
# item 7): drawn on a terminal, not with --json nor when stderr is not a
# terminal unless --progress asks for it; it names a time left, is redrawn at
# most 4 times a second, is erased at the end, and changes no result.  The
# terminal is a pty from script(1).  `rockfuzz run` follows the same rule.
# Usage: bash cli_progress.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
fem=(impact --solver fem --refinement 14) # an axisymmetric run of about 1 s
# the first line after 0.1 s instead of 1 s, so that the run draws a few lines on a fast machine too
export ROCKFUZZ_PROGRESS_DELAY=0.1

# piped, --progress: the line, its time left, erased at the end; same JSON as without it
start=$(date +%s.%N)
"$bin" "${fem[@]}" --json --progress > "$tmp/p.json" 2> "$tmp/p.err" || fail "--progress run: $(tr '\r' '\n' < "$tmp/p.err" | tail -2)"
wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
"$bin" "${fem[@]}" --json > "$tmp/q.json" 2> "$tmp/q.err" || fail "quiet run"
[ -s "$tmp/q.err" ] && fail "piped stderr without --progress is not empty: $(head -c 200 "$tmp/q.err")"
[ "$(sed 's/, "wall_seconds".*//' "$tmp/p.json")" = "$(sed 's/, "wall_seconds".*//' "$tmp/q.json")" ] ||
    fail "--progress changed the result"
draws=$(grep -o $'\r  fem impact: simulated [0-9.e+-]* of ~[0-9.e+-]* s ([0-9]* %), elapsed [0-9]* s, left ~[0-9]* s' "$tmp/p.err" | wc -l)
[ "$draws" -ge 2 ] || fail "--progress drew $draws lines with a time left: $(tr '\r' '\n' < "$tmp/p.err" | head -3)"
awk -v n="$draws" -v w="$wall" 'BEGIN { exit !(n <= 4 * w + 1) }' || fail "$draws redraws in $wall s: more than 4 a second"
[ "$(tail -c 4 "$tmp/p.err" | od -An -c | tr -d ' ')" = '\r033[K' ] || fail "the line is not erased at the end"
# the share done never exceeds 100 % and the last drawn one is past half
tr '\r' '\n' < "$tmp/p.err" | sed -n 's/.*(\([0-9]*\) %).*/\1/p' > "$tmp/share"
awk '$1 > 100 { bad = 1 } END { exit bad || !($1 >= 50) }' "$tmp/share" || fail "shares done: $(tr '\n' ' ' < "$tmp/share")"

# on a terminal: drawn without --json, not with it
if script -qec true /dev/null > /dev/null 2>&1; then
    script -qec "'$bin' ${fem[*]}" /dev/null > "$tmp/tty.out" 2>&1
    grep -q "fem impact: simulated" "$tmp/tty.out" || fail "no progress line on a terminal"
    grep -q "max contact force" "$tmp/tty.out" || fail "no summary on a terminal"
    script -qec "'$bin' ${fem[*]} --json" /dev/null > "$tmp/ttyj.out" 2>&1
    grep -q "fem impact: simulated" "$tmp/ttyj.out" && fail "a progress line with --json on a terminal"
else
    echo "note: script(1) cannot make a terminal here; the terminal cases are skipped"
fi

# rockfuzz run: no line when piped, the line with --progress
cat > "$tmp/s.yaml" <<EOF2
name: progress
levels: 2
parameters:
  a: {tfn: [2, 1, 1]}
model:
  formula: {y: "a*a"}
EOF2
"$bin" run "$tmp/s.yaml" --out "$tmp/r1" --no-plots > /dev/null 2> "$tmp/r1.err" || fail "run"
grep -q "evaluations" "$tmp/r1.err" && fail "run draws its progress line when piped"
"$bin" run "$tmp/s.yaml" --out "$tmp/r2" --no-plots --progress > /dev/null 2> "$tmp/r2.err" || fail "run --progress"
grep -q "evaluations .*left" "$tmp/r2.err" || fail "run --progress: no line"

[ "$fails" -eq 0 ] && echo "cli_progress: all passed"
exit $((fails > 0))
