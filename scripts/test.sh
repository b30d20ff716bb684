#!/usr/bin/env bash
# The README's second command (and CI's): install what is missing, build every target, run the
# test tiers (tests/CMakeLists.txt, docs/testing.md): the default suite (every tier but slow and
# sanitize), then the slow tier (GTBAKE_SKIP_SLOW=1 skips it), then the ASan+UBSan build of the
# reliability subset (GTBAKE_SKIP_SANITIZE=1 skips it). One tier alone: ctest --test-dir build -L unit
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh all
scripts/build.sh all
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900 -LE 'slow|sanitize'
if [[ "${GTBAKE_SKIP_SLOW:-0}" != 1 ]]; then
  ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900 -L slow
fi
if [[ "${GTBAKE_SKIP_SANITIZE:-0}" != 1 ]]; then scripts/test-sanitize.sh; fi
