#!/usr/bin/env bash
# `make sanitize`: the ctest suite built with AddressSanitizer and UBSan (-O1 -g1, in
# build-sanitize/) and run; a memory error, a leak or undefined behaviour ends the test that
# met it with the sanitizer's report (undefined behaviour is not recovered from). CI runs it. The
# whole suite but the 3 end-to-end liver pipelines (they passed under ASan too: 4 minutes each).
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD=${SANITIZE_BUILD:-build-sanitize}
JOBS=${JOBS:-2}
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD" -DBCASSIM_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug \
    -DBCASSIM_BUILD_BENCH=OFF > "$BUILD.configure.log" 2>&1 ||
    { cat "$BUILD.configure.log"; exit 1; }
fi
cmake --build "$BUILD" -j"$JOBS" > "$BUILD/sanitize-build.log" 2>&1 ||
  { grep -E "error|Error" "$BUILD/sanitize-build.log" | head -40; exit 1; }

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:malloc_context_size=20}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The end-to-end liver pipelines (minutes each under ASan) run in the Release suite only; every
# room's own tests run here.
cd "$BUILD" && ctest --output-on-failure -j"$JOBS" --timeout 1500 -E '^(Tracked)?LiverPipeline\.'

