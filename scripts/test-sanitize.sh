#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer on the reliability subset (hostile inputs, output
# sets, failing writes, signals, the fuzz targets' bounded loops, glTF I/O), in its own build
# directory build-sanitize/: only the targets the tier runs are built, and the tier is the tests
# labelled `sanitize` there (GTBAKE_SANITIZE_SUBSET in tests/CMakeLists.txt).
# Usage: scripts/test-sanitize.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-sanitize}"
# -O1 -g1: ASan's recommended optimisation and line tables for its stack traces; half the compile
# time of RelWithDebInfo's -O2 -g (docs/testing.md).
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DGTBAKE_SANITIZE=ON -DGTBAKE_BUILD_BENCH=OFF -DGTBAKE_FUZZ_ITERATIONS=400 \
  -DGTBAKE_FUZZ_READER_ITERATIONS=5000
cmake --build "$build" -j"$(nproc)" --target gtbake_sanitize_tier
# Leak checking is off: TBB and Embree keep process-lifetime allocations that LSan reports.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir "$build" --output-on-failure -j"$(nproc)" --timeout 600 -L sanitize
