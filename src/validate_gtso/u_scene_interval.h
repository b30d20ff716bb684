// The cone aperture u at the scene level (docs/validate_gtso.md §3): how far the fitted u moves
// with the choice of scenes, which u each roughness wants under each law, and which law predicts
// scenes it was not fitted on better.
//
// Everything comes from one table: per law (u^(α²/2) with α = r_p², and u^(r_p²/2)), per scene
// cluster and roughness, the sum of squared errors of S_cone(u) against the path-traced S on a
// grid of log10 u. A fit to any set of clusters and roughness values is the grid minimum of the
// summed table, refined by the parabola through it and its neighbours.
//  - Scene-level interval: the delete-one-cluster jackknife of log10 u (S refits),
//    SE_J = √((S − 1)/S Σ (z_(s) − z̄)²), and z ± t_{0.975, S−1} SE_J: a 95 % interval over scene
//    mixes drawn like this one (to first order; S − 1 degrees of freedom). u's SE is the delta
//    method's u · ln 10 · SE_J.
//  - Per-roughness optima under each law (all clusters, one roughness).
//  - Law comparison: each cluster's RMSE at the u fitted without it, per law, compared by a
//    paired sign-flip test (scene_paired_test.h).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "common/progress.h"
#include "validate_gtso/scene_paired_test.h"
#include "validate_gtso/specular_methods.h"

namespace gtbake {

// The log10 u grid: kLog10UMin..0 in this step (decades); the top end is u = 1 − 1e-6 (cone_u_fit).
inline constexpr double kUGridStep = 0.25;

// [law][cluster][roughness][grid point]; law 0: u^(α²/2), 1: u^(r_p²/2).
struct ConeSseTable {
  std::vector<double> log10_u;
  std::array<std::vector<std::vector<std::vector<double>>>, 2> sse;
  std::vector<std::vector<std::size_t>> count;  // [cluster][roughness]
};

// cluster_of[scene]: the cluster of each sweep scene (clusters numbered 0..clusters − 1).
// progress (optional) advances by one per sample scored.
ConeSseTable coneSseTable(const std::vector<SpecularSample>& samples,
                          const std::vector<int>& cluster_of, std::size_t clusters,
                          std::size_t roughness, Progress* progress = nullptr);

// The minimiser of a sampled curve: the parabola through the smallest sample and its neighbours
// (the sample itself at either end, flagged).
double gridArgmin(const std::vector<double>& x, const std::vector<double>& y, bool* at_bound);

struct UOptimum {
  double u = 0.0;
  double log10_u = 0.0;
  bool at_bound = false;  // at the grid's end: the data want u beyond the search range
};

struct USceneInterval {
  double log10_u = 0.0;  // pooled grid fit
  double log10_se = 0.0;
  double low = 0.0, high = 0.0;    // 10^(z ± t SE)
  double u_se = 0.0;               // u · ln 10 · SE_J
  double t = 0.0;                  // t_{0.975, S−1}
  std::vector<double> replicates;  // log10 u without each cluster
};

struct LawComparison {
  std::array<std::vector<double>, 2> held_out_rmse;  // [law][cluster], u fitted without it
  PairedTest test;                                   // law 0 minus law 1
  int chosen = 0;                                    // the law with the lower mean held-out RMSE
};

struct UAnalysis {
  std::size_t clusters = 0;
  std::array<USceneInterval, 2> interval;              // [law], every roughness pooled
  std::array<std::vector<UOptimum>, 2> per_roughness;  // [law][roughness]
  std::array<std::vector<UOptimum>, 2> per_cluster;    // [law][cluster]
  LawComparison law;
};

// Throws gtbake::Error with fewer than kMinJackknifeScenes clusters.
UAnalysis analyzeU(const ConeSseTable& table);

inline constexpr const char* kLawNames[2] = {"alpha", "perceptual"};

}  // namespace gtbake
