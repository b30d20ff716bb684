// `gtbake sweep`: path-traced A and G over a set of glTF scenes (SPEC §1.1, §2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

namespace gtbake {

struct SweepOptions {
  // .gltf files, or directories whose *.gltf files are all taken (sorted by name).
  std::vector<std::filesystem::path> scenes;
  std::filesystem::path out;
  int spp = 256;    // cosine random walks per pixel
  int width = 256;  // pixels; the camera's aspect ratio is taken from width/height
  int height = 256;
  int bounces = 3;                                          // K: interreflections counted in G
  double radius = std::numeric_limits<double>::infinity();  // sky beyond this distance
  std::uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
  bool progress = true;
};

struct SweepSceneResult {
  std::filesystem::path exr;
  double seconds = 0.0;
  std::uint64_t rays = 0;
};

struct SweepResult {
  std::vector<SweepSceneResult> scenes;
  double seconds = 0.0;
  std::uint64_t rays = 0;
};

// Writes <out>/<scene>.exr per scene and <out>/sweep.json; prints a summary to stdout.
SweepResult runSweep(const SweepOptions& options);

}  // namespace gtbake
