#!/bin/bash
# cli_report.sh - report.html: written by `run`, regenerated identically by
# `rockfuzz report DIR` from result.json + the PNGs (no evaluation), self-
# contained (only data: URIs and inline SVG), with the cut tables, influence
# bars, warnings and run metadata; the answer (summary) first, no "nan" shown
# without a reason, no warning for a check the study turned off, outputs that
# are 0 everywhere in one line; rendered by headless Chromium: the screenshot
# is not blank, its top is the summary box, and no image is broken (skipped
# if chromium is absent).
# Usage: bash cli_report.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir

cat > "$tmp/s.yaml" <<'EOF2'
name: report-check
scheme: reduced
levels: 4
parameters:
  x1: {tfn: [2, 1, 1], unit: m}
  x2: {tfn: [0, 1, 1]}
model:
  formula: {f: "x1*x2", h: "x2^2 + x1"}
options: {left_right: true}
EOF2
"$bin" run "$tmp/s.yaml" --out "$tmp/r" --quiet > /dev/null 2> "$tmp/r.err" || fail "run: $(cat "$tmp/r.err")"
h="$tmp/r/report.html"
[ -s "$h" ] || fail "run did not write report.html"
for s in "<table" "Output f" "Output h" "Fuzzy inputs" "data:image/png;base64," "<svg" "rho_left" "TM scheme" \
         "report-check" "Warnings" "not monotonic in x2" "distinct evaluations" "wall time"; do
    grep -q -- "$s" "$h" || fail "report.html lacks '$s'"
done
python3 - "$h" <<'EOF2' || fail "report.html is not self-contained"
import re, sys
t = open(sys.argv[1]).read()
refs = re.findall(r'(?:src|href)="([^"]*)"', t)
bad = [r for r in refs if not r.startswith("data:")]
assert not bad, bad
assert t.count("data:image/png;base64,") == 4, t.count("data:image/png;base64,")  # 2 inputs + 2 outputs
EOF2
python3 - "$h" <<'EOF2' || fail "report.html: summary first / nan without a reason"
import re, sys
t = open(sys.argv[1]).read()
assert t.index("id=summary") < t.index("<h2>Run") < t.index("<h2>Output"), "the summary is not first"
assert t.index("id=summary") < t.index("class=warn"), "warnings before the answer"
# the answer: f = x1*x2 on x1 in [1, 3], x2 in [-1, 1] -> [-3, 3] at membership 0, nominal 0
assert "<b>f</b></td><td class=l></td><td>-3 &ndash; 3</td><td>0</td>" in t, "summary row of f"
visible = re.sub(r"<[^>]*>", " ", re.sub(r'src="data:[^"]*"', "", t))
bad = [m.start() for m in re.finditer(r"\bnan\b", visible, re.I)]
assert not bad, [visible[max(0, i - 60):i + 20] for i in bad]
assert "tm_spec" not in t
EOF2
# a study that turns the monotonicity check off on purpose, with an output that is 0 everywhere
cat > "$tmp/off.yaml" <<'EOF2'
name: report-off
scheme: reduced
levels: 2
parameters:
  x1: {tfn: [2, 1, 1], unit: m}
model:
  formula: {f: "2*x1", z: "x1 - x1"}
options: {left_right: false}
EOF2
"$bin" run "$tmp/off.yaml" --out "$tmp/off" > "$tmp/off.out" 2> "$tmp/off.err" || fail "run off: $(cat "$tmp/off.err")"
grep -q "class=warn" "$tmp/off/report.html" && fail "a warning for the check the study turned off"
grep -q "off, as the study asks (options.left_right: false)" "$tmp/off/report.html" || fail "run table: check off"
grep -q "<p class=note>Not shown: z: 0 at every point of the study.</p>" "$tmp/off/report.html" \
    || fail "the zero output z is not summarised in one line"
grep -q "<h2>Output z" "$tmp/off/report.html" && fail "the zero output z got a section"
[ -e "$tmp/off/influence_lr_f.png" ] && fail "an empty left/right influence plot was drawn"
[ "$(grep -c "^Study '" "$tmp/off.out")" = 1 ] || fail "the console shows the study header $(grep -c "^Study '" "$tmp/off.out") times"
grep -qw "nan" "$tmp/off.out" && fail "the console shows nan: $(grep -w nan "$tmp/off.out")"
grep -q "^  f: 2 to 6, nominal 4; x1 100 %" "$tmp/off.out" || fail "console answer of f: $(cat "$tmp/off.out")"
cp "$h" "$tmp/first.html"
rm "$h"
"$bin" report "$tmp/r" > /dev/null 2> "$tmp/rep.err" || fail "report: $(cat "$tmp/rep.err")"
cmp -s "$h" "$tmp/first.html" || fail "rockfuzz report did not regenerate the same page"
[ -e "$tmp/r/report.html.tmp" ] && fail "report.html.tmp left behind"

# errors: no result, broken result
mkdir -p "$tmp/empty"
"$bin" report "$tmp/empty" > /dev/null 2> "$tmp/e.err" && fail "report without result.json succeeded"
grep -q "result.json" "$tmp/e.err" || fail "report without result.json: message $(cat "$tmp/e.err")"
mkdir -p "$tmp/broken" && echo '{"name": [1, 2' > "$tmp/broken/result.json"
"$bin" report "$tmp/broken" > /dev/null 2> "$tmp/b.err" && fail "report of a broken result.json succeeded"
grep -q "not a rockfuzz result" "$tmp/b.err" || fail "broken result.json: message $(cat "$tmp/b.err")"
[ -e "$tmp/broken/report.html" ] && fail "broken result.json produced a report"

# rendering
chrome=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$chrome" ]; then
    echo "cli_report: rendering check SKIPPED: chromium not found"
else
    prof=$(mktemp -d)
    flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
           --disable-component-update --disable-sync --user-data-dir="$prof")
    timeout 120 "$chrome" "${flags[@]}" --screenshot="$tmp/shot.png" --window-size=1200,2000 "file://$h" \
        > /dev/null 2>&1
    # broken images: a copy of the page counts, once loaded, the images the browser could not decode
    sed 's|</body>|<script>addEventListener("load",function(){var b=0,n=0;for(const i of document.images)'\
'{n++;if(!i.complete\|\|i.naturalWidth==0)b++;}var p=document.createElement("p");p.id="imgcheck";'\
'p.textContent="images "+n+" broken "+b;document.body.appendChild(p);});</script></body>|' "$h" > "$tmp/r/check.html"
    got=$(timeout 120 "$chrome" "${flags[@]}" --virtual-time-budget=5000 --dump-dom "file://$tmp/r/check.html" \
        2> /dev/null | grep -o 'images [0-9]* broken [0-9]*')
    [ "$got" = "images 4 broken 0" ] || fail "images in the rendered page: '$got' (expected 4, none broken)"
    rm -rf "$prof"
    python3 - "$tmp/shot.png" <<'EOF2' || fail "the screenshot of report.html is missing or blank"
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
pos, idat, w, h = 8, b"", 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    if kind == b"IHDR":
        w, h = struct.unpack(">II", data[pos + 8:pos + 16])
    if kind == b"IDAT":
        idat += data[pos + 8:pos + 8 + n]
    pos += 12 + n
raw = zlib.decompress(idat)
assert w >= 1000 and h >= 1500, (w, h)
# a blank page compresses to a handful of byte values; text, tables and plots give many
assert len(set(raw)) > 64, len(set(raw))
assert len(data) > 30000, len(data)
# decode the scanlines (8-bit RGB/RGBA, PNG filters 0-4) and look at the top of the page
bpp = {2: 3, 6: 4}[data[25]]
stride, rows, prev, pos = w * bpp, [], bytearray(w * bpp), 0
for y in range(h):
    ft, line = raw[pos], bytearray(raw[pos + 1:pos + 1 + stride])
    pos += 1 + stride
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b, c = prev[i], prev[i - bpp] if i >= bpp else 0
        if ft == 1: line[i] = (line[i] + a) & 255
        elif ft == 2: line[i] = (line[i] + b) & 255
        elif ft == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif ft == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
    if y > 260:
        break
def blue(y):  # pixels of the summary box's background #eef5ff in row y
    r = rows[y]
    return sum(1 for x in range(0, w * bpp, bpp) if (r[x], r[x + 1], r[x + 2]) == (0xee, 0xf5, 0xff))
assert max(blue(y) for y in range(40, 260)) > w // 2, "the top of the page is not the summary box"
EOF2
fi
[ $fails -eq 0 ] && echo "cli_report: all checks passed"
exit $((fails > 0))
