#!/bin/bash
# cli_terrain.sh - `rockfuzz trajectory` on a terrain file (issue 28
# item 8's minimal shape, DEM and class raster as ESRI ASCII grids made
# here): the summary gives the answer first; --json has the documented shape
# (per trajectory state, impacts with v_in/v_out/omega_out of 3 and class,
# rest or null, barrier crossings; statistics with runout and reach angle
# percentiles and the barrier); --out writes the CSV files with units in
# their headers, hazard.tif, paths.gpkg and report.html; the JSON is the
# same at 1 and 2 threads; `rockfuzz report DIR` redraws the run.
# A fuzzy study on the same terrain (docs/fuzzy-hazard.md) writes
# fuzzy_rasters.tif whose alpha = 1 cut of the reach probability is, cell by
# cell and bit for bit, the reach probability raster of a direct run at the
# nominal values (the same seed and samples: common random numbers), and
# whose cuts nest (alpha 0 contains alpha 0.5 contains alpha 1); its report
# shows the maps of that raster (nominal, alpha = 0 upper bound, blame).
# Usage: bash cli_terrain.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

python3 - "$tmp" <<'PY' || fail "cannot write the grids"
import math, sys
d = sys.argv[1]
n, cell = 151, 2.0
def z(x, y):
    base = 60 + 0.7 * (y - 200) if y > 200 else 40 + 0.1 * (y - 0)
    return base + 0.5 * math.sin(x / 7) * math.cos(y / 9)
for name, val in (("dem.asc", lambda x, y: "%.4f" % z(x, y)), ("classes.asc", lambda x, y: "1" if y > 200 else "2")):
    with open(f"{d}/{name}", "w") as f:
        f.write(f"ncols {n}\nnrows {n}\nxllcenter 0\nyllcenter 0\ncellsize {cell}\nNODATA_value -9999\n")
        for j in reversed(range(n)):
            f.write(" ".join(val(i * cell, j * cell) for i in range(n)) + "\n")
PY
cat > "$tmp/valley.yaml" <<EOF
name: valley
terrain: {dem: $tmp/dem.asc, materials: {raster: $tmp/classes.asc, classes: {1: rock, 2: talus}}}
materials:
  rock:  {R_n: 0.5, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, roughness: 5}
  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: 0.2, roughness: 10}
block: {shape: sphere, radius: 0.5, density: 2600}
release: {points: [[140, 280], [160, 280]], height: 1.0, velocity: [0, 0, 0]}
bounce: {law: constant}
barriers: [{name: fence, line: [[20, 150], [280, 150]], height: 4, capacity: 2.0e6}]
rasters: {cell: 2, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}
samples: 400
seed: 1
EOF

"$bin" trajectory "$tmp/valley.yaml" > "$tmp/summary.txt" || fail "valley.yaml did not run"
sed -n 2p "$tmp/summary.txt" | grep -q '% stop (' || fail "the summary does not say first how many stop"
grep -q 'runout (horizontal, release to end) \[m\]: p50' "$tmp/summary.txt" || fail "no runout in the summary"
grep -q 'barrier fence: reached by' "$tmp/summary.txt" || fail "no barrier in the summary"
"$bin" trajectory "$tmp/valley.yaml" --json --threads 1 > "$tmp/t1.json" || fail "--json failed"
"$bin" trajectory "$tmp/valley.yaml" --json --threads 2 > "$tmp/t2.json" || fail "--json 2 threads failed"
python3 - "$tmp/t1.json" "$tmp/t2.json" <<'PY' || fail "JSON shape or thread determinism"
import json, sys
d = json.load(open(sys.argv[1])); d2 = json.load(open(sys.argv[2]))
d.pop("wall_seconds"); d2.pop("wall_seconds")
assert d == d2, "1 and 2 threads differ"
assert d["kind"] == "terrain" and d["samples"] == 400 and d["units"]["angle"] == "deg"
assert sum(d["states"].values()) == 400
t = d["trajectories"][0]
assert t["state"] in ("stopped", "exited", "step_limit")
i = t["impacts"][0]
for k in ("t", "x", "y", "z", "class"):
    assert k in i, k
for k in ("v_in", "v_out", "omega_out"):
    assert len(i[k]) == 3, k
assert i["class"] in ("rock", "talus")
assert t["rest"] is None or set(t["rest"]) == {"t", "x", "y", "z"}
assert "fence" in t["barriers"]
s = d["statistics"]
assert set(s["runout"]) == {"p50", "p95", "p99", "max", "mean"}
assert 0 < s["reach_angle"]["p50"] < 90
assert 0 <= s["barriers"]["fence"]["reach_probability"] <= 1
PY
"$bin" trajectory "$tmp/valley.yaml" --out "$tmp/out" --quiet || fail "--out"
for f in result.json samples.csv crossings.csv statistics.csv hazard.tif paths.gpkg report.html invocation.json; do
  [ -s "$tmp/out/$f" ] || fail "missing $f"
done
head -1 "$tmp/out/samples.csv" | grep -q '^sample,state,start_x_m,.*,runout_m,reach_angle_deg,' || fail "samples.csv header"
[ "$(grep -c . "$tmp/out/samples.csv")" = 401 ] || fail "samples.csv rows"
[ "$(grep -c ',fence,' "$tmp/out/crossings.csv")" = 400 ] || fail "crossings.csv rows"
grep -q '^reach_angle,deg,' "$tmp/out/statistics.csv" || fail "statistics.csv has no reach angle in deg"
if command -v gdalinfo > /dev/null; then
  gdalinfo "$tmp/out/hazard.tif" | grep -q 'passages' || fail "hazard.tif has no passages band"
fi
rm "$tmp/out/report.html"
"$bin" report "$tmp/out" || fail "rockfuzz report on a terrain run"
[ -s "$tmp/out/report.html" ] || fail "rockfuzz report did not redraw report.html"
# ---- a fuzzy hazard map: its alpha = 1 cut is the nominal run's raster, its cuts nest ----
if command -v gdal_translate > /dev/null; then
  cat > "$tmp/study.yaml" <<EOF
name: valley-fuzzy
scheme: general
levels: 2
parameters:
  rock_Rn: {tfn: [0.5, 0.1, 0.1]}
  talus_rolling: {tfn: [0.2, 0.1, 0.1]}
model:
  trajectory:
    file: $tmp/valley.yaml
    samples: 60
    bind: {rock_Rn: materials.rock.R_n, talus_rolling: materials.talus.rolling_resistance}
    rasters: {fuzzy: [reach_probability]}
EOF
  "$bin" run "$tmp/study.yaml" --out "$tmp/fz" --quiet > /dev/null || fail "fuzzy terrain study"
  # the maps of the first fuzzy raster: nominal and alpha-0 upper side by side, the blame map, in report.html
  for m in nominal upper blame; do
    [ "$(stat -c %s "$tmp/fz/fuzzy_map_$m.png" 2>/dev/null || echo 0)" -gt 20000 ] || fail "no fuzzy_map_$m.png (or blank)"
    grep -q "<a href=\"fuzzy_map_$m.png\">" "$tmp/fz/report.html" || fail "report.html does not show fuzzy_map_$m.png"
  done
  grep -q '<h2 id=fuzzy-maps>' "$tmp/fz/report.html" || fail "report.html has no fuzzy hazard maps section"
  [ "$(sed -n '/id=fuzzy-maps/,/<h2>Output/p' "$tmp/fz/report.html" | grep -c 'src="data:image/png;base64,')" = 3 ] \
    || fail "the fuzzy hazard maps section does not embed its 3 maps"
  cmp -s "$tmp/fz/fuzzy_map_nominal.png" "$tmp/fz/fuzzy_map_upper.png" && fail "the nominal and the upper map are the same image"
  "$bin" trajectory "$tmp/valley.yaml" --samples 60 --out "$tmp/nom" --no-plots --quiet || fail "nominal run"
  for b in 1 2 3 4 5 6; do gdal_translate -q -b $b -of AAIGrid "$tmp/fz/fuzzy_rasters.tif" "$tmp/fz_$b.asc"; done
  gdal_translate -q -b 2 -of AAIGrid "$tmp/nom/hazard.tif" "$tmp/nom_p.asc"
  cmp -s "$tmp/fz_5.asc" "$tmp/nom_p.asc" || fail "alpha 1 lower bound differs from the nominal run's reach probability"
  cmp -s "$tmp/fz_6.asc" "$tmp/nom_p.asc" || fail "alpha 1 upper bound differs from the nominal run's reach probability"
  python3 - "$tmp" <<'PY' || fail "the fuzzy cuts do not nest, or nothing is uncertain"
import sys
t = sys.argv[1]
def grid(b):
    vals = []
    for line in open(f"{t}/fz_{b}.asc"):
        w = line.split()
        if w and w[0].lower() not in ("ncols", "nrows", "xllcorner", "yllcorner", "cellsize", "nodata_value", "dx", "dy"):
            vals += [float(v) for v in w]
    return vals
lo0, hi0, lo5, hi5, lo1, hi1 = (grid(b) for b in range(1, 7))
bad = sum(1 for k in range(len(lo0)) if not (lo0[k] <= lo5[k] <= lo1[k] <= hi1[k] <= hi5[k] <= hi0[k]))
wide = sum(1 for k in range(len(lo0)) if hi0[k] > lo0[k])
print(f"cells {len(lo0)}, not nested {bad}, uncertain at alpha 0: {wide}")
sys.exit(bad > 0 or wide == 0)
PY
fi
exit $((fails > 0))
