#!/bin/bash
# cli_report.sh - report.html: written by `run`, regenerated identically by
# `rockfuzz report DIR` from result.json + the PNGs (no evaluation), self-
# contained (only data: URIs and inline SVG), with the cut tables, influence
# bars, warnings and run metadata; rendered by headless Chromium into a
# screenshot that is checked not to be blank (skipped if chromium is absent).
# Usage: bash cli_report.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$src/tests/cli_run.lsan.supp"
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }

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
    timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$prof" \
        --screenshot="$tmp/shot.png" --window-size=1200,2000 "file://$h" > /dev/null 2>&1
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
EOF2
fi
[ $fails -eq 0 ] && echo "cli_report: all checks passed"
exit $((fails > 0))
