#!/bin/bash
# cli_traj_rel.sh - reliability of the trajectory side at the command line (issue 31):
#   4: a non-finite result is an error naming the inputs (trajectory runs, the
#      trajectory model in a study, `impact`, `material --json`), never null/0 with exit 0;
#  16: command-line counts go through one checked parser (range, no value taken
#      from the next option, no silent truncation); file seeds beyond 2^53 refused;
#  13: special files (FIFO, device) as profile CSV, DEM or impact cache are refused at once;
#  15: DEM steps that would give too many points, geographic DEMs, GDAL's own
#      error lines, a negative capacity: located messages naming the value.
# Usage: bash cli_traj_rel.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
# expect STATUS PATTERN CMD...: exit status STATUS and stderr matching PATTERN (grep -E)
expect() {
    local want=$1 pat=$2
    shift 2
    timeout -k 5 20 "$@" > "$tmp/out" 2> "$tmp/err"
    local rc=$?
    [ "$rc" = "$want" ] || { fail "$* -> exit $rc, want $want; stderr: $(head -c 400 "$tmp/err")"; return; }
    [ -z "$pat" ] || grep -Eq -- "$pat" "$tmp/err" || fail "$* -> stderr lacks /$pat/: $(head -c 400 "$tmp/err")"
}

cat > "$tmp/t.yaml" <<'Y'
name: t
profile:
  points: [[-10, 20], [0, 20], [0, 0], [100, 0]]
  material: rock
materials:
  rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}
block: {shape: point, mass: 1000}
release: {x: -0.5, y: 20.5, vx: 5, vy: 2}
bounce: {law: constant}
collectors: [{name: barrier, x: 6}]
Y

# ---- 4: non-finite results ----
sed 's/vx: 5,/vx: 1e200,/' "$tmp/t.yaml" > "$tmp/fast.yaml"
expect 1 "sample 0: the result collector total_energy \[J\] = inf is not finite.*vx, vy\) = \(1e\+200, 2\)" \
  "$bin" trajectory "$tmp/fast.yaml" --json
sed 's/^name: t/name: t\ngravity: 1e308/' "$tmp/t.yaml" > "$tmp/grav.yaml"
expect 1 "not finite.*gravity = 1e\+308 m/s\^2" "$bin" trajectory "$tmp/grav.yaml" --quiet
cat > "$tmp/study.yaml" <<Y
name: s
levels: 1
parameters:
  v: {tfn: [1e200, 1e199, 1e199]}
model:
  trajectory: {file: $tmp/t.yaml, bind: {v: release.vx}}
Y
expect 1 "not finite" "$bin" run "$tmp/study.yaml" --out "$tmp/s" --quiet
[ -e "$tmp/s/result.json" ] && fail "a study with non-finite trajectory outputs wrote result.json"
expect 1 "hertz result .* is not finite.*radius = 1e\+300 m" "$bin" impact --solver hertz --radius 1e300 --json
grep -q null "$tmp/out" && fail "impact --radius 1e300 printed nulls"
expect 1 "stresses are not finite.*--E 1e\+308 Pa" \
  "$bin" material --model elastic --E 1e308 --poisson 0.3 --path uniaxial_strain --strain 1 --json
[ -s "$tmp/out" ] && fail "material --json printed a non-finite document: $(cat "$tmp/out")"
# a large but finite result stays a result (a 1e306 kg block: 7e307 J)
sed 's/mass: 1000/mass: 1e306/' "$tmp/t.yaml" > "$tmp/heavy.yaml"
expect 0 "" "$bin" trajectory "$tmp/heavy.yaml" --json
python3 -c "import json,sys; e=json.load(open(sys.argv[1]))['statistics']['collectors']['barrier']['total_energy']; \
assert 7e307 < e['max'] < 7.1e307, e" "$tmp/out" || fail "heavy block energy"

# ---- 16: command-line counts and option values ----
(cd "$tmp" && expect 2 "--out needs a value \(got the option '--quiet'\)" "$bin" trajectory t.yaml --out --quiet)
[ -e "$tmp/--quiet" ] && fail "trajectory --out --quiet created a folder named --quiet"
(cd "$tmp" && expect 2 "--out needs a value \(got the option '--quiet'\)" "$bin" run study.yaml --out --quiet)
[ -e "$tmp/--quiet" ] && fail "run --out --quiet created a folder named --quiet"
expect 2 "--samples = 99999999999999999999: expected an integer in \[1, 100000000\]" \
  "$bin" trajectory "$tmp/t.yaml" --samples 99999999999999999999
expect 2 "--seed = 18446744073709551615: expected an integer in \[0, 9007199254740992\]" \
  "$bin" trajectory "$tmp/t.yaml" --seed 18446744073709551615
expect 2 "--threads = 5e9: expected an integer in \[0, 1024\]" "$bin" trajectory "$tmp/t.yaml" --threads 5e9
expect 2 "--threads = 100000: expected an integer" "$bin" trajectory "$tmp/t.yaml" --threads 100000
expect 2 "--samples = \+5: expected an integer" "$bin" trajectory "$tmp/t.yaml" --samples +5
expect 2 "--threads = 99999999999999999999: expected an integer in \[0, 1024\]" \
  "$bin" run "$tmp/study.yaml" --out "$tmp/s2" --threads 99999999999999999999
sed 's/^name: t/name: t\nseed: 9007199254740993/' "$tmp/t.yaml" > "$tmp/seed.yaml"
expect 1 "seed.yaml:2: seed = 9007199254740993: must lie in \[0, 9007199254740992\]" "$bin" trajectory "$tmp/seed.yaml"
sed 's/^name: t/name: t\nseed: 9.007199254740993e15/' "$tmp/t.yaml" > "$tmp/seed2.yaml"
expect 1 "seed2.yaml:2: seed = 9.007199254740993e15: from 2\^53 on" "$bin" trajectory "$tmp/seed2.yaml"
sed 's/^name: t/name: t\nseed: 9007199254740992/' "$tmp/t.yaml" > "$tmp/seed3.yaml"
expect 0 "" "$bin" trajectory "$tmp/seed3.yaml" --quiet

# ---- 13: special files are refused, never waited on or read forever ----
mkfifo "$tmp/fifo"
printf 'name: f\nprofile: {csv: fifo, material: rock}\nmaterials: {rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\nblock: {shape: point, mass: 1}\nrelease: {x: 1, y: 30}\n' > "$tmp/csvfifo.yaml"
expect 1 "csvfifo.yaml:2: profile.csv = fifo: .*fifo: cannot read the profile CSV: it is a pipe or FIFO" \
  "$bin" trajectory "$tmp/csvfifo.yaml"
sed 's|csv: fifo|csv: /dev/zero|' "$tmp/csvfifo.yaml" > "$tmp/csvdev.yaml"
expect 1 "/dev/zero: cannot read the profile CSV: it is not a regular file" "$bin" trajectory "$tmp/csvdev.yaml"
sed 's|^bounce: {law: constant}|bounce: {law: impact_model, impact: {solver: rigid, cache: /dev/full}}|; s|block: {shape: point, mass: 1000}|block: {shape: sphere, radius: 0.5, density: 2600}|' \
  "$tmp/t.yaml" > "$tmp/cache.yaml"
expect 1 "/dev/full: cannot read the impact cache: it is a device" "$bin" trajectory "$tmp/cache.yaml" --quiet
printf 'name: f\nprofile: {dem: {file: DEM, line: [[5, 20], [35, 20]], step: STEP}, material: rock}\nmaterials: {rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\nblock: {shape: point, mass: 1}\nrelease: {x: 1, y: 40}\n' > "$tmp/dem.tmpl"
dem() { sed "s|DEM|$1|; s|STEP|$2|" "$tmp/dem.tmpl" > "$tmp/dem.yaml"; }
dem fifo 1
if "$bin" trajectory "$tmp/dem.yaml" 2>&1 | grep -q "built without GDAL"; then
    echo "no GDAL: DEM cases skipped"
else
    expect 1 "fifo: cannot read the DEM: it is a pipe or FIFO" "$bin" trajectory "$tmp/dem.yaml"
    dem /dev/zero 1
    expect 1 "/dev/zero: cannot read the DEM: it is a device" "$bin" trajectory "$tmp/dem.yaml"

# ---- 15: DEM validation located and before any work ----
    printf 'ncols 4\nnrows 4\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n' > "$tmp/d.asc"
    for _ in 1 2 3 4; do echo "30 20 10 0" >> "$tmp/d.asc"; done
    dem d.asc 1
    expect 0 "" "$bin" trajectory "$tmp/dem.yaml" --quiet
    dem d.asc 1e-9
    expect 1 "dem.yaml:2: profile.dem.step = 1e-9: the line would be sampled at 3e\+10 points, more than 1000000" \
      "$bin" trajectory "$tmp/dem.yaml"
    dem d.asc 1e-300
    expect 1 "dem.yaml:2: profile.dem.step = 1e-300: the line would be sampled" "$bin" trajectory "$tmp/dem.yaml"
    if command -v gdal_translate > /dev/null; then
        gdal_translate -q -a_srs EPSG:4326 "$tmp/d.asc" "$tmp/geo.tif"
        dem geo.tif 1
        expect 1 "geo.tif' is in geographic coordinates \(degrees\)" "$bin" trajectory "$tmp/dem.yaml"
        # a damaged GeoTIFF: GDAL's "ERROR 1" lines stay off the console, its reason is in our message
        python3 -c "
print('ncols 200\nnrows 200\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999')
for r in range(200): print(' '.join(str(200 - c) for c in range(200)))" > "$tmp/big.asc"
        gdal_translate -q -ot Float64 "$tmp/big.asc" "$tmp/big.tif"
        head -c 200000 "$tmp/big.tif" > "$tmp/trunc.tif"
        sed "s|DEM|trunc.tif|; s|STEP|1|; s|\[35, 20\]|[150, 20]|" "$tmp/dem.tmpl" > "$tmp/dem.yaml"
        expect 1 "cannot read the elevations of '.*trunc.tif' \(GDAL: " "$bin" trajectory "$tmp/dem.yaml"
        grep -q "^ERROR" "$tmp/err" && fail "GDAL's own error lines reached the console: $(cat "$tmp/err")"
    fi
fi
sed 's/collectors: \[{name: barrier, x: 6}\]/collectors:\n  - {name: barrier, x: 6, capacity: -1}/' "$tmp/t.yaml" > "$tmp/cap.yaml"
expect 1 "cap.yaml:11: collectors.barrier.capacity = -1: must be >= 0" "$bin" trajectory "$tmp/cap.yaml"

# ---- 14: memory estimated and refused with the figure before allocating (10^8 x 200 crossings of 104 B, ~2.1e3 GB) ----
{ grep -v '^collectors' "$tmp/t.yaml" | sed 's/vx: 5,/vx: {uniform: [4, 6]},/'; echo "samples: 100000000"
  echo "collectors:"; for i in $(seq 200); do echo "  - {name: c$i, x: $((i % 90 + 1))}"; done; } > "$tmp/huge.yaml"
expect 1 "samples = 100000000 with 200 collectors need 2\.[0-9]+e\+03 GB for the per-sample results, more than" \
  "$bin" trajectory "$tmp/huge.yaml" --quiet
# a result.json nested 10^6 deep is refused before it is parsed (it took 3.5 GB)
mkdir "$tmp/deep" && head -c 1000000 /dev/zero | tr '\0' '[' > "$tmp/deep/result.json"
# (under 1 GB of address space, unless the binary is a sanitizer build, which reserves terabytes)
( ldd "$bin" 2>/dev/null | grep -q libasan || ulimit -v 1000000
  expect 1 "result.json: nested deeper than 64 levels" "$bin" report "$tmp/deep" )

[ "$fails" = 0 ] || { echo "$fails failure(s)" >&2; exit 1; }
echo "cli_traj_rel: all passed"
