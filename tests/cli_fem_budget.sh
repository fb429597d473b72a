#!/bin/bash
# cli_fem_budget.sh - an FE impact that would run for hours says so or is
# refused before it runs (issue 31 item 17):
#   the step estimate made after assembly is the step count of the run: with
#   a given end time the run takes exactly the estimated steps (JSON steps),
#   a budget one below is refused, naming the count;
#   --end-time 100 (8e7 steps; ran > 120 s before) is refused within the
#   timeout by the default budget; with --max-steps 0 (no limit) it says its
#   steps and the time it will take on stderr within its first steps;
#   --slope-E 1e300 and --velocity 1e-300 are refused naming the input;
#   the bound made before meshing (from the finest element's h / c_p) is at
#   most the estimate after assembly; --slope-poisson 0.4999999 is refused
#   before meshing naming the near incompressibility (was silent for minutes),
#   and with --max-steps 0 the bound is said before the mesh.
# Usage: bash cli_fem_budget.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
fem=("$bin" impact --solver fem --refinement 2)

# the bound before meshing is at most the estimate after assembly, which is the run's step count
"${fem[@]}" --end-time 0.001 --max-steps 1 > /dev/null 2> "$tmp/err"
lb=$(sed -n 's/.*fem: before meshing: the run needs at least \([0-9]*\) time steps (of at most .*/\1/p' "$tmp/err")
[ -n "$lb" ] && [ "$lb" -gt 10 ] || fail "bound before meshing: no step count in: $(cat "$tmp/err")"
"${fem[@]}" --end-time 0.001 --max-steps "${lb:-1}" > /dev/null 2> "$tmp/err"
n=$(sed -n 's/.*the run needs about \([0-9]*\) time steps of .*/\1/p' "$tmp/err")
[ -n "$n" ] && [ "$n" -gt 10 ] || fail "estimate: no step count in: $(cat "$tmp/err")"
[ -n "$n" ] && [ -n "$lb" ] && { [ "$lb" -le "$n" ] || fail "the bound before meshing $lb > the estimate $n"; }
echo "bound before meshing: $lb steps, estimate after assembly: $n"
if [ -n "$n" ]; then
    "${fem[@]}" --end-time 0.001 --max-steps "$n" --json > "$tmp/run.json" 2> "$tmp/err" \
        || fail "a budget equal to the estimate $n refused: $(cat "$tmp/err")"
    steps=$(python3 -c "import json,sys; print(int(json.load(open(sys.argv[1]))['steps']))" "$tmp/run.json" 2>/dev/null)
    [ "$steps" = "$n" ] || fail "estimate $n steps, the run took '$steps'"
    "${fem[@]}" --end-time 0.001 --max-steps $((n - 1)) > /dev/null 2> "$tmp/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "the run needs about $n time steps .* more than the budget of $((n - 1)) steps" "$tmp/err" \
        || fail "a budget of $((n - 1)) < $n: exit $rc, $(cat "$tmp/err")"
    echo "estimate: $n steps, the run took $steps"
fi

# a long end time: refused by the default budget, at once
timeout 60 "${fem[@]}" --end-time 100 > /dev/null 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] || fail "--end-time 100: exit $rc (124: still running after 60 s), want 1"
grep -Eq "fem: (before meshing: )?the run needs (about|at least) [0-9.e+]+ time steps .* for 100 s simulated \(the given end time\), more than the budget of 1e\+06 steps" \
    "$tmp/err" || fail "--end-time 100: message: $(cat "$tmp/err")"
# ... asked for: it says its steps and time, then runs (stopped here)
timeout 40 "${fem[@]}" --end-time 100 --max-steps 0 > /dev/null 2> "$tmp/err"; rc=$?
[ $rc -eq 124 ] || fail "--end-time 100 --max-steps 0: exit $rc, want it still running at 40 s"
grep -Eq "^rockfuzz impact: fem: about [0-9.e+]+ time steps of .* for 100 s simulated .*; about [0-9]+ s at the .* ms per step of the first 16 steps" \
    "$tmp/err" || fail "--max-steps 0: no estimate said: $(cat "$tmp/err")"
"$bin" impact --help | grep -q -- "--max-steps N *fem: the step budget (default 1000000; 0 = no limit)" \
    || fail "--help does not document --max-steps"

# a nearly incompressible slope (issue 31 item 17: silent for 600 s at 989 MB while
# meshing its automatic domain): refused before meshing, naming the cause
timeout 20 "$bin" impact --solver fem --slope-poisson 0.4999999 > /dev/null 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -Eq "fem: before meshing: the run needs at least [0-9]+ time steps .* more than the budget of 1e\+06 steps .*the slope is nearly incompressible \(poisson = 0.4999999: its P waves run at .* times its S waves\)" \
    "$tmp/err" || fail "--slope-poisson 0.4999999: exit $rc (124: still running after 20 s), $(cat "$tmp/err")"
# ... with no budget: it says the bound before meshing
timeout 10 "$bin" impact --solver fem --slope-poisson 0.4999999 --max-steps 0 > /dev/null 2> "$tmp/err"
grep -Eq "^rockfuzz impact: fem: at least [0-9]+ time steps .* estimated before meshing; meshing comes first" \
    "$tmp/err" || fail "--slope-poisson 0.4999999 --max-steps 0: nothing said: $(cat "$tmp/err")"

# inputs beyond what the arithmetic or the mesh holds: named
timeout 120 "$bin" impact --solver fem --slope-E 1e300 > /dev/null 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "slope E = 1e+300 Pa" "$tmp/err" || fail "--slope-E 1e300: exit $rc, $(cat "$tmp/err")"
timeout 120 "$bin" impact --solver fem --velocity 1e-300 > /dev/null 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "velocity = 1e-300 m/s" "$tmp/err" || fail "--velocity 1e-300: exit $rc, $(cat "$tmp/err")"

[ $fails -eq 0 ] && echo "cli_fem_budget: all checks passed"
exit $((fails > 0))
