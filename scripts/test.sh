#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), builds everything and runs the whole test suite:
#   1. Release build, all tests (labels: unit, cli, python, package, browser), the Python module
#      installed for the user;
#   2. AddressSanitizer + UndefinedBehaviorSanitizer build of everything, the tests again (the CLI
#      tests then run the sanitized `penumbra` binary) but the slow-labelled ones and the long
#      accuracy sweeps of tests/release-only.txt.
#   3. the fuzz targets of tests/fuzz (clang's libFuzzer, ASan + UBSan), 20 s each from the seed
#      corpus with a fixed seed (scripts/fuzz.sh; run it alone for longer runs).
# Set PENUMBRA_SKIP_SANITIZE=1 to run only the first part, PENUMBRA_SKIP_FUZZ=1 to skip the third.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --browser
jobs=${PENUMBRA_JOBS:-2}

echo "== Release build and tests"
# Tests ON explicitly: scripts/render.sh configures the same folder without them, and the cache keeps it.
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_BUILD_TESTS=ON >/dev/null
cmake --build build/release -j"$jobs"
scripts/install-python.sh build/release
ctest --test-dir build/release -j"$jobs" --output-on-failure --timeout 900

if [ "${PENUMBRA_SKIP_SANITIZE:-0}" != 1 ]; then
  echo "== ASan + UBSan build and tests"
  # Not the tests labelled slow (the browser and the package's consumer: no code of ours runs
  # differently sanitized) nor those of tests/release-only.txt (long accuracy sweeps).
  release_only="^($(grep -v '^#' tests/release-only.txt | paste -sd'|'))\$"
  cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPENUMBRA_SANITIZE=ON >/dev/null
  cmake --build build/sanitize -j"$jobs"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS=suppressions="$PWD/tests/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build/sanitize -j"$jobs" --output-on-failure --timeout 1800 -LE slow -E "$release_only"
fi

if [ "${PENUMBRA_SKIP_FUZZ:-0}" != 1 ]; then
  echo "== fuzz targets under ASan + UBSan"
  PENUMBRA_FUZZ_SEED=${PENUMBRA_FUZZ_SEED:-1} scripts/fuzz.sh "${PENUMBRA_FUZZ_SECONDS:-20}"
fi
