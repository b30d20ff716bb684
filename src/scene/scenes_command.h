// `gtbake scenes`: write the seven procedural scene types of docs/scenes.md "The seven scene types"
// as glTF 2.0.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gtbake {

struct ScenesOptions {
  std::filesystem::path out = "data/scenes";
  std::uint64_t seed = 1;  // seeds the clutter and terrain generators
  bool progress = true;
};

// Writes <out>/<name>.gltf and <out>/<name>.bin for every scene type; returns the .gltf paths in
// a fixed order (cavity, wedge, corner, spheres, wells, clutter, terrain).
std::vector<std::filesystem::path> runScenes(const ScenesOptions& options);

}  // namespace gtbake
