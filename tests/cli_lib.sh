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
