// Scene-level uncertainty of the fit: a delete-one-scene jackknife (docs/fit.md §5).
//
// The Monte Carlo SE answers "what would another seed move"; the pooled scenes are the data set's
// definition and move the constants far more. Treating the S scenes as independent draws from the
// population of content the constants are meant for, the jackknife refits with each scene left
// out, θ_(s), and estimates
//   Cov(θ̂) ≈ (S − 1)/S · Σ_s (θ_(s) − θ̄)(θ_(s) − θ̄)ᵀ,   θ̄ = mean_s θ_(s),
// which for a smooth function of per-scene sums (the fit is one) equals the cluster-robust
// (scene-clustered sandwich) covariance to first order and is never smaller than it in
// expectation (Efron–Stein). Each replica is the total statistics minus one scene's
// (normal_equations.h), so it costs ~40 small Ceres solves, not a pass over the points.
//
// G is linear in the six constants, G(A, ρ) = g(A, ρ)ᵀk, so the curve band is
//   SE_G(A, ρ) = sqrt(g(A, ρ)ᵀ Cov g(A, ρ)),
// evaluated on a grid of A ∈ (0, 1], ρ ∈ [0.1, 0.9]. Any constants k' are scored against it by
// the largest |G(k') − G(refit)| / SE_G over the grid, against the simultaneous 95 % max-t
// threshold of the leave-one-out curves on that grid with S − 1 degrees of freedom
// (simultaneous_band.h): the pointwise t quantile would be exceeded somewhere on the grid far more
// often than 5 % of the time. The open-surface row A = 1 (every scene's open pixels pin
// G(1, ρ) ≈ 1, so the band there is the replicas' agreement on a near-constraint, not the scene
// mix; /open_surface reports it) and points where the band vanishes to rounding are not scored.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "fit/fit_errors.h"
#include "fit/multibounce_coeffs.h"
#include "fit/multibounce_fit.h"
#include "fit/sweep_data.h"
#include "stats/jackknife.h"
#include "stats/simultaneous_band.h"

namespace gtbake {

struct LeaveOneOut {
  std::string left_out;        // the scene not pooled
  MultiBounceCoeffs linear{};  // the refit without it
  CurveDifference vs_refit;    // max |G_without − G_all| over A ∈ [0,1], ρ ∈ [0.1, 0.9]
  CurveDifference vs_shipped;  // max |G_without − G_shipped|
};

// A point of the (A, ρ) grid and a value there.
struct GridPoint {
  double value = 0.0;
  double A = 0.0;
  double rho = 0.0;
};

// The band's grid and simultaneous rule. A = k / a_steps, k = 1..a_steps; ρ in rho_steps equal
// steps of [0.1, 0.9] (the paper's albedo range).
struct BandRule {
  int a_steps = 200;   // steps of 0.005 in A
  int rho_steps = 80;  // steps of 0.01 in ρ
  MaxTRule max_t;
  // The ranges of A the verdict judges apart (docs/fit.md §5, "The verdict by range of A"):
  // [e_r, e_{r+1}), the last one closed. Where the data live — few pixels below 0.3, most
  // between 0.3 and 1 — and apart from A → 1, where open pixels pin the band to ~0.
  std::vector<double> ranges = {0.0, 0.3, 0.7, 1.0};
};

// The range of `rule.ranges` that holds A (A = 1 in the last).
std::size_t rangeOf(const BandRule& rule, double A);

// Calls f(A, ρ) on the band grid of `rule`, A slowest, ρ fastest: A = k / a_steps for
// k = 1..a_steps (A = 0 is left out: G = 0 there for every set of constants) and ρ in rho_steps
// equal steps of [0.1, 0.9].
template <typename F>
void forEachBandPoint(const BandRule& rule, F&& f) {
  for (int u = 1; u <= rule.a_steps; ++u) {
    const double A = static_cast<double>(u) / rule.a_steps;
    for (int v = 0; v <= rule.rho_steps; ++v) {
      f(A, kRhoMin + (kRhoMax - kRhoMin) * v / rule.rho_steps);
    }
  }
}

// Constants scored against the band.
struct BandScore {
  GridPoint max_ratio;      // largest |G_k − G_refit| / SE_G over the scored points, and where
  double difference = 0.0;  // G_k − G_refit there
  double band = 0.0;        // SE_G there
  double threshold = 0.0;   // the simultaneous max-t threshold
  double pointwise_threshold = 0.0;  // t_{0.975, S−1}, for comparison only
  std::size_t scored_points = 0;
  std::size_t excluded_points = 0;  // A = 1 and rounding-level bands
  GridPoint smallest_detectable;    // min over scored points of threshold · SE_G, and where
  GridPoint largest_undetectable;   // max over scored points of threshold · SE_G, and where
  bool consistent = false;          // max_ratio ≤ threshold
  std::string verdict;              // one line
};

// The groups a jackknife deletes one at a time: every view (image) of the sweep belongs to one.
struct Grouping {
  std::string unit;                // "scene" or "type"
  std::vector<std::string> names;  // per group, in order of first appearance
  std::vector<std::size_t> of;     // per view: its group
};

// Views grouped by scene (SweepScene::cluster: the views of one scene are one cluster) or by
// scene type (SweepScene::type).
Grouping groupByScene(const SweepData& data);
Grouping groupByType(const SweepData& data);

struct SceneJackknife {
  bool available = false;
  std::string message;     // why not, when not available
  std::string unit;        // what one replicate leaves out: "scene" or "type"
  std::size_t scenes = 0;  // groups (n: scenes, or types)
  std::vector<LeaveOneOut> leave_one_out;
  MultiBounceCoeffs se{};
  std::array<double, 36> covariance{};  // row-major 6 × 6
  std::array<double, 36> correlation{};
  GridPoint band_max;     // max SE_G over the grid
  GridPoint mc_band_max;  // the same for the Monte Carlo covariance
  BandRule rule;
  std::vector<char> scored;  // [grid point]: enters the maximum (see above)
  double threshold = 0.0;    // simultaneous max-t threshold over the scored points
  // Per range of A (rule.ranges), simultaneous over the ranges and the points of each, from the
  // same simulated draws (jointGroupThresholds): the thresholds of the verdict by range.
  std::vector<double> range_thresholds;
  double pointwise_threshold = 0.0;  // t_{0.975, S−1}
  // How often the pointwise threshold would be exceeded somewhere on the grid under "no
  // difference" (the simulated maxima above it): that rule's false-alarm rate on this band.
  double pointwise_false_alarm = 0.0;
};

// Leave-one-group-out refits (always, with ≥ 2 groups) and, with ≥ kMinJackknifeScenes groups,
// the jackknife covariance and band of `fit`: one replicate per group, S = group count.
SceneJackknife groupJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const Grouping& groups,
                              const BandRule& rule = {});
// The delete-one-scene jackknife, groupJackknife over groupByScene.
SceneJackknife sceneJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const BandRule& rule = {});
// The delete-one-type jackknife (the uncertainty for content unlike any type in the corpus),
// groupJackknife over groupByType.
SceneJackknife typeJackknife(const SweepData& data, const MultiBounceFit& fit,
                             const MultiBounceCoeffs& shipped, const BandRule& rule = {});

// From `jk.leave_one_out` and `jk.rule`: available, the covariance, SEs and correlation, the band's
// maximum and the scored points (everything but the simulated thresholds). groupJackknife calls
// it; a jackknife read back from its replicas (validate_data.h) calls it too.
void completeJackknife(SceneJackknife& jk);

// The leave-one-out curves on the band grid, [replica][grid point] (ρ fastest).
ReplicateMatrix bandReplicates(const SceneJackknife& jk);

// SE_G at (A, ρ) for a 6 × 6 covariance.
double curveBand(const std::array<double, 36>& covariance, double A, double rho);

// The jackknife's SE_G at (A, ρ) from the replicas themselves, √((S − 1)/S Σ (G_(s) − Ḡ)²): the
// same value as curveBand(covariance) without the quadratic form's cancellation where the band is
// ~0 (the band, its maximum and the score use this one).
double jackknifeBand(const SceneJackknife& jk, double A, double rho);

// Scores `k` against the band of `jackknife` around `refit`. Without a jackknife the verdict says
// so and `consistent` is false.
BandScore scoreAgainstBand(const SceneJackknife& jackknife, const MultiBounceCoeffs& refit,
                           const MultiBounceCoeffs& k);

}  // namespace gtbake
