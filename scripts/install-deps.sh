#!/usr/bin/env bash
# Installs the Debian 12 packages gtbake builds, tests and benchmarks with; skips what is present.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libceres-dev libembree-dev libopenexr-dev libeigen3-dev libtinygltf-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libstb-dev librandom123-dev
  libgtest-dev libgmock-dev
  libsquish-dev libnvtt-dev glslang-tools
  chromium
  mesa-vulkan-drivers
  libvulkan-dev
  clang libclang-rt-14-dev
  slurm-wlm
  munge
  parallel
  # tests only: real meshes for the slow tier (Slow.RealMeshesSweepAndFitWithAutomaticCameras)
  assimp-utils assimp-testmodels
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[[ $(id -u) -ne 0 ]] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
