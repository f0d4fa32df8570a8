#!/usr/bin/env bash
# Builds the fuzz targets of tests/fuzz with clang's libFuzzer under ASan + UBSan and runs each for
# a while from the seed corpus (made by make_seeds) and the regressions (every input that once
# crashed: tests/fuzz/regressions/<target>/). A crash, a leak, undefined behaviour, a timeout or
# running out of memory stops with the input written to build/fuzz/crashes/ and exit status 1:
# keep that input in tests/fuzz/regressions/<target>/ once it is fixed.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 20 s each; gltf scene image xyz)
# Longer runs: scripts/fuzz.sh 3600 gltf  (the corpus in build/fuzz/corpus/ grows between runs).
# PENUMBRA_FUZZ_SEED fixes libFuzzer's seed (scripts/test.sh uses 1); unset, each run draws one.
# PENUMBRA_FUZZ_TIMEOUT: seconds one input may take before it counts as a hang (default 10; raise it
# when several fuzzers share a loaded machine: under ASan an input of 0.2 s took over 10 s there).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
seconds=${1:-20}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(gltf scene image xyz)
jobs=${PENUMBRA_JOBS:-2}

CC=clang-14 CXX=clang++-14 cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DPENUMBRA_FUZZ=ON -DPENUMBRA_SANITIZE=ON -DPENUMBRA_BUILD_TESTS=OFF -DPENUMBRA_BUILD_APPS=OFF >/dev/null
cmake --build build/fuzz -j"$jobs" --target make_seeds $(printf 'fuzz_%s ' "${targets[@]}")

mkdir -p build/fuzz/corpus build/fuzz/crashes
ASAN_OPTIONS=detect_leaks=1 build/fuzz/tests/fuzz/make_seeds build/fuzz/seeds >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export LSAN_OPTIONS=suppressions="$PWD/tests/lsan.supp"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for t in "${targets[@]}"; do
  mkdir -p "build/fuzz/corpus/$t"
  cp -n build/fuzz/seeds/"$t"/* "build/fuzz/corpus/$t/" 2>/dev/null || true
  echo "== fuzz $t for ${seconds}s"
  # OpenImageIO and libpng are built without frame pointers: ASan's fast unwinder stops inside them
  # and the suppressions of tests/lsan.supp (OpenImageIO's own leak on corrupt PNGs) cannot match.
  unwind=1
  [ "$t" = image ] && unwind=0
  # New inputs go to the first folder; the regressions (if the target has any: git keeps no empty
  # folder) are read only.
  inputs=("build/fuzz/corpus/$t")
  [ -d "tests/fuzz/regressions/$t" ] && inputs+=("tests/fuzz/regressions/$t")
  if ! ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=$unwind" "build/fuzz/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout="${PENUMBRA_FUZZ_TIMEOUT:-10}" -rss_limit_mb=2560 \
      -print_final_stats=1 -seed="${PENUMBRA_FUZZ_SEED:-0}" -artifact_prefix="build/fuzz/crashes/$t-" \
      "${inputs[@]}" 2>"build/fuzz/$t.log"; then
    tail -n 40 "build/fuzz/$t.log"
    echo "fuzz $t: failed; the input is in build/fuzz/crashes/" >&2
    exit 1
  fi
  grep -E "^stat::number_of_executed_units|^stat::new_units_added|^stat::peak_rss_mb|cov:" "build/fuzz/$t.log" | tail -n 4
done
