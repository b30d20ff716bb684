// The squared error of Eq. 10 from sufficient statistics against a pass over the points
// (docs/tune.md §2, §6).
#include <gtest/gtest.h>

#include <cmath>

#include "fit/multibounce_fit.h"
#include "synthetic_sweep.h"
#include "tune/tune_analysis.h"
#include "tune/tune_statistics.h"

namespace gtbake {
namespace {

constexpr double kRelative = 1e-9;

// Four views of three scenes (views 0 and 1 are one scene), each from its own law and noise.
SweepData threeClusterSweep() {
  const MultiBounceCoeffs other = {1.2, 0.1, 3.1, -0.2, 2.9, 0.4};
  const MultiBounceCoeffs third = {-0.5, 1.5, 0.8, 2.1, 1.6, 1.3};
  SweepData data = test::pooledSweep({{"s0", kPaperCoeffs, 3000},
                                      {"s0_v1", other, 2000},
                                      {"s1", third, 2500},
                                      {"s2", other, 1000}},
                                     0.02, 0.03, 0.5, 17);
  data.scenes[1].cluster = "s0";
  return data;
}

TEST(TuneStatistics, SumSquaredErrorEqualsTheDirectSumForPaperAndRefitConstants) {
  const SweepData data = threeClusterSweep();
  const Grouping clusters = groupByScene(data);
  ASSERT_EQ(clusters.names.size(), 3u);
  EXPECT_EQ(clusters.of, (std::vector<std::size_t>{0, 0, 1, 2}));
  const auto stats = clusterStatistics(data, clusters, clusterTargetSquares(data, clusters));
  const MultiBounceCoeffs refit =
      refitCoefficients(sumClusters(stats), data.albedos, profileFitSettings());
  const MultiBounceCoeffs without_last = refitCoefficients(sumClusters(stats, {true, true, false}),
                                                           data.albedos, profileFitSettings());
  for (const MultiBounceCoeffs& k : {kPaperCoeffs, refit, without_last}) {
    std::vector<std::size_t> every;
    for (std::size_t c = 0; c < clusters.names.size(); ++c) {
      std::vector<std::size_t> views;
      for (std::size_t v = 0; v < data.scenes.size(); ++v) {
        if (clusters.of[v] == c) views.push_back(v);
      }
      every.insert(every.end(), views.begin(), views.end());
      const double direct = directSquaredError(data, views, k);
      EXPECT_NEAR(sumSquaredError(stats[c], data.albedos, k), direct, kRelative * direct);
    }
    const double direct = directSquaredError(data, every, k);
    EXPECT_NEAR(sumSquaredError(sumClusters(stats), data.albedos, k), direct, kRelative * direct);
  }
}

TEST(TuneStatistics, RefitIsTheProfileFit) {
  const SweepData data = threeClusterSweep();
  const Grouping clusters = groupByScene(data);
  const auto stats = clusterStatistics(data, clusters, clusterTargetSquares(data, clusters));
  const MultiBounceCoeffs refit =
      refitCoefficients(sumClusters(stats), data.albedos, profileFitSettings());
  const MultiBounceFit fit = fitMultiBounce(data, profileFitSettings());
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(refit[i], fit.linear.coeffs[i], kRelative * std::abs(fit.linear.coeffs[i]));
  }
}

}  // namespace
}  // namespace gtbake
