#!/bin/bash
# cli_block_traj.sh - `rockfuzz trajectory` with a rigid block (issue 30,
# docs/block-shape.md "Wiring"): a box on a small terrain (ESRI ASCII grids
# made here) and an ellipsoid on a profile run and write their run folders;
# the --json carries per impact the orientation q (a unit quaternion) and the
# rotational energy about each body axis (never negative), and per recorded
# trajectory the orientation at its events (times increasing); the terrain
# run's trajectories.csv has every event of each recorded trajectory, its
# orientation the JSON's and its lowest point never below the plane DEM
# (to h x 10 m/s; on it, from above, at rest); bad block
# values are refused with file:line, field and value.
# Usage: bash cli_block_traj.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

python3 - "$tmp" <<'PY' || fail "cannot write the grids"
import sys
d = sys.argv[1]
n, cell = 41, 2.0
for name, val in (("dem.asc", lambda x, y: "%.4f" % (60 - 0.6 * x)), ("classes.asc", lambda x, y: "1")):
    with open(f"{d}/{name}", "w") as f:
        f.write(f"ncols {n}\nnrows {n}\nxllcenter 0\nyllcenter 0\ncellsize {cell}\nNODATA_value -9999\n")
        for j in reversed(range(n)):
            f.write(" ".join(val(i * cell, j * cell) for i in range(n)) + "\n")
PY
cat > "$tmp/box.yaml" <<EOF
name: box
terrain: {dem: $tmp/dem.asc, materials: {raster: $tmp/classes.asc, classes: {1: rock}}}
materials:
  rock: {R_n: 0.4, R_t: 0.8, friction_angle: 35}
block: {shape: box, edges: [1.2, 0.9, 0.6], density: 2600, orientation: random, spin: [0, 1, 0]}
release: {points: [[10, 40]], height: 2.0, velocity: [2, 0, 0]}
barriers: [{name: fence, line: [[50, 0], [50, 80]], height: 3, capacity: 1.0e7}]
samples: 6
seed: 3
EOF
"$bin" trajectory "$tmp/box.yaml" > "$tmp/summary.txt" || fail "box.yaml did not run"
grep -q 'barrier fence: reached by' "$tmp/summary.txt" || fail "no barrier in the summary"
"$bin" trajectory "$tmp/box.yaml" --json > "$tmp/t.json" || fail "--json failed"
python3 - "$tmp/t.json" <<'PY' || fail "JSON of a rigid block on terrain"
import json, math, sys
d = json.load(open(sys.argv[1]))
assert sum(d["states"].values()) == 6
for t in d["trajectories"]:
    assert t["n_impacts"] >= 1 and t["impacts"], "no impact"
    for i in t["impacts"]:
        q = i["q"]
        assert len(q) == 4 and abs(math.sqrt(sum(c * c for c in q)) - 1) < 1e-9, q
        r = i["rotational_energy_axes"]
        assert len(r) == 3 and min(r) >= 0, r
    o = t["orientation"]
    assert len(o) >= 2 and all(len(r) == 5 for r in o)
    assert all(o[k + 1][0] >= o[k][0] for k in range(len(o) - 1)), "times go back"
    assert "fence" in t["barriers"]
PY
"$bin" trajectory "$tmp/box.yaml" --out "$tmp/out" --quiet || fail "--out"
python3 - "$tmp/out/trajectories.csv" "$tmp/t.json" <<'PY' || fail "trajectories.csv of a block on terrain"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
traj = json.load(open(sys.argv[2]))["trajectories"]
assert len(traj) == 6 and {r["sample"] for r in rows} == {str(k) for k in range(6)}
rest = 0
for k, t in enumerate(traj):
    ev = [r for r in rows if r["sample"] == str(k)]
    assert len(ev) == len(t["orientation"]) and ev[0]["event"] == "release", (k, len(ev))
    for r, o in zip(ev, t["orientation"]):
        q = [float(r[c]) for c in ("q_w", "q_x", "q_y", "q_z")]
        assert abs(float(r["t_s"]) - o[0]) < 1e-12 and max(abs(a - b) for a, b in zip(q, o[1:])) < 1e-12, (r, o)
        assert abs(math.sqrt(sum(c * c for c in q)) - 1) < 1e-9, q
        ground = 60 - 0.6 * float(r["x_m"])   # the plane DEM
        z = float(r["z_m"])
        # the lowest point never below the ground by more than Moreau's step allows (h x the approach
        # speed: 1 ms x 10 m/s; the velocity-level scheme does not push a point back out)
        assert z >= ground - 0.01, (k, r)
        if r["event"] == "rest" and float(r["x_m"]) < 49:   # (a block held by the fence at x = 50 rests on it)
            rest += 1
            assert z - ground < 1e-6, (k, r)
assert rest >= 1, "no block came to rest on the plane"
PY
for f in result.json samples.csv crossings.csv statistics.csv; do
  [ -s "$tmp/out/$f" ] || fail "missing $f"
done

# outputs.vtk: the box's hull along each recorded trajectory, a ParaView time series whose every frame
# is the box (8 points, its diagonal sqrt(1.2^2 + 0.9^2 + 0.6^2) m apart at most)
printf 'outputs: {vtk: true}\nrecord: 2\n' >> "$tmp/box.yaml"
"$bin" trajectory "$tmp/box.yaml" --out "$tmp/vout" --quiet || fail "--out with outputs.vtk"
python3 - "$tmp/vout" <<'PY' || fail "the ParaView files"
import glob, math, sys, xml.etree.ElementTree as ET
d = sys.argv[1] + "/vtk"
for k in (0, 1):
    frames = ET.parse(f"{d}/block_{k}.pvd").getroot().findall(".//DataSet")
    assert len(frames) > 2, len(frames)
    for fr in frames[:: max(1, len(frames) // 7)]:
        p = ET.parse(f"{d}/{fr.get('file')}").getroot().find(".//Points/DataArray").text.split()
        pts = [tuple(map(float, p[i:i + 3])) for i in range(0, len(p), 3)]
        assert len(pts) == 8, len(pts)
        far = max(math.dist(a, b) for a in pts for b in pts)
        assert abs(far - math.sqrt(1.2**2 + 0.9**2 + 0.6**2)) < 1e-6, far
assert not glob.glob(f"{d}/block_2.pvd")
PY

cat > "$tmp/p.yaml" <<EOF
name: p
profile: {points: [[0, 30], [30, 10], [60, 5], [100, 5]], material: m}
materials: {m: {R_n: 0.4, R_t: 0.8, friction_angle: 35}}
block: {shape: ellipsoid, axes: [0.8, 0.5, 0.4], density: 2600, axis_ratios: [1, 0.8, 0.6]}
release: {x: 2, y: 32, vx: 3}
collectors: [{name: c, x: 45}]
samples: 3
EOF
"$bin" trajectory "$tmp/p.yaml" --out "$tmp/pout" --quiet || fail "profile --out"
for f in result.json samples.csv trajectories.csv envelopes.csv; do
  [ -s "$tmp/pout/$f" ] || fail "profile: missing $f"
done
"$bin" trajectory "$tmp/p.yaml" --json | python3 -c '
import json, sys
t = json.load(sys.stdin)["trajectories"][0]
assert len(t["impacts"][0]["q"]) == 4 and len(t["orientation"]) > 2
' || fail "profile JSON of a rigid block"
sed 's/axes: \[0.8, 0.5, 0.4\]/axes: [0.8, -0.5, 0.4]/' "$tmp/p.yaml" > "$tmp/bad.yaml"
msg=$("$bin" trajectory "$tmp/bad.yaml" 2>&1) && fail "a negative semi-axis was accepted"
echo "$msg" | grep -q 'bad.yaml:4: block.axes' || fail "the message lacks file:line and field: $msg"
sed 's/density: 2600, axis/volume: -1, density: 2600, axis/' "$tmp/p.yaml" > "$tmp/bad2.yaml"
msg=$("$bin" trajectory "$tmp/bad2.yaml" 2>&1) && fail "a negative volume was accepted"
echo "$msg" | grep -q 'bad2.yaml:4: block.volume = -1' || fail "the message lacks file:line, field and value: $msg"
exit $((fails > 0))
