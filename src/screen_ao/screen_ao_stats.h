// Errors of one estimator against the sweep's ray-traced answers (docs/screen_ao.md,
// "Statistics"), per group of images (the views[] entry's scene, else its name) and bin of the
// ray-traced A (width 0.1), over the unmasked pixels.
#pragma once

#include <string>
#include <vector>

#include "screen_ao/estimate.h"
#include "screen_ao/gbuffer.h"

namespace gtbake {

struct ErrorSummary {
  double lo = 0.0;  // bin of ray-traced A: [lo, hi) (the last bin includes 1)
  double hi = 1.0;
  std::size_t pixels = 0;
  double bias = 0.0;  // mean of Â − A
  double rmse = 0.0;
  // Against A_R at the estimator's radius (pixels_at_radius = 0 without that channel).
  std::size_t pixels_at_radius = 0;
  double bias_at_radius = 0.0;
  double rmse_at_radius = 0.0;
  double bent_mean_deg = 0.0;  // angle between b̂ and the sweep's bent normal
  double bent_p95_deg = 0.0;   // 95th percentile (nearest rank)
};

struct GroupErrors {
  std::string group;
  ErrorSummary all;
  std::vector<ErrorSummary> bins;  // 10, empty ones with pixels = 0
};

inline constexpr int kErrorBins = 10;

// estimates[k] belongs to images[k]. Groups in order of first appearance, then "all" last.
std::vector<GroupErrors> errorStatistics(const std::vector<SweepImage>& images,
                                         const std::vector<AoEstimate>& estimates, double radius);

// The angle in degrees between two unit vectors (clamped dot product).
double angleDegrees(const float* a, const float* b);

}  // namespace gtbake
