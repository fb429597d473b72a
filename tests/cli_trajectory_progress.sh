#!/bin/bash
# cli_trajectory_progress.sh - `rockfuzz trajectory` draws the progress line
# of its Monte Carlo on stderr (trajectories done of all, share, elapsed, time
# left), erased at the end, when --progress asks (or on a terminal); nothing
# when stderr is piped without it; stdout (summary, JSON) is untouched by it.
# ROCKFUZZ_PROGRESS_DELAY=0 draws from the first trajectory on.
# Usage: bash cli_trajectory_progress.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
file=$src/examples/trajectory/slope.yaml

ROCKFUZZ_PROGRESS_DELAY=0 "$bin" trajectory "$file" --samples 3000 --threads 2 --progress \
  > "$tmp/out.txt" 2> "$tmp/err.txt" || fail "run with --progress"
python3 - "$tmp/err.txt" > "$tmp/check.txt" 2>&1 <<'EOF' || fail "progress line: $(cat "$tmp/check.txt")"
import re, sys
err = open(sys.argv[1], "rb").read().decode()
lines = re.findall(r"\r  trajectories: (\d+) of (\d+) \((\d+) %\), elapsed [^,]+, left ~([^\r\x1b]+)\x1b\[K", err)
assert lines, repr(err[:300])
done = [int(d) for d, n, p, left in lines]
for d, n, p, left in lines:
    assert int(n) == 3000 and 1 <= int(d) <= 3000, (d, n)
    assert int(p) == round(100 * int(d) / 3000), (d, p)  # the share printed %.0f
    assert left.endswith(" s") or left.endswith("min") or left == "?", left
assert done == sorted(done), done
assert err.endswith("\r\x1b[K"), repr(err[-20:])  # erased at the end
assert err.replace("\r\x1b[K", "").count("\r") == len(lines), "other text on stderr"
EOF
grep -q "barrier" "$tmp/out.txt" || fail "the summary is missing with --progress"

# piped stderr, no --progress: no line; --json keeps stdout pure JSON with --progress
ROCKFUZZ_PROGRESS_DELAY=0 "$bin" trajectory "$file" --samples 300 > /dev/null 2> "$tmp/quiet.txt" || fail "run"
[ -s "$tmp/quiet.txt" ] && fail "a progress line on a piped stderr without --progress: $(head -c 200 "$tmp/quiet.txt")"
ROCKFUZZ_PROGRESS_DELAY=0 "$bin" trajectory "$file" --samples 300 --json --progress > "$tmp/j.json" 2> "$tmp/j.err" \
  || fail "run --json --progress"
python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$tmp/j.json" 2> /dev/null || fail "--json output is not JSON"
grep -q "trajectories: " "$tmp/j.err" || fail "--json --progress: no line on stderr"

[ $fails = 0 ] && echo "cli_trajectory_progress: all checks passed"
