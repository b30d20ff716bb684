#!/usr/bin/env bash
# Real content beside the procedural corpus (docs/scenes.md "Real meshes"): six meshes of Debian's
# assimp-testmodels, converted to glTF 2.0 at run time with `assimp export` (assimp-utils), never
# copied into the repository. They have no cameras, so the sweep gives each its four automatic
# views; it runs at `gtbake all`'s corpus settings (128² pixels, 84 walks, seed 1), then Eq. 10 is
# fitted with the report.
#
# Usage: scripts/real-meshes.sh OUT [GTBAKE]        (GTBAKE: default build/gtbake)
# Writes OUT/scenes/<mesh>.gltf, OUT/sweep/ (sweep.json and the views' EXRs), OUT/fit.json and
# OUT/report/. data/real_meshes/ commits this run's sweep.json and fit.json (docs quote them);
# test Slow.RealMeshesSweepAndFitWithAutomaticCameras reruns it and compares.
set -euo pipefail
out="${1:?usage: scripts/real-meshes.sh OUT [GTBAKE]}"
gtbake="${2:-build/gtbake}"
models=/usr/share/assimp/models
if [[ ! -d "$models" ]] || ! command -v assimp >/dev/null; then
  echo "real-meshes: needs Debian's assimp-utils and assimp-testmodels (scripts/install-deps.sh all)" >&2
  exit 2
fi
# Machinery, a figure, a creature, an animal, a teapot group and a rock face, from five formats.
meshes=(glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
  PLY/Wuson.ply
  OBJ/spider.obj
  Collada/duck.dae
  Collada/teapots.DAE
  3DS/fels.3ds)
mkdir -p "$out/scenes"
for mesh in "${meshes[@]}"; do
  stem="$(basename "${mesh%.*}")"
  assimp export "$models/$mesh" "$out/scenes/$stem.gltf" -fgltf2 >/dev/null
done
"$gtbake" sweep --quiet --scenes "$out/scenes" --out "$out/sweep" --res 128x128 --spp 84 \
  --seed 1 --specular-roughness none
"$gtbake" fit --quiet --sweep "$out/sweep" --out "$out/fit.json" --report "$out/report"
