// The 4D and 3D tables' error by how far the bent normal b leaves the plane of n and ωr, over
// occluded pixels only (docs/validate_gtso.md §2). An open pixel (A near 1) has b ≈ n, so b lies
// in that plane and both tables are exact there; mixed into the 0–2° bin, such pixels would make
// it look accurate for a reason that has nothing to do with the angle.
#pragma once

#include <array>
#include <vector>

#include "validate_gtso/specular_methods.h"

namespace gtbake {

inline constexpr double kOpenA = 0.99;  // pixels with A above this are open, left out
inline constexpr std::array<double, 6> kOutOfPlaneEdges = {0.0, 2.0, 5.0, 10.0, 20.0, 90.0};

struct OutOfPlaneBin {
  double min_deg = 0.0, max_deg = 0.0;
  std::size_t open_excluded = 0;  // samples in the bin with A > kOpenA
  ErrorStats s4, s3;              // occluded samples (A ≤ kOpenA)
};

// s4[i], s3[i]: the two tables' values at samples[i].
std::vector<OutOfPlaneBin> outOfPlaneOccluded(const std::vector<SpecularSample>& samples,
                                              const std::vector<float>& s4,
                                              const std::vector<float>& s3);

}  // namespace gtbake
