#!/bin/bash
# cli_trajectory.sh - `rockfuzz trajectory`: the minimal file of issue 11
# runs, --json has the documented shape (checked with python3), --out writes
# the CSV files, plots and a self-contained report.html, a bad file exits 1
# with file:line: field = value, a bad option exits 2; the hybrid example
# study loads.  Usage: bash cli_trajectory.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

"$bin" trajectory "$src/examples/trajectory/cliff.yaml" > "$tmp/summary.txt" || fail "cliff.yaml did not run"
grep -q "stopped at t = " "$tmp/summary.txt" || fail "no rest point in the summary"
"$bin" trajectory "$src/examples/trajectory/cliff.yaml" --json > "$tmp/cliff.json" || fail "--json failed"
python3 - "$tmp/cliff.json" <<'PY' || fail "JSON shape"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["samples"] == 1
t = d["trajectories"][0]
assert t["state"] in ("stopped", "exited", "step_limit")
i = t["impacts"][0]
for k in ("t", "x", "y", "segment", "vx_in", "vy_in", "vx_out", "vy_out", "omega_out"):
    assert k in i, k
assert i["segment"] == 2 and abs(i["x"] - 10.791871594517408) < 1e-9
assert set(t["rest"]) >= {"t", "x", "y"}
c = t["collectors"]["barrier"]
for k in ("t", "height_lowest", "height_centre", "normal_height", "speed", "translational_energy",
          "rotational_energy", "total_energy"):
    assert k in c, k
assert "kinetic_energy" not in c and "height" not in c
assert c["total_energy"] == c["translational_energy"] + c["rotational_energy"]
s = d["statistics"]
assert set(s["runout_x"]) == {"p50", "p95", "p99", "max", "mean"}
b = s["collectors"]["barrier"]
assert b["reach_probability"] == 1 and set(b["total_energy"]) == {"p50", "p95", "p99", "max", "mean"}
for k in ("translational_energy", "rotational_energy", "height_lowest", "height_centre", "speed"):
    assert k in b, k
assert "kinetic_energy" not in b and "height" not in b
PY
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --samples 300 --threads 2 --out "$tmp/out" --quiet \
  || fail "slope.yaml --out"
for f in result.json trajectories.csv crossings.csv statistics.csv envelopes.csv report.html trajectory_profile.png \
         trajectory_profile.svg trajectory_hist_barrier.png trajectory_hist_road.svg; do
  [ -s "$tmp/out/$f" ] || fail "missing $f"
done
grep -q "data:image/png;base64" "$tmp/out/report.html" || fail "report.html does not embed its figures"
[ "$(grep -c ',barrier,' "$tmp/out/crossings.csv")" = 300 ] || fail "crossings.csv rows"
# envelopes from all 300 trajectories: at the barrier's x (95 m, an edge) as many reach as cross it
head -1 "$tmp/out/envelopes.csv" | grep -q '^x_m,reached,fraction_reaching,height_p50_m,.*,energy_max_J$' \
  || fail "envelopes.csv header"
[ "$(grep -c . "$tmp/out/envelopes.csv")" = 162 ] || fail "envelopes.csv rows"
n_cross=$(awk -F, '$4 == "barrier" && $5 == 1' "$tmp/out/crossings.csv" | wc -l)
[ "$(awk -F, '$1 == 95 {print $2}' "$tmp/out/envelopes.csv")" = "$n_cross" ] || fail "envelope reach at the barrier"
grep -q "envelopes use all 300" "$tmp/out/report.html" || fail "report: envelopes from all trajectories"

# outputs: chosen percentiles, thresholds and the runout histogram, checked against a
# brute-force recomputation from the per-sample CSV files (Hyndman-Fan type 7 =
# Python's statistics.quantiles(method="inclusive")); every CSV header names units
sed -e 's/^  - {name: barrier, x: 95} .*/  - {name: barrier, x: 95, capacity: 100e3, height: 1, energy_thresholds: [50e3, 300e3], height_thresholds: [0.5]}/' \
    -e 's/^samples: 2000/samples: 400\noutputs: {percentiles: [50, 90, 95, 98, 99.5], runout_thresholds: [100, 120.5], runout_bins: 12}/' \
    "$src/examples/trajectory/slope.yaml" > "$tmp/outputs.yaml"
"$bin" trajectory "$tmp/outputs.yaml" --out "$tmp/o2" --no-plots > "$tmp/o2.txt" || fail "outputs.yaml did not run"
grep -q "units: energy kJ" "$tmp/o2.txt" || fail "the summary does not state its units once"
grep -q "P(total energy > 100 kJ, the capacity) = " "$tmp/o2.txt" || fail "summary: P(E > capacity): $(cat "$tmp/o2.txt")"
python3 - "$tmp/o2" <<'PY' || fail "user percentiles / exceedance / histogram differ from the brute-force ones"
import csv, json, statistics, sys
d = sys.argv[1]
r = json.load(open(d + "/result.json"))["statistics"]
rows = lambda f: list(csv.DictReader(open(d + "/" + f)))
sam, cro = rows("samples.csv"), [x for x in rows("crossings.csv") if x["collector"] == "barrier"]
assert len(sam) == 400 and len(cro) == 400
lv = [50, 90, 95, 98, 99.5]
def pct(v):
    q = statistics.quantiles(v, n=1000, method="inclusive")
    return {("p%g" % l).replace(".", "_"): q[int(round(l * 10)) - 1] for l in lv}
def close(a, b):
    assert abs(a - b) <= 1e-9 * (1 + abs(b)), (a, b)
x = [float(s["runout_x_m"]) for s in sam]
for k, v in pct(x).items():
    close(r["runout_x"][k], v)
close(r["runout_x"]["max"], max(x))
assert [e["threshold"] for e in r["p_runout_x_above"]] == [100, 120.5]
for e in r["p_runout_x_above"]:
    close(e["probability"], sum(v > e["threshold"] for v in x) / 400)
reach = [c for c in cro if c["reached"] == "1"]
E = [float(c["total_energy_J"]) for c in reach]
H = [float(c["height_lowest_m"]) for c in reach]
for c in reach:
    close(float(c["total_energy_J"]), float(c["translational_energy_J"]) + float(c["rotational_energy_J"]))
    close(float(c["height_centre_m"]), float(c["height_lowest_m"]) + 0.5)
b = r["collectors"]["barrier"]
for k, v in pct(E).items():
    close(b["total_energy"][k], v)
for k, v in pct(H).items():
    close(b["height_lowest"][k], v)
pe = b["p_total_energy_above"]
assert [(e["threshold"], e["barrier"]) for e in pe] == [(100e3, True), (50e3, False), (300e3, False)], pe
for e in pe:
    close(e["probability"], sum(v > e["threshold"] for v in E) / 400)
ph = b["p_height_lowest_above"]
assert [(e["threshold"], e["barrier"]) for e in ph] == [(1, True), (0.5, False)], ph
for e in ph:
    close(e["probability"], sum(v > e["threshold"] for v in H) / 400)
h = r["runout_histogram"]
assert len(h["counts"]) == 12 and len(h["edges"]) == 13 and sum(h["counts"]) == 400
close(h["edges"][0], min(x)); close(h["edges"][-1], max(x))
ed = h["edges"]
cnt = [sum(ed[k] <= v < ed[k + 1] or (k == 11 and v == ed[12]) for v in x) for k in range(12)]
assert cnt == h["counts"], (cnt, h["counts"])
hc = rows("runout_histogram.csv")
assert [int(c["count"]) for c in hc] == h["counts"]
st = rows("statistics.csv")
assert list(st[0].keys()) == ["quantity", "unit", "p50", "p90", "p95", "p98", "p99_5", "max", "mean"], list(st[0])
ex = rows("exceedance.csv")
assert [ex[0][k] for k in ("quantity", "threshold", "unit", "source")] == ["runout_x", "100", "m", "user"], ex[0]
assert float(ex[0]["probability"]) == r["p_runout_x_above"][0]["probability"]
assert [e["source"] for e in ex if e["quantity"] == "barrier.total_energy"] == ["capacity", "user", "user"]
PY
for f in trajectories samples crossings statistics exceedance runout_histogram; do
  head -1 "$tmp/o2/$f.csv" | grep -qE '_(m|s|J|m_s)(,|$)|,unit,|,unit$' || fail "$f.csv: no unit in the header"
done
# without any collector: the runout of every sample is still written
grep -v -e '^collectors:' -e '^  - {name:' "$src/examples/trajectory/slope.yaml" | sed 's/^samples: 2000/samples: 50/' \
    > "$tmp/nocol.yaml"
"$bin" trajectory "$tmp/nocol.yaml" --out "$tmp/o3" --no-plots --quiet || fail "no-collector run"
[ "$(tail -n +2 "$tmp/o3/samples.csv" | wc -l)" = 50 ] || fail "samples.csv without collectors"
[ "$(tail -n +2 "$tmp/o3/runout_histogram.csv" | awk -F, '{s += $4} END {print s}')" = 50 ] || fail "histogram without collectors"

printf 'profile: {points: [[0, 0], [10, -1]], material: m}\nmaterials: {m: {R_n: 2, R_t: 0.5}}\nblock: {mass: 1}\nrelease: {x: 1, y: 1}\n' > "$tmp/bad.yaml"
"$bin" trajectory "$tmp/bad.yaml" 2> "$tmp/err.txt"
[ $? = 1 ] || fail "bad file: exit status"
grep -q "bad.yaml:2: materials.m.R_n = 2: must lie in \[0, 1\]" "$tmp/err.txt" || fail "bad file message: $(cat "$tmp/err.txt")"
"$bin" trajectory "$src/examples/trajectory/cliff.yaml" --samples x 2> /dev/null
[ $? = 2 ] || fail "bad option: exit status"
"$bin" trajectory --help | grep -q "Usage: rockfuzz trajectory" || fail "--help"
"$bin" --help | grep -q "trajectory FILE.yaml" || fail "rockfuzz --help lists trajectory"

# the hybrid study loads and plans (no evaluation: a cap of 1 refuses to start)
"$bin" run "$src/examples/trajectory/hybrid.yaml" --out "$tmp/h" --max-evaluations 1 > /dev/null 2> "$tmp/h.txt"
grep -q "general" "$tmp/h.txt" || grep -q "evaluations" "$tmp/h.txt" || fail "hybrid study: $(cat "$tmp/h.txt")"

# --out into a user's folder (their own report.html and result.json, no invocation.json) is
# refused before anything runs, and nothing there is touched; --force writes; a folder that
# holds a trajectory run (invocation.json) is written again without --force
mkdir -p "$tmp/mine"
echo "<p>my report</p>" > "$tmp/mine/report.html"
echo '{"mine": 1}' > "$tmp/mine/result.json"
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --out "$tmp/mine" --quiet 2> "$tmp/mine.err"
[ $? = 2 ] || fail "--out into a user's folder: not refused with exit 2"
grep -q "holds no rockfuzz run (no invocation.json).*--force" "$tmp/mine.err" || fail "--out refusal: $(cat "$tmp/mine.err")"
grep -q "my report" "$tmp/mine/report.html" && grep -q '"mine"' "$tmp/mine/result.json" || fail "--out touched the user's files"
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --out "$tmp/mine" --quiet --force || fail "--out --force"
[ -f "$tmp/mine/invocation.json" ] || fail "--force wrote no invocation.json"
"$bin" trajectory "$src/examples/trajectory/slope.yaml" --out "$tmp/mine" --quiet || fail "--out into its own run again"

[ $fails = 0 ] && echo "cli_trajectory: all checks passed"
exit $fails
