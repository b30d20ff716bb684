// The G-buffer a screen-space AO pass reads, taken from a sweep (docs/screen_ao.md,
// "G-buffer"): per pixel linear view depth Z, the world-space shading normal N and the mask, plus
// the camera of the sweep.json entry. The ray-traced answers (A, A_R…, BN) are kept apart in
// SweepTruth, which no estimator sees.
//
// View space: x right, y up, z backward (towards the camera), the camera at the origin, so a
// visible point has z = −Z < 0. Pixel (i, j), j = 0 the top row, looks along
// (sx, sy, −1) with sx = (2(i + ½)/W − 1)·tan(yfov/2)·W/H, sy = (1 − 2(j + ½)/H)·tan(yfov/2),
// the sweep's cameraRay; its view-space point is Z·(sx, sy, −1).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

// One pixel's view-space sample data in one 32-byte record, so a horizon step touches one cache
// line.
struct Texel {
  float position[3];
  float normal[3];
  float depth;  // Z, 0 where masked
  float plane;  // N·T, the tangent plane's offset
};

struct GBuffer {
  int width = 0;
  int height = 0;
  PerspectiveCamera camera;
  std::vector<std::uint8_t> mask;  // 1 = the pixel sees geometry
  std::vector<float> depth;        // Z, metres (0 where masked)
  std::vector<float> normal;       // world space, xyz at 3p
  // Derived once (makeViewSpace): view-space position and normal, xyz at 3p.
  std::vector<float> position;
  std::vector<float> view_normal;
  std::vector<Texel> texels;  // the same, interleaved
  double tan_half = 0.0;      // tan(yfov/2)
  double aspect = 1.0;        // width/height

  std::size_t pixels() const { return static_cast<std::size_t>(width) * height; }
  // Pixels per metre at depth Z along the image's vertical axis: (H/2)/(tan(yfov/2)·Z).
  double pixelsPerMetre(double z) const;
  // Screen position (continuous pixel coordinates, centre of pixel (i, j) at (i + ½, j + ½)) of a
  // view-space point with z < 0.
  Eigen::Vector2d project(const Eigen::Vector3d& view) const {
    const double sx = view.x() / -view.z();
    const double sy = view.y() / -view.z();
    return {0.5 * width * (sx / (tan_half * aspect) + 1.0), 0.5 * height * (1.0 - sy / tan_half)};
  }
  Eigen::Vector3d viewPoint(int i, int j, double z) const;      // Z·(sx, sy, −1)
  Eigen::Vector3d worldToView(const Eigen::Vector3d& w) const;  // rotation only
  Eigen::Vector3d viewToWorld(const Eigen::Vector3d& v) const;  // rotation only
};

// Fills position and view_normal from depth, normal and the camera.
void makeViewSpace(GBuffer* g);

struct SweepTruth {
  std::vector<float> a;     // ray-traced A (unbounded, or the sweep's --radius)
  std::vector<float> bent;  // BNX BNY BNZ, world space, xyz at 3p
  std::map<std::string, std::vector<float>> a_at_radius;  // A_R… channels by name
};

struct SweepImage {
  std::string name;   // the views[] entry's name (the EXR's stem)
  std::string group;  // its "scene" field if present, else its name: the statistics' grouping
  GBuffer gbuffer;
  SweepTruth truth;
};

struct SweepImages {
  std::vector<SweepImage> images;
  std::string sweep_version;  // gtbake_version of sweep.json
};

// Reads <dir>/sweep.json and every entry's EXR through the sweep's manifest (verified). Throws
// gtbake::Error with one line on a missing manifest, entry field, camera, channel (Z, NX NY NZ,
// mask, A, BNX BNY BNZ) or a size that differs from the entry's.
SweepImages readSweepImages(const std::filesystem::path& dir);

// The G-buffer part of an EXR's channels (used by readSweepImages and tests).
GBuffer gbufferFromChannels(int width, int height, const PerspectiveCamera& camera,
                            const std::map<std::string, std::vector<float>>& channels,
                            const std::string& where);

}  // namespace gtbake
