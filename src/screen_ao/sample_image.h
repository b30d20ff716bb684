// The depth-buffer surface as a sample loop reads it (docs/screen_ao.md §1): texelPlanePoint's
// points, with the G-buffer fields they need copied once (read through the GBuffer, the compiler
// reloads them after every store a loop makes to memory that may alias them).
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "screen_ao/gbuffer.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

struct SampleImage {
  explicit SampleImage(const GBuffer& g)
      : texels(g.texels.data()),
        columns(static_cast<std::size_t>(g.width)),
        width(g.width),
        height(g.height),
        tan_half(g.tan_half),
        aspect(g.aspect),
        reach(slabReach(g)) {}
  // texelPlanePoint's point at the image point (x, y), with imageRay's arithmetic, but without
  // its floor calls: x ≥ 0 exactly where ⌊x⌋ ≥ 0 and x < W where ⌊x⌋ < W (W an integer), and
  // there the truncation that indexes the texel is the floor.
  bool point(double x, double y, Eigen::Vector3d* out) const {
    if (!(x >= 0.0 && y >= 0.0 && x < width && y < height)) return false;
    const Texel& t = texels[static_cast<std::size_t>(static_cast<int>(y)) * columns +
                            static_cast<std::size_t>(static_cast<int>(x))];
    if (!(t.depth > 0.0f)) return false;
    const Eigen::Vector3d ray((2.0 * x / width - 1.0) * tan_half * aspect,
                              (1.0 - 2.0 * y / height) * tan_half, -1.0);
    *out = texelDepthOnRay(t, ray, reach) * ray;
    return true;
  }
  const Texel* texels;
  std::size_t columns;
  double width, height, tan_half, aspect, reach;  // reach: slabReach
};

}  // namespace gtbake
