#!/bin/bash
# cli_block_shape.sh - the fuzzy shape study of whole trajectories (issue 30,
# docs/studies.md S7, examples/block_shape/) in miniature, and the block
# outputs of docs/block-shape.md:
#  - a study with the box's flatness c/a fuzzy (levels 2, a few samples) has
#    the fuzzy rows of the barrier energy and the runout, nested alpha-cuts,
#    and the inputs that reach each bound lie in that level's input cut;
#  - the mass is the same at every TM point (constant volume): replayed
#    through the trajectory file at each point's c/a, every crossing's
#    2 E_trans / v^2 is rho V;
#  - trajectories.csv of a block carries q (unit, equal to the JSON's);
#  - the envelopes weigh a random volume's own mass and add the rotation:
#    their energy max at a collector's x is the crossings' total energy max;
#  - ParaView frames follow each sample's own shape: with a random volume,
#    the hull volume of every recorded trajectory's frames times rho equals
#    that sample's mass from its crossings (2 E_trans / v^2);
#  - on terrain a tumbling box crosses every line it passes (each block that
#    ends beyond a line across the whole DEM has crossed it);
#  - outputs.vtk with a sphere or a point is refused with file:line.
# Usage: bash cli_block_shape.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

# The study's trajectory file: examples/block_shape/profile.yaml with few samples.
sed -e 's/^samples: .*/samples: 6/' -e 's/^record: .*/record: 2/' \
    "$src/examples/block_shape/profile.yaml" > "$tmp/profile.yaml"
cat > "$tmp/study.yaml" <<'EOF'
name: tiny-shape
scheme: general
levels: 2
parameters:
  flatness: {tfn: [0.7, 0.3, 0.3]}
model:
  trajectory:
    file: profile.yaml
    samples: 6
    bind:
      flatness: block.axis_ratio_c
options:
  left_right: false
EOF
"$bin" run "$tmp/study.yaml" --out "$tmp/study" --threads 2 --quiet --no-plots > /dev/null \
    || fail "the tiny shape study did not run"
python3 - "$tmp/study" <<'PY' || fail "the study's fuzzy rows"
import csv, json, sys
d = json.load(open(sys.argv[1] + "/result.json"))
cut = {}
for r in csv.DictReader(open(sys.argv[1] + "/inputs.csv")):
    cut[float(r["mu"])] = (float(r["lower"]), float(r["upper"]))
assert abs(cut[0][0] - 0.4) < 1e-12 and abs(cut[0][1] - 1.0) < 1e-12, cut
for name in ("barrier_total_energy_p95", "runout_x_p95", "barrier_reach_probability"):
    o = d["outputs"][name]
    mu, lo, up = o["mu"], o["lower"], o["upper"]
    assert len(mu) == 3 and mu[0] == 0 and mu[-1] == 1, (name, mu)
    for k in range(len(mu)):
        assert lo[k] <= o["nominal"] <= up[k], (name, k)
        if k:  # nested: a higher level's cut lies inside the lower's
            assert lo[k] >= lo[k - 1] and up[k] <= up[k - 1], (name, k, lo, up)
        c = cut[mu[k]]
        for x in (o["x_lower"][k]["flatness"], o["x_upper"][k]["flatness"]):
            assert c[0] - 1e-12 <= x <= c[1] + 1e-12, (name, k, x, c)
    assert lo[-1] == up[-1] == o["nominal"], name
    assert up[0] > lo[0], (name, "the shape changes nothing?")
assert d["outputs"]["barrier_total_energy_p95"]["unit"] == "J"
print(" ".join(sorted(set("%.17g" % v for c in cut.values() for v in c))))
PY
points=$(python3 -c "
import csv, sys
print(' '.join(sorted(set('%.17g' % float(r[k]) for r in csv.DictReader(open('$tmp/study/inputs.csv')) for k in ('lower', 'upper')))))")
[ "$(echo "$points" | wc -w)" = 5 ] || fail "levels 2 should give 5 TM values of c/a, got: $points"

# Constant volume: the same mass at every TM point's c/a (rho V = 2600 x 0.5236 kg).
for c in $points; do
    sed -e "s/axis_ratios: \[1, 1, 0.7\]/axis_ratios: [1, 1, $c]/" "$tmp/profile.yaml" > "$tmp/p_$c.yaml"
    grep -q "axis_ratios: \[1, 1, $c\]" "$tmp/p_$c.yaml" || fail "cannot set c/a = $c"
    "$bin" trajectory "$tmp/p_$c.yaml" --out "$tmp/p_$c" --quiet --no-plots || fail "c/a = $c did not run"
done
python3 - "$tmp" $points <<'PY' || fail "the mass is not the same at every TM point"
import csv, sys
m0 = 2600 * 0.5236
for c in sys.argv[2:]:
    rows = [r for r in csv.DictReader(open(f"{sys.argv[1]}/p_{c}/crossings.csv")) if r["reached"] == "1"]
    assert rows, f"c/a = {c}: no block reached a collector"
    for r in rows:
        m = 2 * float(r["translational_energy_J"]) / float(r["speed_m_s"]) ** 2
        assert abs(m / m0 - 1) < 1e-9, (c, m, m0)
PY

# trajectories.csv: the block's orientation, a unit quaternion equal to the JSON's at each event.
"$bin" trajectory "$tmp/profile.yaml" --json > "$tmp/p.json" || fail "--json"
python3 - "$tmp/p_0.69999999999999996/trajectories.csv" "$tmp/p.json" <<'PY' || fail "q in trajectories.csv"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert list(rows[0].keys())[-4:] == ["q_w", "q_x", "q_y", "q_z"], list(rows[0].keys())
for r in rows:
    q = [float(r[k]) for k in ("q_w", "q_x", "q_y", "q_z")]
    assert abs(math.sqrt(sum(v * v for v in q)) - 1) < 1e-8, q
d = json.load(open(sys.argv[2]))
for i, t in enumerate(d["trajectories"][:2]):
    ev = [r for r in rows if r["sample"] == str(i) and r["event"]]
    assert len(ev) == len(t["orientation"]), (len(ev), len(t["orientation"]))
    for r, o in zip(ev, t["orientation"]):
        assert abs(float(r["t_s"]) - o[0]) < 1e-8
        assert all(abs(float(r[k]) - o[j + 1]) < 1e-8 for j, k in enumerate(("q_w", "q_x", "q_y", "q_z")))
PY

# Envelopes: a random volume (each sample its own mass) and the rotation. The collector stands on an
# envelope edge (161 edges over the 280 m profile: x = 1.75 k), so both record the same passages; the
# envelope takes the state of the event before (events 0.01 s apart), hence 1 % and not round-off.
sed -e 's/volume: 0.5236/volume: {uniform: [0.2, 1.0]}/' -e 's/^samples: .*/samples: 12/' \
    -e 's/- {name: barrier, x: 95}/- {name: barrier, x: 94.5}/' -e 's/^record: .*/record: 12/' \
    "$tmp/profile.yaml" > "$tmp/env.yaml"
echo "outputs: {vtk: true}" >> "$tmp/env.yaml"
"$bin" trajectory "$tmp/env.yaml" --out "$tmp/env" --quiet --no-plots || fail "random volume did not run"
python3 - "$tmp/env" <<'PY' || fail "the envelopes' energy of a block"
import csv, sys
cr = [r for r in csv.DictReader(open(sys.argv[1] + "/crossings.csv")) if r["collector"] == "barrier" and r["reached"] == "1"]
assert len(cr) >= 3, len(cr)
emax = max(float(r["total_energy_J"]) for r in cr)
tmax = max(float(r["translational_energy_J"]) for r in cr)
masses = {round(2 * float(r["translational_energy_J"]) / float(r["speed_m_s"]) ** 2, 6) for r in cr}
assert len(masses) == len(cr), "the volume is not random per sample"
env = [r for r in csv.DictReader(open(sys.argv[1] + "/envelopes.csv")) if abs(float(r["x_m"]) - 94.5) < 1e-9]
assert len(env) == 1, "no envelope edge at x = 94.5 m"
e = float(env[0]["energy_max_J"])
assert int(env[0]["reached"]) == len(cr), (env[0]["reached"], len(cr))
assert abs(e / emax - 1) < 0.01, (e, emax, tmax)   # with the rotation (tmax alone is lower)
assert emax / tmax > 1.02, "no rotational energy to tell the two apart"
PY
python3 - "$tmp/env" <<'PY' || fail "the ParaView frames of a random volume"
import csv, sys, xml.etree.ElementTree as ET
d = sys.argv[1]
def volume(path):  # the closed hull's volume by the divergence theorem
    r = ET.parse(path).getroot()
    p = [float(v) for v in r.find(".//Points/DataArray").text.split()]
    c = [int(v) for v in r.find(".//Polys/DataArray[@Name='connectivity']").text.split()]
    P = [p[i:i + 3] for i in range(0, len(p), 3)]
    v = 0
    for i in range(0, len(c), 3):
        a, b, e = P[c[i]], P[c[i + 1]], P[c[i + 2]]
        v += (a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0]) + a[2] * (b[0] * e[1] - b[1] * e[0])) / 6
    return v
checked, vols = 0, set()
for r in csv.DictReader(open(d + "/crossings.csv")):
    if r["collector"] != "barrier" or r["reached"] != "1":
        continue
    k = int(r["sample"])
    mass = 2 * float(r["translational_energy_J"]) / float(r["speed_m_s"]) ** 2
    frames = ET.parse(f"{d}/vtk/block_{k}.pvd").getroot().findall(".//DataSet")
    for fr in (frames[0], frames[-1]):
        v = volume(f"{d}/vtk/{fr.get('file')}")
        assert abs(2600 * v / mass - 1) < 1e-6, (k, 2600 * v, mass)
    vols.add(round(v, 6))
    checked += 1
assert checked >= 3 and len(vols) == checked, (checked, vols)
PY

# Terrain: each block that ends beyond a line across the whole DEM has crossed it.
python3 - "$tmp" <<'PY' || fail "cannot write the grids"
import sys
d, n, cell = sys.argv[1], 61, 2.0
for name, val in (("dem.asc", lambda x, y: "%.4f" % (80 - 0.7 * x + 0.03 * x * x / 10)), ("classes.asc", lambda x, y: "1")):
    with open(f"{d}/{name}", "w") as f:
        f.write(f"ncols {n}\nnrows {n}\nxllcenter 0\nyllcenter 0\ncellsize {cell}\nNODATA_value -9999\n")
        for j in reversed(range(n)):
            f.write(" ".join(val(i * cell, j * cell) for i in range(n)) + "\n")
PY
cat > "$tmp/ter.yaml" <<EOF
name: ter
terrain: {dem: $tmp/dem.asc, materials: {raster: $tmp/classes.asc, classes: {1: rock}}}
materials:
  rock: {R_n: 0.5, R_t: 0.6, friction_angle: 30}
block: {shape: box, edges: [1.2, 1.0, 0.5], density: 2600, orientation: random, spin: [0, 6, 0]}
release: {points: [[6, 60]], height: 2.0, velocity: [6, 0, 0]}
barriers: [{name: l30, line: [[30, -1], [30, 121]]}, {name: l45, line: [[45, -1], [45, 121]]},
           {name: l60, line: [[60, -1], [60, 121]]}, {name: l75, line: [[75, -1], [75, 121]]}]
samples: 12
seed: 5
EOF
"$bin" trajectory "$tmp/ter.yaml" --out "$tmp/ter" --quiet --no-plots || fail "the terrain box did not run"
python3 - "$tmp/ter" <<'PY' || fail "a block on terrain passed a line without crossing it"
import csv, sys
end = {r["sample"]: float(r["end_x_m"]) for r in csv.DictReader(open(sys.argv[1] + "/samples.csv"))}
passed = 0
for r in csv.DictReader(open(sys.argv[1] + "/crossings.csv")):
    x = float(r["barrier"][1:])
    if end[r["sample"]] > x + 1:   # its lowest point ended beyond the line (+1 m: a vertex's reach)
        passed += 1
        assert r["reached"] == "1", (r["sample"], r["barrier"], end[r["sample"]])
assert passed >= 10, passed
PY

# outputs.vtk draws a rigid block's hull: a sphere or a point is refused, naming file:line.
for blk in "{shape: sphere, radius: 0.5, density: 2600}" "{shape: point, mass: 1000}"; do
    sed -e "s/^block: .*/block: $blk/" "$tmp/profile.yaml" > "$tmp/v.yaml"
    echo "outputs: {vtk: true}" >> "$tmp/v.yaml"
    line=$(grep -n "^outputs:" "$tmp/v.yaml" | cut -d: -f1)
    if "$bin" trajectory "$tmp/v.yaml" --out "$tmp/v" --quiet 2> "$tmp/v.err"; then
        fail "outputs.vtk with $blk was accepted"
    fi
    grep -q "v.yaml:$line: outputs.vtk = true: ParaView frames draw a rigid block's hull" "$tmp/v.err" \
        || fail "the vtk refusal: $(cat "$tmp/v.err")"
done
exit $((fails > 0))
