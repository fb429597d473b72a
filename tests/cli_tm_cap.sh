#!/bin/bash
# cli_tm_cap.sh - `rockfuzz run` refuses a study whose grids exceed the
# evaluation cap before it builds them (issue 12): a general-form study with
# 8 inputs at m = 10 (11^8 points at mu = 0) and a reduced one with 14 inputs
# whose three-point left/right grid explodes (3^14).  Both run under a 300 MB
# address-space limit and a 20 s timeout; the message names the grid and
# what to change, the exit status is non-zero.
# Usage: bash cli_tm_cap.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

# study NAME SCHEME N: N tfn inputs, a formula summing them
study() {
    {
        echo "name: $1"
        echo "scheme: $2"
        echo "levels: 10"
        echo "parameters:"
        sum=""
        for i in $(seq 1 "$3"); do
            echo "  x$i: {tfn: [$i, 0.1, 0.2]}"
            sum="$sum${sum:++}x$i"
        done
        echo "model: {formula: {y: \"$sum\"}}"
    } > "$tmp/$1.yaml"
}

# refused NAME PATTERN...: the run fails within the limits and stderr has every pattern
refused() {
    local name=$1
    shift
    # sanitizer builds reserve terabytes of shadow memory: no address-space limit there
    local limit="ulimit -v 300000;"
    if ldd "$bin" 2>/dev/null | grep -q libasan || [ -n "${ASAN_OPTIONS:-}" ]; then limit=""; fi
    if bash -c "$limit exec timeout 20 \"\$0\" run \"\$1\" --out \"\$2\" --quiet" "$bin" "$tmp/$name.yaml" \
        "$tmp/$name.out" > "$tmp/$name.stdout" 2> "$tmp/$name.err"; then
        fail "$name: the run was not refused"
        return
    fi
    for p in "$@"; do
        grep -qF -- "$p" "$tmp/$name.err" || fail "$name: stderr lacks '$p': $(cat "$tmp/$name.err")"
    done
    [ -e "$tmp/$name.out/result.json" ] && fail "$name: a result.json was written"
}

study general8 general 8
refused general8 "general8.yaml" "general-form grid at mu = 0 has 214358881 points" "more than the cap of 100000" \
    "scheme: reduced"

study reduced14 reduced 14
refused reduced14 "reduced14.yaml" "three-point grid of the left/right influence" "4782969 points" \
    "options.left_right: false"
grep -q "use scheme: reduced" "$tmp/reduced14.err" && fail "reduced14: the advice names the reduced form"

# the same reduced study without the left/right grid runs (2^14 corners + 1 fit the cap)
sed -i 's/^levels: 10$/levels: 1\noptions: {left_right: false}/' "$tmp/reduced14.yaml"
timeout 60 "$bin" run "$tmp/reduced14.yaml" --out "$tmp/r14ok" --quiet --no-plots > "$tmp/r14ok.out" 2> "$tmp/r14ok.err" ||
    fail "reduced14 without left/right: $(cat "$tmp/r14ok.err")"

if [ "$fails" -gt 0 ]; then
    echo "$fails failure(s)" >&2
    exit 1
fi
echo "cli_tm_cap: all checks passed"
