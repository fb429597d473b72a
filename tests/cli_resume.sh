#!/bin/bash
# cli_resume.sh - a study killed with SIGKILL mid-run and restarted loses at
# most the evaluations in flight: an external-program model sleeps 0.05 s per
# evaluation, the run is killed after some results are stored, the rerun
# evaluates exactly total - stored points and its cuts equal those of an
# uninterrupted run bit for bit.  Also: `status` while stopped, a changed
# model setting refused (--fresh starts over), foreign/corrupt store files
# refused and left unchanged, failures stored with --tolerate-failures.
# Usage: bash cli_resume.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
pid=""
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp"' EXIT

cat > "$tmp/model.sh" <<'EOF2'
#!/bin/sh
# f = a*b + c^2, g = a/b; NaN-free; slow on purpose
sleep 0.05
awk -v a="$1" -v b="$2" -v c="$3" 'BEGIN { printf "f = %.17g\ng = %.17g\n", a*b + c*c, a/b }'
EOF2
chmod +x "$tmp/model.sh"
study() { # $1 = file, $2 = extra model text
cat > "$1" <<EOF2
name: resume
scheme: reduced
levels: 8
parameters:
  a: {tfn: [2, 1, 1]}
  b: {tfn: [3, 1, 2]}
  c: {tfn: [1, 0.5, 0.5]}
model:
  program:
    argv: ["$tmp/model.sh", "{a}", "{b}", "{c}"$2]
    outputs: {f: {}, g: {}}
    workdir: "$tmp/work"
options: {left_right: false, jobs: 2}
EOF2
}
mkdir -p "$tmp/work"
study "$tmp/s.yaml" ""
total=65   # 1 nominal + 8 levels x 8 corners

# ---- uninterrupted reference ----
"$bin" run "$tmp/s.yaml" --out "$tmp/ref" --quiet > /dev/null 2> "$tmp/ref.err" || fail "reference run: $(cat "$tmp/ref.err")"
python3 - "$tmp/ref/result.json" $total <<'EOF2' || fail "reference: distinct count"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["evaluations"]["distinct"] == int(sys.argv[2]), r["evaluations"]
assert r["evaluations"]["evaluated"] == int(sys.argv[2]), r["evaluations"]
EOF2

# ---- killed run ----
"$bin" run "$tmp/s.yaml" --out "$tmp/k" --quiet > /dev/null 2>&1 &
pid=$!
stored=0
for _ in $(seq 1 200); do
    sleep 0.05
    stored=$("$bin" status "$tmp/k" 2>/dev/null | awk '/^Done/ {print $2}')
    [ -n "$stored" ] && [ "$stored" -ge 10 ] && break
done
kill -9 $pid 2>/dev/null
wait $pid 2>/dev/null
pid=""
[ -e "$tmp/k/result.json" ] && fail "killed run left a result.json"
"$bin" status "$tmp/k" > "$tmp/status.txt" 2>&1 || fail "status after kill: $(cat "$tmp/status.txt")"
stored=$(awk '/^Done/ {print $2}' "$tmp/status.txt")
grep -q "^Planned points  $total " "$tmp/status.txt" || fail "status: planned total $total missing: $(cat "$tmp/status.txt")"
grep -q "^State *stopped" "$tmp/status.txt" || fail "status: not 'stopped' after the kill: $(cat "$tmp/status.txt")"
grep -q "^Time left" "$tmp/status.txt" || fail "status: no time left line"
grep -q "^Rate .*evaluations/s" "$tmp/status.txt" || fail "status: no rate"
if [ -z "$stored" ] || [ "$stored" -lt 10 ] || [ "$stored" -ge $total ]; then
    fail "kill came at the wrong time: $stored of $total stored"
fi

# ---- resumed run: exactly the missing points, one JSON line each ----
"$bin" run "$tmp/s.yaml" --out "$tmp/k" --progress=jsonl > "$tmp/k.out" 2> "$tmp/k.err" || fail "resume run: $(tail -3 "$tmp/k.err")"
fresh=$(grep -c '"event": "evaluation"' "$tmp/k.err")
[ "$fresh" -eq $((total - stored)) ] || fail "resume evaluated $fresh points, expected $total - $stored = $((total - stored))"
python3 - "$tmp/ref/result.json" "$tmp/k/result.json" "$stored" <<'EOF2' || fail "resumed result differs from the uninterrupted one"
import json, sys
a = json.load(open(sys.argv[1])); b = json.load(open(sys.argv[2]))
for k in ("f", "g"):
    for side in ("lower", "upper", "x_lower", "x_upper", "nominal"):
        assert a["outputs"][k][side] == b["outputs"][k][side], (k, side)
    assert a["outputs"][k]["influence"] == b["outputs"][k]["influence"], k
assert b["evaluations"]["from_store"] == int(sys.argv[3]), b["evaluations"]
EOF2
last=$(grep '"event"' "$tmp/k.err" | tail -1)
echo "$last" | grep -q "\"done\": $total, \"total\": $total" || fail "last JSON line: $last"
"$bin" status "$tmp/k" | grep -q "^State *finished" || fail "status after the resumed run is not 'finished'"

# ---- a third run evaluates nothing ----
"$bin" run "$tmp/s.yaml" --out "$tmp/k" --progress=jsonl > /dev/null 2> "$tmp/k3.err" || fail "third run"
[ "$(grep -c '"event"' "$tmp/k3.err")" -eq 0 ] || fail "third run evaluated points again"

# ---- a changed model setting is refused; nothing overwritten; --fresh starts over ----
study "$tmp/s2.yaml" ', "extra"'
cp "$tmp/k/store.sqlite" "$tmp/before.sqlite"
"$bin" run "$tmp/s2.yaml" --out "$tmp/k" --quiet > /dev/null 2> "$tmp/chg.err" && fail "changed model accepted"
grep -q "different model or its settings" "$tmp/chg.err" || fail "changed model message: $(cat "$tmp/chg.err")"
grep -q -- "--fresh" "$tmp/chg.err" || fail "changed model message does not mention --fresh"
[ -e "$tmp/k/result.json" ] || fail "refused run removed the old result.json"
"$bin" run "$tmp/s2.yaml" --out "$tmp/k" --fresh --quiet --progress=jsonl > /dev/null 2> "$tmp/fresh.err" || fail "--fresh: $(tail -2 "$tmp/fresh.err")"
n=$(grep -c "\"event\"" "$tmp/fresh.err"); [ "$n" -eq $total ] || fail "--fresh evaluated $n of $total: $(tail -2 "$tmp/fresh.err")"

# ---- foreign and corrupt files: refused, untouched ----
mkdir -p "$tmp/f" "$tmp/c"
python3 -c "import sqlite3,sys; c=sqlite3.connect(sys.argv[1]); c.execute('create table t(a)'); c.commit()" "$tmp/f/store.sqlite"
head -c 3000 /dev/urandom > "$tmp/c/store.sqlite"
for d in f c; do
    cp "$tmp/$d/store.sqlite" "$tmp/$d.orig"
    "$bin" run "$tmp/s.yaml" --out "$tmp/$d" --fresh --quiet > /dev/null 2> "$tmp/$d.err"; rc=$?
    [ $rc -ne 0 ] || fail "$d: accepted a non-rockfuzz store"
    grep -q "not a rockfuzz result store" "$tmp/$d.err" || fail "$d: message: $(cat "$tmp/$d.err")"
    cmp -s "$tmp/$d/store.sqlite" "$tmp/$d.orig" || fail "$d: the file was modified"
    "$bin" status "$tmp/$d" > /dev/null 2>&1 && fail "$d: status accepted it"
done

# ---- failures: stored with their parameters; default stops, --tolerate-failures goes on ----
cat > "$tmp/bad.sh" <<'EOF2'
#!/bin/sh
case "$1" in 1|1.0) echo "solver diverged" >&2; exit 3 ;; esac
awk -v a="$1" -v b="$2" 'BEGIN { printf "f = %.17g\n", a*b }'
EOF2
chmod +x "$tmp/bad.sh"
cat > "$tmp/bad.yaml" <<EOF2
scheme: reduced
levels: 2
parameters:
  a: {tfn: [2, 1, 1]}
  b: {tfn: [3, 1, 2]}
model:
  program: {argv: ["$tmp/bad.sh", "{a}", "{b}"], outputs: {f: {}}, workdir: "$tmp/work"}
options: {left_right: false, jobs: 1}
EOF2
"$bin" run "$tmp/bad.yaml" --out "$tmp/b" --quiet > /dev/null 2> "$tmp/b.err" && fail "failing model: run succeeded"
"$bin" status "$tmp/b" > "$tmp/b.status" || fail "status of the failed run"
grep -q "^Failed *1" "$tmp/b.status" || fail "status: failed count: $(cat "$tmp/b.status")"
grep -q "x = (1, " "$tmp/b.status" || fail "status: failed parameter vector not listed"
"$bin" run "$tmp/bad.yaml" --out "$tmp/b" --tolerate-failures --quiet > "$tmp/b2.out" 2> "$tmp/b2.err" || fail "--tolerate-failures run: $(cat "$tmp/b2.err")"
grep -q "WARNING: 2 evaluations failed" "$tmp/b2.err" || fail "no loud warning: $(cat "$tmp/b2.err")"
python3 - "$tmp/b/result.json" <<'EOF2' || fail "tolerated failures not in result.json"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["evaluations"]["failed_points"] == 2, r["evaluations"]
assert any("LEFT OUT" in w for w in r["warnings"]), r["warnings"]
assert r["outputs"]["f"]["lower"][0] == 3.75, r["outputs"]["f"]["lower"]   # a=1 excluded: level-1 corner 1.5*2.5 (else 2)
EOF2
grep -q "LEFT OUT" "$tmp/b/report.html" || fail "report.html does not show the failure warning"

[ $fails -eq 0 ] && echo "cli_resume: all checks passed"
exit $((fails > 0))
