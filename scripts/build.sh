#!/usr/bin/env bash
# Configures and builds gtbake (Release) into build/.
# Usage: scripts/build.sh [tool|all]
#   tool  only the `gtbake` program (tests and benchmarks not configured: no GoogleTest needed)
#   all   every target: the tool, gtbake-docs, the test suites, benchmarks and fuzz drivers (default)
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-all}"
case "$what" in
  tool)
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGTBAKE_WERROR=ON \
      -DGTBAKE_BUILD_TESTS=OFF -DGTBAKE_BUILD_BENCH=OFF
    cmake --build build -j"$(nproc)" --target gtbake
    ;;
  all)
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGTBAKE_WERROR=ON \
      -DGTBAKE_BUILD_TESTS=ON -DGTBAKE_BUILD_BENCH=ON
    cmake --build build -j"$(nproc)"
    ;;
  *)
    echo "build: unknown target set '$what' (tool or all)" >&2
    exit 2
    ;;
esac
