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
  // Defaults (docs/sweep.md): 7 scenes × 192² px × 384 walks ≈ 164 M rays, ~19 s on 2 cores. The
  // fit's standard errors shrink with the pixel count (its residuals are model misfit, not noise):
  // 192² gives SE(b₁) ≈ 0.004 ≤ 0.005; 384 stratified walks leave a noise variance of A of 4e-5,
  // 5e-4 of A's spread over the pixels, so the errors-in-variables bias is negligible.
  int spp = 384;    // cosine random walks per pixel (even: two half-sample estimates)
  int width = 192;  // pixels; the camera's aspect ratio is taken from width/height
  int height = 192;
  int bounces = 3;                                          // K: interreflections counted in G
  double radius = std::numeric_limits<double>::infinity();  // sky beyond this distance
  std::uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
  bool progress = true;
  // First walk direction stratified within each half-sample estimate (docs/sweep.md); off gives
  // independent walks, e.g. to compare variances.
  bool stratify_first_bounce = true;
  // True specular occlusion channels S + r_p×100 at these perceptual roughness values (α = r_p²;
  // empty: none) with this many VNDF samples per value and pixel (even; docs/sweep.md §2).
  std::vector<double> specular_roughness = {0.10, 0.25, 0.40, 0.60, 0.80};
  int specular_spp = 64;
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
