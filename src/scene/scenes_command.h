// `gtbake scenes`: write the procedural scene corpus (docs/scenes.md) as glTF 2.0.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene_corpus.h"

namespace gtbake {

struct ScenesOptions {
  std::filesystem::path out = "data/scenes";
  std::uint64_t seed = 1;  // seeds every variant (and the classic clutter and terrain)
  bool progress = true;
  // The seven classic scenes only (data/scenes/ holds them, seed 1), named by their type.
  bool classic = false;
  int variants = kCorpusVariants;  // per corpus type
};

// Writes <out>/<name>.gltf and <out>/<name>.bin for every corpus scene <type>_<variant> (type by
// type in corpusTypeNames() order, variants 0, 1, …), or with `classic` for the seven classic
// types; returns the .gltf paths in that order.
std::vector<std::filesystem::path> runScenes(const ScenesOptions& options);

}  // namespace gtbake
