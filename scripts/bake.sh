#!/usr/bin/env bash
# The README's first command: install what building and running the tool needs, build only the
# `gtbake` target (no tests, benchmarks or fuzz targets), and run `gtbake all` on the built-in
# scenes into out/ (or the directory given as $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh tool
scripts/build.sh tool
build/gtbake all --out "${1:-out}"
