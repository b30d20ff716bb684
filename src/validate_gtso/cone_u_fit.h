// The cone-aperture constant u fitted the paper's way (Appendix B: "minimize differences between
// resulting GTSO and Monte Carlo ground truth references"): least squares of the cone-to-cone
// S_cone(u) against the path-traced S over every unmasked pixel and roughness r_p > 0, minimised
// in z = log10 u (the objective is flat over decades of u, so the search runs on a log scale): the
// best point of a scan, golden-section search within one scan step of it, then parabolas through
// three exact SSEs down to 1e-5 decades (docs/validate_gtso.md §3).
//
// Conventions: cos αs = u^(w²/2) with w = α = r_p² (docs/gtso.md §1) or w = r_p (the paper's r read
// as perceptual roughness). Uncertainty: the profile interval, the u range whose RMSE is within 5%
// of the optimum (bisection on each side in log10 u; "open" when the range end is reached first).
// With the cone SSE table of the same samples, its grid is the scan and it guides the bisections,
// whose end points are then checked with exact SSEs (the same result as the exact bisection).
#pragma once

#include <vector>

#include "common/progress.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/u_scene_interval.h"

namespace gtbake {

inline constexpr double kProfileTolerance = 1.05;  // RMSE within 5% of the optimum
inline constexpr double kLog10UMin = -12.0;        // search range of log10 u
inline constexpr double kLog10UMax = -1e-6;

struct UFit {
  double u = 0.0;
  double low = 0.0, high = 0.0;              // profile interval
  bool low_open = false, high_open = false;  // the interval reached the search range's end
  double rmse = 0.0;
  double rmse_paper = 0.0;   // at u = 0.01
  double rmse_uludag = 0.0;  // at u = 0.244
  std::size_t count = 0;
};

struct UFits {
  UFit all;        // every r_p > 0
  UFit rp_ge_0_3;  // r_p ≥ 0.3
};

// Throws gtbake::Error if there is nothing to fit. table: the cone SSE table of the same samples,
// or nullptr (a 13-point scan, exact bisections). progress (optional) advances by one per subset.
UFits fitConeU(const std::vector<SpecularSample>& samples, bool perceptual,
               const ConeSseTable* table = nullptr, Progress* progress = nullptr);

}  // namespace gtbake
