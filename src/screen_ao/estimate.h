// What every screen-space estimator returns for one image (docs/screen_ao.md).
#pragma once

#include <vector>

#include "screen_ao/gbuffer.h"

namespace gtbake {

struct AoEstimate {
  std::vector<float> a;     // Â per pixel (0 where masked)
  std::vector<float> bent;  // b̂ per pixel, world space, unit, xyz at 3p (0 where masked)
};

// What a pass computes: Â and b̂, or Â alone (tune scores Â only, docs/tune.md §7). No
// estimator's Â reads its b̂, so Â has the same bytes either way; b̂ is left empty.
enum class EstimateParts { kAoAndBent, kAoOnly };

// Sized for g, all zero (bent empty for kAoOnly).
AoEstimate makeEstimate(const GBuffer& g, EstimateParts parts = EstimateParts::kAoAndBent);

// Runs perPixel(p, &a, &bent_view) for every unmasked pixel with TBB over rows (each pixel writes
// only its own slot, so any thread count gives the same bytes) and stores Â and the bent normal
// rotated to world space and normalised (N where the integral vanishes).
template <typename F>
AoEstimate estimatePerPixel(const GBuffer& g, F perPixel);

// Stores one pixel's Â, clamped to [0, 1].
inline void storeAo(std::size_t p, double a, AoEstimate* e);
// Stores one pixel's Â (storeAo) and view-space bent normal as estimatePerPixel does.
inline void storePixel(const GBuffer& g, std::size_t p, double a, const Eigen::Vector3d& bent,
                       AoEstimate* e);

}  // namespace gtbake

#include "screen_ao/estimate_impl.h"
