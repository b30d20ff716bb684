// The depth-buffer surface as a sample loop reads it (docs/screen_ao.md §1): texelPlanePoint's
// points, from a copy of the G-buffer laid out for the loop (read through the GBuffer, the
// compiler reloads its fields after every store a loop makes to memory that may alias them).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "screen_ao/gbuffer.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

class SampleImage {
 public:
  explicit SampleImage(const GBuffer& g)
      : width_(g.width),
        height_(g.height),
        near_(1.0 - slabReach(g)),
        far_(1.0 + slabReach(g)),
        x_scale_(powerOfTwoScale(g.width)),
        y_scale_(powerOfTwoScale(g.height)),
        tan_half_(g.tan_half),
        aspect_(g.aspect) {
    texels_.resize(g.pixels());
    for (std::size_t p = 0; p < g.pixels(); ++p) {
      const Texel& t = g.texels[p];
      texels_[p] = {t.normal[0] * static_cast<double>(t.position[0]) +
                        t.normal[1] * static_cast<double>(t.position[1]) +
                        t.normal[2] * static_cast<double>(t.position[2]),
                    {t.normal[0], t.normal[1], t.normal[2]},
                    t.depth};
    }
  }

  // texelPlanePoint(g, x, y, slabReach(g), out): the same operations on the same values but for
  // the texel's index and bounds. x ≥ 0 exactly where ⌊x⌋ ≥ 0 and x < W where ⌊x⌋ < W (W an
  // integer), and there the truncation that indexes the texel is the floor; N·T is
  // texelDepthOnRay's plane offset computed once per texel; and at a power-of-two W, 2x/W is
  // x·(2/W) exactly (both scale x by a power of two), so the step needs no division.
  bool point(double x, double y, Eigen::Vector3d* out) const {
    if (!(x >= 0.0 && y >= 0.0 && x < width_ && y < height_)) return false;
    const PlaneTexel& t = texels_[static_cast<std::size_t>(static_cast<int>(y)) * width_ +
                                  static_cast<std::size_t>(static_cast<int>(x))];
    if (!(t.depth > 0.0f)) return false;
    const double u = x_scale_ != 0.0 ? x * x_scale_ : 2.0 * x / width_;
    const double w = y_scale_ != 0.0 ? y * y_scale_ : 2.0 * y / height_;
    const Eigen::Vector3d ray((u - 1.0) * tan_half_ * aspect_, (1.0 - w) * tan_half_, -1.0);
    const double d = t.normal[0] * ray.x() + t.normal[1] * ray.y() + t.normal[2] * ray.z();
    const double plane = t.k * d > 0.0 ? t.k / d : std::numeric_limits<double>::infinity();
    const double z = t.depth;
    *out = std::clamp(plane, z * near_, z * far_) * ray;
    return true;
  }

 private:
  // A texel as the samples read it: its plane offset N·T in double, N, and its depth Z (0 where
  // masked).
  struct PlaneTexel {
    double k;
    float normal[3];
    float depth;
  };
  // 2/n where n is a power of two, else 0 (the division is kept).
  static double powerOfTwoScale(int n) { return (n & (n - 1)) == 0 ? 2.0 / n : 0.0; }

  std::vector<PlaneTexel> texels_;
  std::size_t width_;
  std::size_t height_;
  double near_, far_;  // 1 − κ, 1 + κ: the slab's ends per metre of depth (slabReach)
  double x_scale_, y_scale_;
  double tan_half_, aspect_;
};

}  // namespace gtbake
