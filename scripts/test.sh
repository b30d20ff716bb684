#!/usr/bin/env bash
# The README's second command (and CI's): install what is missing, build, run the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900
# ASan + UBSan on the reliability subset (its own build dir; skip with GTBAKE_SKIP_SANITIZE=1).
if [[ "${GTBAKE_SKIP_SANITIZE:-0}" != 1 ]]; then scripts/test-sanitize.sh; fi
