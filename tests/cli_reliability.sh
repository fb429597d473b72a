#!/bin/bash
# cli_reliability.sh - the faults a real user meets (issue 12), each with a
# short timeout:
#   SIGTERM / SIGINT: clean stop, exit status 128+signal, finished evaluations
#     stored, every program and every descendant (also one that left with
#     setsid) gone; SIGKILL of rockfuzz: the programs die with it;
#   a second run into a folder in use is refused, naming the holder;
#   a non-empty folder that is not a rockfuzz run is refused (--force accepts);
#   a damaged store is refused with nothing in the folder changed, the last
#     result.json and `report` still work, --fresh moves it aside;
#   an edited program is not served from the store;
#   the model's warnings reach the report also when every point was stored;
#   count options are bounded on the command line.
# Usage: bash cli_reliability.sh ROCKFUZZ_BINARY SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"
cli_tmpdir
pid=""
cleanup() {
    [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null
    # anything the test models started and the test failed to see killed
    [ -f "$tmp/pids" ] && while read -r p; do kill -9 "$p" 2>/dev/null; done < "$tmp/pids"
    rm -rf "$tmp"
}
trap cleanup EXIT

# A slow model that leaves a setsid grandchild behind (which must not survive).
cat > "$tmp/model.sh" <<EOF2
#!/bin/sh
echo \$\$ >> "$tmp/pids"
setsid sleep 300 &
echo \$! >> "$tmp/pids"
sleep 0.25
awk -v a="\$1" -v b="\$2" 'BEGIN { printf "f = %.17g\n", a*b + b }'
EOF2
chmod +x "$tmp/model.sh"
cat > "$tmp/s.yaml" <<EOF2
name: reliability
scheme: reduced
levels: 8
parameters:
  a: {tfn: [2, 1, 1]}
  b: {tfn: [3, 1, 2]}
model:
  program: {argv: ["$tmp/model.sh", "{a}", "{b}"], outputs: {f: {}}, workdir: "$tmp/work", timeout: 30}
options: {left_right: false, jobs: 2}
EOF2
total=33 # 1 nominal + 8 levels x 4 corners

alive() { # pids of the recorded processes still running (zombies do not count)
    [ -f "$tmp/pids" ] || return 0
    while read -r p; do
        s=$(ps -o stat= -p "$p" 2>/dev/null) && [ "${s#Z}" = "$s" ] && echo "$p"
    done < "$tmp/pids"
}
wait_stored() { # $1 = dir: wait until some evaluations are stored (at most 10 s)
    for _ in $(seq 100); do
        n=$("$bin" status "$1" 2>/dev/null | awk '/^Done/ {print $2}')
        [ -n "$n" ] && [ "$n" -ge 2 ] && return 0
        sleep 0.1
    done
    return 1
}

# ---- SIGTERM and SIGINT: clean stop ----
for sig in TERM INT; do
    rm -f "$tmp/pids"
    # not under timeout(1): it would pass the signal on twice (and a second SIGINT means "now")
    "$bin" run "$tmp/s.yaml" --out "$tmp/$sig" --quiet > /dev/null 2> "$tmp/$sig.err" &
    pid=$!
    wait_stored "$tmp/$sig" || fail "$sig: nothing stored within 10 s: $(cat "$tmp/$sig.err")"
    kill -s $sig $pid
    for _ in $(seq 100); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
    kill -0 $pid 2>/dev/null && { fail "$sig: still running 10 s after the signal"; kill -9 $pid; }
    wait $pid; rc=$?
    pid=""
    want=$((128 + $(kill -l $sig)))
    [ $rc -eq $want ] || fail "$sig: exit status $rc, expected $want: $(cat "$tmp/$sig.err")"
    grep -q "interrupted" "$tmp/$sig.err" || fail "$sig: message: $(cat "$tmp/$sig.err")"
    left=$(alive)
    [ -z "$left" ] || fail "$sig: processes survived the run: $left"
    [ -e "$tmp/$sig/result.json" ] && fail "$sig: result.json written by an interrupted run"
    # the rerun evaluates only what is missing
    timeout 60 "$bin" run "$tmp/s.yaml" --out "$tmp/$sig" --quiet --progress=jsonl > "$tmp/$sig.out" 2> "$tmp/$sig.err2" \
        || fail "$sig: resume: $(tail -3 "$tmp/$sig.err2")"
    n=$(grep -c '"event"' "$tmp/$sig.err2")
    stored=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['evaluations']['from_store'])" "$tmp/$sig/result.json" 2>/dev/null || echo 0)
    [ "$stored" -ge 2 ] && [ $((n + stored)) -eq $total ] || fail "$sig: resume evaluated $n with $stored stored (total $total)"
    left=$(alive)
    [ -z "$left" ] || fail "$sig: processes survived the resumed run: $left"
done

# ---- SIGKILL of rockfuzz: its programs and their descendants die with it ----
rm -f "$tmp/pids"
"$bin" run "$tmp/s.yaml" --out "$tmp/kill" --quiet > /dev/null 2>&1 &
pid=$!
wait_stored "$tmp/kill" || fail "SIGKILL: nothing stored within 10 s"
kill -9 $pid; wait $pid 2>/dev/null; pid=""
for _ in $(seq 50); do [ -z "$(alive)" ] && break; sleep 0.1; done
left=$(alive)
[ -z "$left" ] || fail "SIGKILL: processes survived rockfuzz: $left"

# ---- two runs into one folder: the second is refused and names the holder ----
rm -f "$tmp/pids"
timeout 30 "$bin" run "$tmp/s.yaml" --out "$tmp/lock" --quiet > /dev/null 2>&1 &
pid=$!
wait_stored "$tmp/lock" || fail "lock: first run stored nothing"
timeout 10 "$bin" run "$tmp/s.yaml" --out "$tmp/lock" --quiet > /dev/null 2> "$tmp/lock.err"; rc=$?
[ $rc -eq 1 ] || fail "lock: second run exit status $rc"
grep -q "in use by another rockfuzz run (pid [0-9]* on .*study $tmp/s.yaml)" "$tmp/lock.err" || fail "lock: message: $(cat "$tmp/lock.err")"
"$bin" status "$tmp/lock" | grep -q "^State  *running (pid [0-9]* on .*study $tmp/s.yaml)" \
    || fail "lock: status does not name the holder: $("$bin" status "$tmp/lock" | grep State)"
kill -TERM $pid; wait $pid 2>/dev/null; pid=""
"$bin" status "$tmp/lock" | grep -q "^State  *stopped" || fail "lock: status after the run: $("$bin" status "$tmp/lock" | grep State)"

# ---- --out: a folder of the user's is not overwritten ----
mkdir -p "$tmp/mine" && echo "my notes" > "$tmp/mine/inputs.csv"
cat > "$tmp/f.yaml" <<'EOF2'
levels: 2
parameters:
  x: {tfn: [2, 1, 1]}
model: {formula: {y: "x*x"}}
EOF2
"$bin" run "$tmp/f.yaml" --out "$tmp/mine" --quiet --no-plots > /dev/null 2> "$tmp/mine.err" && fail "--out: foreign folder accepted"
grep -q "not empty.*holds no rockfuzz run.*--force" "$tmp/mine.err" || fail "--out: message: $(cat "$tmp/mine.err")"
[ "$(cat "$tmp/mine/inputs.csv")" = "my notes" ] || fail "--out: the user's file was changed"
[ "$(ls "$tmp/mine")" = "inputs.csv" ] || fail "--out: files were added: $(ls "$tmp/mine")"
"$bin" run "$tmp/f.yaml" --out "$tmp/mine" --quiet --no-plots --force > /dev/null 2>&1 || fail "--force refused"
# a rockfuzz folder is reused without --force
"$bin" run "$tmp/f.yaml" --out "$tmp/mine" --quiet --no-plots > /dev/null 2>&1 || fail "rerun into a run folder refused"

# ---- a damaged store: refused, nothing changed, the last result kept ----
cat > "$tmp/big.yaml" <<'EOF2'
scheme: general
levels: 6
parameters:
  x: {tfn: [2, 1, 1]}
  y: {tfn: [3, 1, 1]}
  z: {tfn: [1, 0.5, 0.5]}
model: {formula: {f: "x*y + z"}}
options: {left_right: false}
EOF2
"$bin" run "$tmp/big.yaml" --out "$tmp/dmg" --quiet --no-plots > /dev/null 2>&1 || fail "damaged: first run failed"
size=$(stat -c %s "$tmp/dmg/store.sqlite")
[ "$size" -ge 16384 ] || fail "damaged: store too small to damage its middle ($size bytes)"
python3 - "$tmp/dmg/store.sqlite" <<'EOF2'
import sys
p = sys.argv[1]
b = bytearray(open(p, 'rb').read())
mid = len(b) // 2 // 4096 * 4096   # a b-tree page in the middle: its header and cells
for i in range(mid, mid + 64):
    b[i] ^= 0x5a
open(p, 'wb').write(bytes(b))
EOF2
(cd "$tmp/dmg" && ls -la --time-style=+%s.%N | awk '$7 != "." && $7 != ".." {print $5, $6, $7}' > "$tmp/dmg.before"; md5sum * > "$tmp/dmg.md5")
"$bin" run "$tmp/big.yaml" --out "$tmp/dmg" --quiet --no-plots > /dev/null 2> "$tmp/dmg.err"; rc=$?
[ $rc -eq 1 ] || fail "damaged: exit status $rc"
grep -q "store.sqlite is damaged" "$tmp/dmg.err" || fail "damaged: message: $(cat "$tmp/dmg.err")"
(cd "$tmp/dmg" && md5sum -c --quiet "$tmp/dmg.md5") > /dev/null 2>&1 || fail "damaged: files in the folder changed"
(cd "$tmp/dmg" && ls -la --time-style=+%s.%N | awk '$7 != "." && $7 != ".." {print $5, $6, $7}') | cmp -s - "$tmp/dmg.before" \
    || fail "damaged: the folder listing changed: $(cd "$tmp/dmg" && ls -la --time-style=+%s.%N | awk '$7 != "." && $7 != ".." {print $5, $6, $7}' | diff - "$tmp/dmg.before")"
"$bin" report "$tmp/dmg" > /dev/null 2>&1 || fail "damaged: report from the kept result.json failed"
"$bin" run "$tmp/big.yaml" --out "$tmp/dmg" --quiet --no-plots --fresh > /dev/null 2> "$tmp/dmg2.err" \
    || fail "damaged: --fresh: $(cat "$tmp/dmg2.err")"
[ -f "$tmp/dmg/store.sqlite.damaged" ] || fail "damaged: --fresh did not keep the damaged store aside"

# ---- an edited program is not served from the store ----
cat > "$tmp/p.sh" <<'EOF2'
#!/bin/sh
echo "f = $1"
EOF2
chmod +x "$tmp/p.sh"
cat > "$tmp/p.yaml" <<EOF2
levels: 2
parameters:
  a: {tfn: [2, 1, 1]}
model:
  program: {argv: ["$tmp/p.sh", "{a}"], outputs: {f: {}}, workdir: "$tmp/work"}
options: {left_right: false}
EOF2
"$bin" run "$tmp/p.yaml" --out "$tmp/edit" --quiet --no-plots > /dev/null 2>&1 || fail "edit: first run"
sed -i 's/echo "f = $1"/echo "f = 7"/' "$tmp/p.sh"
"$bin" run "$tmp/p.yaml" --out "$tmp/edit" --quiet --no-plots > /dev/null 2> "$tmp/edit.err" && fail "edit: the edited program was served from the store"
grep -q "different model or its settings" "$tmp/edit.err" || fail "edit: message: $(cat "$tmp/edit.err")"

# ---- the model's warnings reach the report as data, also when every point comes from the store ----
cat > "$tmp/w.yaml" <<'EOF2'
levels: 1
parameters:
  velocity: {tfn: [10, 1, 1]}
model:
  impact: {solver: fem, refinement: 2, domain_factor: 4}
EOF2
for k in 1 2; do
    "$bin" run "$tmp/w.yaml" --out "$tmp/w" --quiet --no-plots > /dev/null 2> "$tmp/w.err" || fail "warnings: run $k: $(cat "$tmp/w.err")"
done
python3 - "$tmp/w/result.json" <<'EOF2' || fail "warnings: the reflection warning of the first run is not in the second run's report"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["evaluations"]["evaluated"] == 0, r["evaluations"]
assert any("P waves reflected" in w and "earlier run" in w for w in r["warnings"]), r["warnings"]
EOF2

# ---- count options are bounded ----
"$bin" run "$tmp/f.yaml" --out "$tmp/j" --jobs 100000 > /dev/null 2> "$tmp/j.err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--jobs = 100000: expected an integer in \[0, 1024\]" "$tmp/j.err" || fail "--jobs 100000: status $rc: $(cat "$tmp/j.err")"
"$bin" impact --solver fem --threads 100000 > /dev/null 2> "$tmp/t.err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--threads '100000'" "$tmp/t.err" || fail "--threads 100000: status $rc: $(cat "$tmp/t.err")"

[ $fails -eq 0 ] || { echo "$fails check(s) failed" >&2; exit 1; }
echo "cli_reliability: all checks passed"
