// `gtbake gbuffer`: a sweep's G-buffer written as an engine holds it, so that an engine's own
// screen-space pass can run on it and its Â be imported back (`gtbake screen-ao --import`).
// Every convention is in docs/screen_ao.md §8 ("Bring your own pass") and in the set's
// gbuffer.json.
#pragma once

#include <Eigen/Core>
#include <filesystem>

#include "screen_ao/gbuffer.h"

namespace gtbake {

// The clip planes of the exported projection matrix, metres. The depth buffer is linear (Z), so
// they only shape the matrix; an engine that needs hyperbolic depth derives it with them.
inline constexpr double kExportNear = 0.05;
inline constexpr double kExportFar = 1000.0;

// World -> view (x right, y up, z backward), p_view = V·(p_world, 1), column vectors.
Eigen::Matrix4d exportViewMatrix(const PerspectiveCamera& camera);
// View -> clip, right-handed, NDC x and y in [-1, 1] with y up (row 0 of the image at y = +1),
// depth z_ndc = z_clip/w_clip in [0, 1] from near to far (D3D/Vulkan range), w_clip = Z.
Eigen::Matrix4d exportProjectionMatrix(double yfov, double aspect);

struct GbufferExportOptions {
  std::filesystem::path sweep;  // a directory written by gtbake sweep (with G-buffer channels)
  std::filesystem::path out;
  int threads = 0;
};

// Writes <out>/<image>.exr, <image>.depth.dds, <image>.normal.dds and gbuffer.json as one output
// set (gbuffer.manifest.json). Throws a one-line gtbake::Error (readSweepImages' errors).
void runGbufferExport(const GbufferExportOptions& options);

}  // namespace gtbake
