# cli_lib.sh - the preamble every tests/cli_*.sh sources (not a test itself:
# CMakeLists.txt leaves it out of the cli_*.sh glob).  A script starts
#     set -u
#     . "${BASH_SOURCE[0]%/*}/cli_lib.sh"
#     cli_tmpdir        # when it needs a temporary folder
# and is run as `bash cli_NAME.sh ROCKFUZZ_BINARY SOURCE_DIR`.  It gets:
#   bin          the rockfuzz binary (the first argument)
#   src          the source tree (the second argument, else this file's ..)
#   fails, fail  the failure count and `fail MESSAGE` (prints FAIL: MESSAGE, counts it)
#   cli_tmpdir   tmp = a new folder, removed at exit (a script that sets its
#                own EXIT trap after it removes "$tmp" there)
# and the leak suppressions of sanitizer builds (fontconfig's process-lifetime
# caches are not our leaks).
bin=${1:?usage: bash $0 ROCKFUZZ_BINARY SOURCE_DIR}
src=${2:-$(cd "${BASH_SOURCE[0]%/*}/.." && pwd)}
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$src/tests/cli_run.lsan.supp"
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
cli_tmpdir() {
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
}

# cli_render_check NAME HTML MIN_IMAGES [SHOT]: HTML rendered by headless
# Chromium has at least MIN_IMAGES images, none broken, and a screenshot
# (1200x900, kept in SHOT if given) that is not blank (> 30 kB); a skip is
# said when chromium is absent.
cli_render_check() {
    local name=$1 html=$2 min=$3 shot=${4:-} chrome prof got n
    chrome=$(command -v chromium || command -v chromium-browser || true)
    if [ -z "$chrome" ]; then
        echo "$name: browser check SKIPPED: chromium not found"
        return 0
    fi
    prof=$(mktemp -d)
    local flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
                 --disable-component-update --disable-sync --user-data-dir="$prof")
    sed 's|</body>|<script>addEventListener("load",function(){var b=0,n=0;for(const i of document.images)'\
'{n++;if(!i.complete\|\|i.naturalWidth==0)b++;}var p=document.createElement("p");p.id="imgcheck";'\
'p.textContent="images "+n+" broken "+b;document.body.appendChild(p);});</script></body>|' \
        "$html" > "${html%.html}.check.html"
    got=$(timeout 120 "$chrome" "${flags[@]}" --virtual-time-budget=8000 --dump-dom "file://${html%.html}.check.html" \
          2> /dev/null | grep -o 'images [0-9]* broken [0-9]*')
    echo "$name: rendered page: $got"
    n=$(echo "$got" | awk '{print $2}')
    [ -n "$n" ] && [ "$n" -ge "$min" ] && [ "$(echo "$got" | awk '{print $4}')" = 0 ] \
        || fail "images in the rendered page: '$got' (expected $min or more, none broken)"
    shot=${shot:-$prof/shot.png}
    timeout 120 "$chrome" "${flags[@]}" --virtual-time-budget=8000 --screenshot="$shot" --window-size=1200,900 \
        "file://$html" > /dev/null 2>&1
    [ "$(stat -c %s "$shot" 2> /dev/null || echo 0)" -gt 30000 ] || fail "the screenshot of $html is missing or blank"
    rm -rf "$prof" "${html%.html}.check.html"
}
