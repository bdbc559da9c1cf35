#!/usr/bin/env bash
# Configures the sanitized build that `make sanitize` and `make fuzz` share (build-sanitize/ unless
# SANITIZE_BUILD says otherwise): clang-14, AddressSanitizer + UBSan at -O1 -g1, libFuzzer's
# coverage, the fuzz targets and the tests (no benchmarks). Debug keeps assertions on; its own -g
# is left out so that -g1 holds. A unity build (sources compiled in batches of 8) halves the
# compile time CI spends here. Prints the folder.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${SANITIZE_BUILD:-build-sanitize}
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG= -DCMAKE_C_FLAGS_DEBUG= \
    -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
    -DBCASSIM_FUZZ=ON -DBCASSIM_BUILD_TESTS=ON -DBCASSIM_BUILD_BENCH=OFF \
    -DCMAKE_UNITY_BUILD=ON \
    > "$BUILD.configure.log" 2>&1 || { cat "$BUILD.configure.log" >&2; exit 1; }
fi
echo "$BUILD"
