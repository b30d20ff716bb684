// The squared error of Equation 10 per scene cluster from sufficient statistics (docs/tune.md §2).
//
// Per albedo ρ_j and cluster c, with x_i = (Â_i³, −Â_i², Â_i), S = Σ x xᵀ, b_j = Σ x G_ij (the
// level-0 NormalEquations of normal_equations.h, unit weights) and q_j = Σ G_ij²,
//   SSE_c(θ_j) = Σ_i (G_ij − x_iᵀθ_j)² = q_j − 2 θ_jᵀ b_j + θ_jᵀ S θ_j,
// so any constants (the paper's, a refit on any union of clusters) are scored on any cluster with a
// 3 × 3 quadratic form per albedo instead of a pass over the points. q does not depend on Â and is
// summed once per cluster; S and b are summed per estimator run.
#pragma once

#include <cstddef>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/multibounce_fit.h"
#include "fit/normal_equations.h"
#include "fit/scene_jackknife.h"
#include "fit/sweep_data.h"

namespace gtbake {

// One cluster's sums at one Â.
struct ClusterStatistics {
  NormalEquations sums;        // level 0: S, b_j, Σ w, points
  std::vector<long double> q;  // [albedo] Σ G_ij²
  ClusterStatistics& operator+=(const ClusterStatistics& other);
};

// [cluster] Σ G_ij² per albedo (the part that does not depend on Â).
std::vector<std::vector<long double>> clusterTargetSquares(const SweepData& data,
                                                           const Grouping& clusters);

// [cluster] statistics of `data` with its current A (Â), unit weights; clusters in parallel, each
// summed in point order (the same bits on any thread count).
std::vector<ClusterStatistics> clusterStatistics(
    const SweepData& data, const Grouping& clusters,
    const std::vector<std::vector<long double>>& target_squares);

// Σ over the clusters whose include flag is set (all when include is empty).
ClusterStatistics sumClusters(const std::vector<ClusterStatistics>& clusters,
                              const std::vector<bool>& include = {});

// SSE of Eq. 10 with constants k over every point and albedo the statistics hold.
double sumSquaredError(const ClusterStatistics& s, const std::vector<double>& albedos,
                       const MultiBounceCoeffs& k);

// The profile's refit (coefficientsFromStatistics, `settings` without the errors-in-variables
// correction: level 0 is all it reads) on the statistics.
MultiBounceCoeffs refitCoefficients(const ClusterStatistics& s, const std::vector<double>& albedos,
                                    const FitSettings& settings);

// The same SSE by a pass over the points of views [begin, end) (the identity's cross-check).
double directSquaredError(const SweepData& data, const std::vector<std::size_t>& views,
                          const MultiBounceCoeffs& k);

}  // namespace gtbake
