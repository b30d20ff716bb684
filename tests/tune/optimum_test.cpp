// The argmin and its delete-one-cluster jackknife interval on curves with a known optimum
// (docs/tune.md §3, §6).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "tune/tune_optimum.h"

namespace gtbake {
namespace {

// Twenty clusters, each with SSE_c(z) = n_c (σ² + (z − m_c)²) on z = log10 value, the minima m_c
// scattered about kCentre; the pooled objective is the RMSE over every cluster's points.
constexpr double kCentre = 0.13;
constexpr std::size_t kClusters = 20;

struct Curves {
  std::vector<double> x, pooled;
  std::vector<std::vector<double>> replicas;
  double sample_centre = 0.0;  // the pooled SSE's exact minimiser, Σ n_c m_c / Σ n_c
};

Curves quadraticClusters() {
  Curves c;
  for (double z = -1.0; z <= 1.0 + 1e-12; z += 0.25) c.x.push_back(z);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> scatter(0.0, 0.2);
  std::uniform_int_distribution<int> size(500, 3000);
  std::vector<double> m, n;
  double weight = 0.0;
  for (std::size_t s = 0; s < kClusters; ++s) {
    m.push_back(kCentre + scatter(rng));
    n.push_back(size(rng));
    c.sample_centre += n.back() * m.back();
    weight += n.back();
  }
  c.sample_centre /= weight;
  const auto rmse = [&](double z, std::size_t skip) {
    double sse = 0.0, count = 0.0;
    for (std::size_t s = 0; s < kClusters; ++s) {
      if (s == skip) continue;
      sse += n[s] * (0.01 + (z - m[s]) * (z - m[s]));
      count += n[s];
    }
    return std::sqrt(sse / count);
  };
  c.replicas.assign(kClusters, {});
  for (double z : c.x) {
    c.pooled.push_back(rmse(z, kClusters));
    for (std::size_t s = 0; s < kClusters; ++s) c.replicas[s].push_back(rmse(z, s));
  }
  return c;
}

TEST(TuneOptimum, RecoversAKnownMinimumAndItsIntervalCoversIt) {
  const Curves c = quadraticClusters();
  const SceneInterval o = sceneInterval(c.x, c.pooled, c.replicas);
  EXPECT_FALSE(o.at_bound);
  EXPECT_NEAR(o.z, c.sample_centre, 0.02);  // the parabola through an RMSE (√ of a quadratic)
  EXPECT_LT(o.low, kCentre);
  EXPECT_GT(o.high, kCentre);
  EXPECT_GT(o.se, 0.01);  // the scatter of 0.2 over 20 clusters: about 0.2/√20
  EXPECT_LT(o.se, 0.15);
  EXPECT_NEAR(o.t, 2.093, 1e-3);  // t_{0.975, 19}
  EXPECT_EQ(o.replicates.size(), kClusters);
  // The flat range is of grid nodes: here the node z = 0 alone (0.25 costs more than 5 %).
  EXPECT_EQ(c.x[o.flat_first], 0.0);
  EXPECT_EQ(o.flat_last, o.flat_first);
}

TEST(TuneOptimum, ParabolaVertexOnAnUnevenGrid) {
  const std::vector<double> x = {0.5, 0.75, 1.0, 1.5, 2.0};
  std::vector<double> y;
  for (double v : x) y.push_back(3.0 + 2.0 * (v - 1.1) * (v - 1.1));
  bool at_bound = true;
  EXPECT_NEAR(curveArgmin(x, y, &at_bound), 1.1, 1e-12);
  EXPECT_FALSE(at_bound);
}

TEST(TuneOptimum, CurveFallingToTheGridEndIsAtBound) {
  const std::vector<double> x = {-1.0, -0.5, 0.0, 0.5};
  const std::vector<double> pooled = {4.0, 3.0, 2.0, 1.0};
  const std::vector<std::vector<double>> replicas(4, pooled);
  const SceneInterval o = sceneInterval(x, pooled, replicas);
  EXPECT_TRUE(o.at_bound);
  EXPECT_EQ(o.z, 0.5);
  EXPECT_EQ(o.replicates_at_bound, 4u);
  EXPECT_EQ(o.flat_first, 3u);
  EXPECT_EQ(o.flat_last, 3u);
}

TEST(TuneOptimum, FewerThanThreeClustersIsAnError) {
  const std::vector<double> x = {0.0, 1.0, 2.0};
  const std::vector<double> y = {2.0, 1.0, 2.0};
  EXPECT_THROW(sceneInterval(x, y, {y, y}), Error);
}

}  // namespace
}  // namespace gtbake
