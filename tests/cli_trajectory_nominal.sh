#!/bin/bash
# cli_trajectory_nominal.sh - a fuzzy trajectory study reruns its Monte Carlo
# at the nominal point into DIR/nominal/ (result.json, envelopes.csv,
# figures, report.html) and its report embeds the profile figure; the
# nominal run is the same as `rockfuzz trajectory` on the file with the
# parameter at its nominal value (here the file's own value).
# Usage: bash cli_trajectory_nominal.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

cat > "$tmp/study.yaml" <<YAML
name: nominal-check
levels: 2
parameters:
  rock_Rn: {tfn: [0.35, 0.1, 0.1]}
model:
  trajectory:
    file: $src/examples/trajectory/slope.yaml
    samples: 300
    bind: {rock_Rn: materials.rock.R_n.mean}
options: {left_right: false}
YAML
"$bin" run "$tmp/study.yaml" --out "$tmp/run" > "$tmp/run.txt" 2>&1 || fail "study run: $(tail -3 "$tmp/run.txt")"
for f in result.json envelopes.csv crossings.csv report.html trajectory_profile.png trajectory_hist_barrier.png; do
  [ -s "$tmp/run/nominal/$f" ] || fail "missing nominal/$f"
done
grep -q "Trajectories at the nominal point" "$tmp/run/report.html" || fail "study report: no nominal trajectories"
grep -q 'alt="trajectories: Nominal point" src="data:image/png;base64,' "$tmp/run/report.html" \
  || fail "study report: the profile figure is not embedded"
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --samples 300 --out "$tmp/direct" --quiet || fail "direct run"
cmp -s "$tmp/run/nominal/envelopes.csv" "$tmp/direct/envelopes.csv" || fail "nominal envelopes differ from a direct run"
cmp -s "$tmp/run/nominal/crossings.csv" "$tmp/direct/crossings.csv" || fail "nominal crossings differ from a direct run"
# `rockfuzz report` rebuilds the page with the section
rm "$tmp/run/report.html"
"$bin" report "$tmp/run" > /dev/null 2>&1 || fail "rockfuzz report"
grep -q "Trajectories at the nominal point" "$tmp/run/report.html" || fail "rebuilt report: no nominal trajectories"

[ $fails = 0 ] && echo "cli_trajectory_nominal: all checks passed"
