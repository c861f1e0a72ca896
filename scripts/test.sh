#!/usr/bin/env bash
# README command 2: install what is missing, build and run every test, in Release and under
# AddressSanitizer + UndefinedBehaviorSanitizer, and the tests of concurrent code under
# ThreadSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=$(nproc)
# ccache (installed above) keeps the objects of earlier runs, keyed by their preprocessed source
# and flags, with paths taken relative to the checkout so that another clone reuses them too.
cache=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  cache=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBEAMTRACE_BUILD_TESTS=ON -DBEAMTRACE_BUILD_BENCH=ON "${cache[@]}" >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"
if [ "${BEAMTRACE_SKIP_SANITIZERS:-0}" != 1 ]; then
  # -O1 -g1: quick to compile, still fast enough to run, and stack traces keep function names.
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
        -DBEAMTRACE_SANITIZE=ON -DBEAMTRACE_BUILD_BENCH=OFF "${cache[@]}" >/dev/null
  cmake --build build-asan -j"$jobs"
  # All but the independent readers' decoding of every example survey, which checks formats,
  # not memory: the Release build runs it, and GoldenOutputs runs every example here too.
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs" \
          -E 'SurveyExamples\.IndependentReadersDecodeExactlyThePointsOfEveryExample'
  # ThreadSanitizer on the tests of concurrent code (tests/CMakeLists.txt lists them), but the
  # single-threaded brute-force cross-checks, which the two builds above run.
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
        -DBEAMTRACE_TSAN=ON -DBEAMTRACE_BUILD_BENCH=OFF "${cache[@]}" >/dev/null
  cmake --build build-tsan -j"$jobs"
  TSAN_OPTIONS="suppressions=$PWD/tests/tsan.supp halt_on_error=1 second_deadlock_stack=1" \
    ctest --test-dir build-tsan --output-on-failure -j"$jobs" \
          -E 'CrossCheck\.(Bunny|Terrain|NoLeaks|AxisAligned|AllHits)'
fi
