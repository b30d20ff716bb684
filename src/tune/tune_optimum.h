// The optimum of a sampled objective and its scene-level interval (docs/tune.md §3), after the
// cone aperture's (validate_gtso/u_scene_interval.h): the grid minimum refined by the parabola
// through it and its neighbours, flagged at a grid end; the delete-one-cluster jackknife of that
// argmin, SE_J = √((S − 1)/S Σ (z_(s) − z̄)²), and z ± t_{0.975, S−1} SE_J.
#pragma once

#include <cstddef>
#include <vector>

namespace gtbake {

// The vertex of the parabola through the smallest sample and its two neighbours, for any spacing
// of x (validate-gtso's gridArgmin assumes even spacing; this equals it there up to rounding). At
// either end, or where the three samples do not curve upwards, the smallest sample itself;
// *at_bound is set when that sample is the first or last.
double curveArgmin(const std::vector<double>& x, const std::vector<double>& y, bool* at_bound);

struct SceneInterval {
  double z = 0.0;  // argmin on the search axis (log10 of the value on a log axis)
  bool at_bound = false;
  double se = 0.0;                 // SE_J of z
  double t = 0.0;                  // t_{0.975, S−1}
  double low = 0.0, high = 0.0;    // z ∓ t·SE_J on the axis, clipped to the grid's ends
  bool interval_clipped = false;   // z ∓ t·SE_J reached past an end of the grid
  std::vector<double> replicates;  // z without each cluster
  std::size_t replicates_at_bound = 0;
  // The flat range: the grid nodes [flat_first, flat_last] whose objective is within
  // kFlatFraction of the smallest sampled one, outward from that node while this holds. A range of
  // grid values (it holds the grid minimum, not necessarily the interpolated z on a coarse grid).
  std::size_t flat_first = 0, flat_last = 0;
};

// Objective within this fraction of the minimum counts as flat (5 %).
inline constexpr double kFlatFraction = 0.05;

// x: the grid on the axis; pooled[k]: the objective at x[k]; replicas[s][k]: the objective
// without cluster s. Throws a one-line gtbake::Error with fewer than kMinJackknifeScenes replicas.
SceneInterval sceneInterval(const std::vector<double>& x, const std::vector<double>& pooled,
                            const std::vector<std::vector<double>>& replicas);

}  // namespace gtbake
