// Template body of estimatePerPixel (estimate.h).
#pragma once

#include <Eigen/Core>
#include <algorithm>

#include "screen_ao/pixel_loop.h"

namespace gtbake {

inline void storeAo(std::size_t p, double a, AoEstimate* e) {
  // Â is a visibility fraction: the rounding of the slice integrals (and of the bitmask's
  // cosine remap at grazing views, up to 3e-5) may leave it just outside [0, 1].
  e->a[p] = static_cast<float>(std::clamp(a, 0.0, 1.0));
}

inline void storePixel(const GBuffer& g, std::size_t p, double a, const Eigen::Vector3d& bent,
                       AoEstimate* e) {
  Eigen::Vector3d world = g.viewToWorld(bent);
  if (!(world.norm() > 1e-12)) {
    world = Eigen::Vector3d(g.normal[3 * p], g.normal[3 * p + 1], g.normal[3 * p + 2]);
  }
  world.normalize();
  storeAo(p, a, e);
  for (int c = 0; c < 3; ++c) e->bent[3 * p + c] = static_cast<float>(world[c]);
}

template <typename F>
AoEstimate estimatePerPixel(const GBuffer& g, F perPixel) {
  AoEstimate e = makeEstimate(g);
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    double a = 0.0;
    Eigen::Vector3d bent = Eigen::Vector3d::Zero();
    perPixel(i, j, p, &a, &bent);
    storePixel(g, p, a, bent, &e);
  });
  return e;
}

}  // namespace gtbake
