#!/usr/bin/env bash
# Configures and builds gtbake (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGTBAKE_WERROR=ON
cmake --build build -j"$(nproc)"
