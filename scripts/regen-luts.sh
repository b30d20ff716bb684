#!/usr/bin/env bash
# Regenerates the committed artifacts and the numbers docs quote from them: `gtbake all --out luts`,
# then every `NUMBER<!--@ FILE POINTER FORMAT-->` marker in docs/ and README.md is rewritten from
# the new luts/ (build/gtbake-docs --update). Run from a configured build (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
build/gtbake all --out luts
build/gtbake-docs --update --luts luts --data data docs README.md
