// `gtbake sweep`: path-traced A and G over a set of glTF scenes (docs/sweep.md §1, docs/index.md
// "Pipeline").
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/input_limits.h"

namespace gtbake {

// Pixels per side of a sweep image (common/input_limits.h): 8192² × 2(K+1) counts and the
// channels fit in memory, and beyond it a sweep would take days.
inline constexpr int kMaxSweepResolution = kMaxImageSide;

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
  // Camera of glTF files with several: a name or a walk-order index; "" = the first (the sweep
  // prints which one it took). "auto" or "auto:K": K views framing each scene's bounding box
  // (scene/auto_camera.h), each one image <stem>_v<k>; a glTF without a camera always gets
  // kAutoViews of them.
  std::string camera;
  bool progress = true;
  // First walk direction stratified within each half-sample estimate (docs/sweep.md); off gives
  // independent walks, e.g. to compare variances.
  bool stratify_first_bounce = true;
  // True specular occlusion channels S + r_p×100 at these perceptual roughness values (α = r_p²;
  // empty: none) with this many VNDF samples per value and pixel (even; docs/sweep.md §2).
  std::vector<double> specular_roughness = {0.10, 0.25, 0.40, 0.60, 0.80};
  int specular_spp = 64;
  // A_R channels (A with the sky beyond R, from the same walks; docs/sweep.md, "G-buffer") at these
  // radii in metres, ascending (empty: none). The default is screen-ao's default radius.
  std::vector<double> gbuffer_radii = {1.0};
  // Per-bounce SH transfer channels T<k>_SH<i> from the same walks (docs/sweep.md, "Transfer");
  // off drops them (`--transfer off`).
  bool transfer = true;
  // Shard `shard` of `shards` (0-based; shards = 0: not sharded). A shard traces only its tiles
  // (tile_plan.h) and writes them with <out>/shard.json for `gtbake merge` (docs/cluster.md).
  int shard = 0;
  int shards = 0;
  // Require tiles checkpointed by an interrupted run of the same sweep in <out>/sweep-tiles and
  // skip them. Without it they are skipped too, if they belong to the same sweep.
  bool resume = false;
  std::string command_line;  // quoted in the message that says how to resume
};

struct SweepViewResult {
  std::filesystem::path exr;
  double seconds = 0.0;
  std::uint64_t rays = 0;
};

struct SweepResult {
  std::vector<SweepViewResult> views;  // one per view, in sweep order
  double seconds = 0.0;
  std::uint64_t rays = 0;
};

// SIGINT or SIGTERM stopped the sweep after its finished tiles were saved; the message says how
// to resume. The CLI exits with 128 + signal.
class SweepInterrupted : public Error {
 public:
  SweepInterrupted(const std::string& message, int signal) : Error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Writes <out>/<view>.exr per view and <out>/sweep.json; prints a summary to stdout. Tiles
// are checkpointed in <out>/sweep-tiles as they finish (removed once the outputs are written); a
// sweep stopped by a signal or killed resumes from them. Sharded: writes <out>/sweep-tiles and
// <out>/shard.json instead (result.views is then empty).
inline constexpr int kMaxShards = kMaxSweepShards;  // common/input_limits.h

SweepResult runSweep(const SweepOptions& options);

// The --gbuffer-radius list as the EXR attribute and sweep.json write it ("none" when empty).
std::string gbufferRadiusList(const std::vector<double>& radii);

}  // namespace gtbake
