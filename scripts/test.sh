#!/usr/bin/env bash
# The whole test suite, as CI runs it: installs the Debian packages, builds
# an optimised tree and an AddressSanitizer + UBSan tree, and runs ctest in
# both.  `scripts/test.sh --quick` skips the sanitizer tree.  The sanitizer
# half leaves out the tests labelled `accuracy` (tests/test_*_accuracy.c: fine
# meshes against references; their code paths run there in coarse variants),
# see CMakeLists.txt and docs/user-guide.md, "Tests".
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"
if [ "${1:-}" != "--quick" ]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DROCKFUZZ_SANITIZE=ON
  cmake --build build-asan -j"$jobs"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs" -LE accuracy
fi
