#!/usr/bin/env bash
# The README's first command: install what is missing, build, and run `gtbake all` on the built-in
# scenes into out/ (or the directory given as $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
build/gtbake all --out "${1:-out}"
