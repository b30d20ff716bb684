#!/usr/bin/env bash
# Installs the Debian 12 packages gtbake needs; skips what is present.
# Usage: scripts/install-deps.sh [tool|all]
#   tool  what building and running the `gtbake` tool needs (scripts/bake.sh)
#   all   the tool's packages plus what the tests and benchmarks need (scripts/test.sh; the default)
set -euo pipefail
group="${1:-all}"
# Building and running the tool.
tool_packages=(
  build-essential cmake pkg-config
  libceres-dev libembree-dev libopenexr-dev libeigen3-dev libtinygltf-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libstb-dev librandom123-dev libssl-dev
)
# Tests and benchmarks only: GoogleTest; libsquish and NVTT (the BC4 benchmark); glslang and
# Mesa's lavapipe (the shader includes compiled and executed); Chromium (the reports rendered
# headless); clang (the sanitizer tier and libFuzzer); slurm-wlm + munge and GNU parallel (the
# cluster tier); assimp and its test models (real meshes in the slow tier); jq (the summary of
# scripts/corpus-seeds.sh).
test_packages=(
  libgtest-dev libgmock-dev
  libsquish-dev libnvtt-dev
  glslang-tools mesa-vulkan-drivers libvulkan-dev
  chromium
  clang libclang-rt-14-dev
  slurm-wlm munge parallel
  assimp-utils assimp-testmodels
  jq
)
case "$group" in
  tool) packages=("${tool_packages[@]}") ;;
  all) packages=("${tool_packages[@]}" "${test_packages[@]}") ;;
  *)
    echo "install-deps: unknown group '$group' (tool or all)" >&2
    exit 2
    ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages of '$group' present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[[ $(id -u) -ne 0 ]] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
