#!/usr/bin/env bash
# cli_mdr.sh - `rockfuzz impact --solver mdr` from the shell: the elastic MDR's
# R_t on the grid of docs/validation-mdr.md (30/45/60 deg x f = 0.1/0.6/5, to
# 1e-4), gross sliding equal to the rigid formula, Hunter's e_n as the default,
# and a bad e_n rejected.  Usage: bash cli_mdr.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
json_get() { # json key
    echo "$1" | sed -n "s/.*\"$2\": \([-0-9.eE+]*\).*/\1/p"
}
close() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

# angle f R_t (elastic MDR, --e-n 1; the table of docs/validation-mdr.md section 4)
while read -r angle f want; do
    out=$("$bin" impact --solver mdr --e-n 1 --slope-angle "$angle" --friction "$f" --json) ||
        { fail "mdr $angle/$f exit $?"; continue; }
    rt=$(json_get "$out" R_t)
    close "$rt" "$want" 1e-4 || fail "mdr $angle deg f=$f: R_t $rt, want $want"
done <<'EOF_GRID'
30 0.1 0.6537
30 0.6 0.7339
30 5 0.7880
45 0.6 0.6604
45 5 0.7834
60 0.1 0.8845
60 0.6 0.5904
60 5 0.7751
EOF_GRID

# gross sliding (45 deg, f = 0.1, psi1 = 8.6): R_t = 1 - f (1 + R_n) / tan 45
out=$("$bin" impact --solver mdr --slope-angle 45 --friction 0.1 --json) || fail "mdr sliding exit"
rn=$(json_get "$out" R_n)
rt=$(json_get "$out" R_t)
close "$rt" "$(awk -v r="$rn" 'BEGIN { printf "%.15f", 1 - 0.1 * (1 + r) }')" 1e-10 || fail "mdr sliding R_t $rt (R_n $rn)"

# default e_n: Hunter's, as the rigid solver
hunter=$("$bin" impact --solver hunter --slope-angle 45 --json)
close "$rn" "$(json_get "$hunter" R_n)" 1e-6 || fail "mdr R_n $rn is not Hunter's"
echo "$out" | grep -q '"contact_force_max": [0-9]' || fail "mdr must define the contact force: $out"

# e_n must be > 0 for the MDR: a model failure (exit 1) naming e_n
err=$("$bin" impact --solver mdr --e-n 0 --slope-angle 45 --friction 0.5 2>&1 >/dev/null)
rc=$?
[ "$rc" -eq 1 ] || fail "mdr --e-n 0: exit $rc"
echo "$err" | grep -q "e_n" || fail "mdr --e-n 0 message: $err"

"$bin" impact --help | grep -q "mdr" || fail "--help does not list mdr"
[ "$fails" -eq 0 ] && echo "cli_mdr: all checks passed"
exit $((fails > 0))
