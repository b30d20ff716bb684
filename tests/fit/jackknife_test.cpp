// The scene jackknife against synthetic clusters with a known between-scene spread, its band
// against a direct computation, the t quantiles against the t distribution, and the verdict.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit/multibounce_fit.h"
#include "fit/scene_jackknife.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

constexpr std::size_t kScenes = 20;
constexpr std::size_t kPointsPerScene = 1000;
constexpr int kRealizations = 8;
// The direction in which scenes differ: c(ρ) += δ_s (1 + ρ), i.e. G += δ_s (1 + ρ) A.
constexpr MultiBounceCoeffs kDirection = {0, 0, 0, 0, 1, 1};
// These tests check the SE and the band, not the threshold: a coarse grid (0.02 in A, 0.05 in ρ)
// and 1000 draws keep them fast (simultaneous_band_test.cpp tests the threshold).
const BandRule kCoarse{50, 16, {0.95, 1000, 1}};

// kScenes scenes whose constants are kPaperCoeffs + δ_s kDirection, δ_s ~ N(0, tau²).
SweepData clusters(double tau, double sigma_A, double sigma_G, std::uint64_t seed,
                   std::vector<double>* deltas) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, tau);
  std::vector<test::SyntheticScene> scenes;
  for (std::size_t s = 0; s < kScenes; ++s) {
    const double delta = tau > 0 ? normal(rng) : 0.0;
    if (deltas) deltas->push_back(delta);
    MultiBounceCoeffs k = kPaperCoeffs;
    for (int i = 0; i < 6; ++i) k[i] += delta * kDirection[i];
    scenes.push_back({"s" + std::to_string(s), k, kPointsPerScene});
  }
  return test::pooledSweep(scenes, sigma_A, sigma_G, 0.3, seed * 1000);
}

// Between-scene spread tau, tiny Monte Carlo noise. The pooled fit is (nearly) the mean of the
// scenes' constants, so its SE is tau/√S along kDirection: the jackknife's mean variance over
// realizations recovers tau²/S within its sampling error (relative SD √(2/(S − 1)) per
// realization, /√R over R), and in each realization it equals the sample variance of the δ_s / S
// (the jackknife of a mean is exact) up to the scenes' unequal Gram matrices (~3 %).
TEST(SceneJackknife, RecoversKnownBetweenSceneSpread) {
  constexpr double kTau = 0.05;
  double mean_ratio = 0.0;
  for (int r = 0; r < kRealizations; ++r) {
    std::vector<double> deltas;
    const SweepData data = clusters(kTau, 0.0, 1e-4, 40 + r, &deltas);
    const MultiBounceFit fit = fitMultiBounce(data);
    const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs, kCoarse);
    ASSERT_TRUE(jk.available);
    double mean = 0.0, var = 0.0;
    for (double d : deltas) mean += d / kScenes;
    for (double d : deltas) var += (d - mean) * (d - mean) / (kScenes - 1);
    for (int i : {4, 5}) {
      EXPECT_NEAR(jk.se[i] / std::sqrt(var / kScenes), 1.0, 0.1) << "realization " << r << " " << i;
      mean_ratio += jk.se[i] * jk.se[i] / (kTau * kTau / kScenes) / (2 * kRealizations);
    }
  }
  EXPECT_NEAR(mean_ratio, 1.0, 3.0 * std::sqrt(2.0 / ((kScenes - 1) * kRealizations)));
}

// No between-scene spread: the scenes are exchangeable draws of Monte Carlo noise, and the
// jackknife variance estimates the Monte Carlo variance, within the same sampling error.
TEST(SceneJackknife, CollapsesToMonteCarloWithoutSpread) {
  double mean_ratio[6] = {};
  for (int r = 0; r < kRealizations; ++r) {
    const SweepData data = clusters(0.0, 0.01, 0.02, 70 + r, nullptr);
    const MultiBounceFit fit = fitMultiBounce(data);
    const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs, kCoarse);
    for (int i = 0; i < 6; ++i) {
      mean_ratio[i] += jk.se[i] * jk.se[i] / (fit.linear.se[i] * fit.linear.se[i]) / kRealizations;
    }
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(mean_ratio[i], 1.0, 3.0 * std::sqrt(2.0 / ((kScenes - 1) * kRealizations))) << i;
  }
}

// The band is the jackknife SD of G itself: (S − 1)/S Σ (G_(s) − Ḡ)² at each (A, ρ), computed
// here from the leave-one-out constants directly.
TEST(SceneJackknife, BandIsTheJackknifeSpreadOfTheCurve) {
  const SweepData data = clusters(0.05, 0.0, 0.01, 3, nullptr);
  const MultiBounceFit fit = fitMultiBounce(data);
  const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs, kCoarse);
  for (double A : {0.1, 0.37, 0.8, 1.0}) {
    for (double rho : {0.1, 0.55, 0.9}) {
      double mean = 0.0, sum2 = 0.0;
      for (const LeaveOneOut& r : jk.leave_one_out) mean += evalMultiBounce(r.linear, A, rho);
      mean /= kScenes;
      for (const LeaveOneOut& r : jk.leave_one_out) {
        sum2 += std::pow(evalMultiBounce(r.linear, A, rho) - mean, 2);
      }
      const double direct = std::sqrt(sum2 * (kScenes - 1) / kScenes);
      EXPECT_NEAR(curveBand(jk.covariance, A, rho), direct, 1e-9 * direct) << A << " " << rho;
      EXPECT_NEAR(jackknifeBand(jk, A, rho), direct, 1e-12 * direct) << A << " " << rho;
    }
  }
  EXPECT_GE(jk.band_max.value, jackknifeBand(jk, 1.0, 0.9));
}

// Constants equal to the refit are consistent; constants moved by 10 band widths are not, and the
// verdict says where. Fewer than three scenes: no jackknife, and a message that says why.
TEST(SceneJackknife, ScoresConstantsAgainstTheBand) {
  const SweepData data = clusters(0.05, 0.0, 0.01, 4, nullptr);
  const MultiBounceFit fit = fitMultiBounce(data);
  const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs, kCoarse);
  const BandScore same = scoreAgainstBand(jk, fit.linear.coeffs, fit.linear.coeffs);
  EXPECT_TRUE(same.consistent);
  EXPECT_NE(same.verdict.find("consistent"), std::string::npos);
  MultiBounceCoeffs moved = fit.linear.coeffs;
  moved[5] += 10.0 * jk.threshold * jk.se[5];  // c0: G moves by that times A
  const BandScore far = scoreAgainstBand(jk, fit.linear.coeffs, moved);
  EXPECT_FALSE(far.consistent);
  EXPECT_GT(far.max_ratio.value, 5.0 * jk.threshold);
  EXPECT_NE(far.verdict.find("outside"), std::string::npos);

  // Under --constrain-open every replica has G(1, ρ) = 1: the band vanishes at A = 1 and the
  // score ignores it instead of dividing by rounding.
  FitSettings open;
  open.constrain_open = true;
  const MultiBounceFit open_fit = fitMultiBounce(data, open);
  const SceneJackknife open_jk = sceneJackknife(data, open_fit, kPaperCoeffs, kCoarse);
  EXPECT_LT(jackknifeBand(open_jk, 1.0, 0.5), 1e-12);
  EXPECT_LT(scoreAgainstBand(open_jk, open_fit.linear.coeffs, kPaperCoeffs).max_ratio.value, 1e3);

  SweepData two;
  test::appendScene(data, 0, two);
  test::appendScene(data, 1, two);
  const MultiBounceFit fit2 = fitMultiBounce(two);
  const SceneJackknife jk2 = sceneJackknife(two, fit2, kPaperCoeffs, kCoarse);
  EXPECT_FALSE(jk2.available);
  EXPECT_EQ(jk2.leave_one_out.size(), 2u);
  EXPECT_NE(jk2.message.find("at least 3 scenes"), std::string::npos) << jk2.message;
  EXPECT_FALSE(scoreAgainstBand(jk2, fit2.linear.coeffs, kPaperCoeffs).consistent);
}

// Entries that view one scene (sweep.json scenes[].scene) are one cluster: the jackknife over
// pairs of views equals the jackknife of the same points with each pair merged into one entry.
TEST(SceneJackknife, ViewsOfOneSceneAreOneCluster) {
  const SweepData views = clusters(0.05, 0.0, 0.01, 9, nullptr);
  SweepData tagged = views, merged = views;
  merged.scenes.clear();
  for (std::size_t s = 0; s < kScenes; ++s) tagged.scenes[s].cluster = "c" + std::to_string(s / 2);
  for (std::size_t s = 0; s < kScenes; s += 2) {
    merged.scenes.push_back(
        {"c" + std::to_string(s / 2), views.scenes[s].begin, views.scenes[s + 1].end});
  }
  const SceneJackknife a = sceneJackknife(tagged, fitMultiBounce(tagged), kPaperCoeffs, kCoarse);
  const SceneJackknife b = sceneJackknife(merged, fitMultiBounce(merged), kPaperCoeffs, kCoarse);
  ASSERT_EQ(a.scenes, kScenes / 2);
  ASSERT_EQ(a.leave_one_out.size(), kScenes / 2);
  EXPECT_EQ(a.leave_one_out[3].left_out, "c3");
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(a.se[i], b.se[i], 1e-9 * b.se[i]) << i;
  EXPECT_NEAR(a.threshold, b.threshold, 1e-9);
}

// studentT975 against the t distribution itself: the CDF (Simpson's rule on the density) at the
// quantile is 0.975 to the table's three decimals, and beyond the table (the expansion; 47 is the
// default corpus's scenes less one) at least as closely.
TEST(SceneJackknife, StudentQuantilesMatchTheDistribution) {
  for (std::size_t dof : {1u, 2u, 6u, 12u, 30u, 31u, 47u, 100u, 1000u}) {
    const double nu = static_cast<double>(dof);
    const double norm = std::exp(std::lgamma((nu + 1) / 2) - std::lgamma(nu / 2)) /
                        std::sqrt(nu * 3.14159265358979323846);
    const auto pdf = [&](double t) { return norm * std::pow(1 + t * t / nu, -(nu + 1) / 2); };
    const double q = studentT975(dof);
    constexpr int kSteps = 20000;
    double integral = pdf(0) + pdf(q);
    for (int k = 1; k < kSteps; ++k) integral += (k % 2 ? 4 : 2) * pdf(q * k / kSteps);
    integral *= q / kSteps / 3;
    EXPECT_NEAR(0.5 + integral, 0.975, (dof > 30 ? 1e-6 : 0.0005) * pdf(q) + 1e-6) << dof;
  }
  EXPECT_GT(studentT975(47), 2.0);  // not the normal's 1.96 (t_0.975,47 = 2.0117)
  EXPECT_LT(studentT975(31), studentT975(30));
}

}  // namespace
}  // namespace gtbake

namespace gtbake {
namespace {

// Leaving out the only scene that spans A leaves two scenes of one A value each, which cannot
// determine a cubic: the jackknife is unavailable and names that scene; the fit itself stands.
TEST(SceneJackknife, UndeterminedReplicaMakesTheJackknifeUnavailable) {
  SweepData data = test::pooledSweep(
      {{"spans", kPaperCoeffs, 3000}, {"flat1", kPaperCoeffs, 500}, {"flat2", kPaperCoeffs, 500}},
      0.0, 0.01, 0.0, 12);
  for (std::size_t s = 1; s < 3; ++s) {
    for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
      const double A = s == 1 ? 0.5 : 0.3;
      data.full.A[i] = data.half[0].A[i] = data.half[1].A[i] = A;
    }
  }
  const MultiBounceFit fit = fitMultiBounce(data);
  const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs, kCoarse);
  EXPECT_FALSE(jk.available);
  EXPECT_NE(jk.message.find("'spans'"), std::string::npos) << jk.message;
}

}  // namespace
}  // namespace gtbake

namespace gtbake {
namespace {

// Two levels: 8 types of 4 scenes of 2 views each. A type moves c(ρ) by δ_t ~ N(0, 0.05²), a
// scene by a further ε_s ~ N(0, 0.01²); the two views of a scene share its constants (other
// pixels, same geometry). The delete-one-type jackknife deletes all 8 views of a type and
// recovers the sample spread of the type means over the 8 types; the delete-one-scene jackknife
// clusters the two views of a scene, so it recovers the spread of the 32 scene constants (a
// delete-one-view jackknife would treat the pair as independent and shrink the SE by about √2).
// Both are the jackknife of a mean of equal-sized groups, exact up to the groups' Gram matrices.
TEST(GroupJackknife, TypesAndScenesClusterTheirViews) {
  constexpr int kTypes = 8, kScenesPerType = 4, kViews = 2;
  std::mt19937_64 rng(77);
  std::normal_distribution<double> type_shift(0.0, 0.05), scene_shift(0.0, 0.01);
  std::vector<test::SyntheticScene> views;
  std::vector<double> type_delta, scene_delta;
  for (int t = 0; t < kTypes; ++t) {
    type_delta.push_back(type_shift(rng));
    for (int s = 0; s < kScenesPerType; ++s) {
      scene_delta.push_back(type_delta.back() + scene_shift(rng));
      MultiBounceCoeffs k = kPaperCoeffs;
      for (int i = 0; i < 6; ++i) k[i] += scene_delta.back() * kDirection[i];
      for (int v = 0; v < kViews; ++v) {
        views.push_back(
            {"t" + std::to_string(t) + "s" + std::to_string(s) + "v" + std::to_string(v), k,
             kPointsPerScene});
      }
    }
  }
  SweepData data = test::pooledSweep(views, 0.0, 1e-4, 0.3, 5000);
  for (std::size_t i = 0; i < data.scenes.size(); ++i) {
    const std::size_t scene = i / kViews, type = scene / kScenesPerType;
    data.scenes[i].cluster = "scene" + std::to_string(scene);
    data.scenes[i].type = "type" + std::to_string(type);
  }
  const MultiBounceFit fit = fitMultiBounce(data);
  const auto spread = [](const std::vector<double>& x) {
    double mean = 0.0, var = 0.0;
    for (double d : x) mean += d / x.size();
    for (double d : x) var += (d - mean) * (d - mean) / (x.size() - 1);
    return std::sqrt(var / x.size());  // SE of the mean
  };
  const SceneJackknife by_type = typeJackknife(data, fit, kPaperCoeffs);
  const SceneJackknife by_scene = sceneJackknife(data, fit, kPaperCoeffs);
  ASSERT_TRUE(by_type.available && by_scene.available);
  EXPECT_EQ(by_type.scenes, static_cast<std::size_t>(kTypes));
  EXPECT_EQ(by_scene.scenes, static_cast<std::size_t>(kTypes * kScenesPerType));
  EXPECT_EQ(by_type.unit, "type");
  EXPECT_EQ(by_scene.leave_one_out[5].left_out, "scene5");
  // n - 1 degrees of freedom of the type level: the pointwise quantile, and the simultaneous
  // max-t over the grid above it.
  EXPECT_DOUBLE_EQ(by_type.pointwise_threshold, studentT975(kTypes - 1));
  EXPECT_GT(by_type.threshold, by_type.pointwise_threshold);
  for (int i : {4, 5}) {
    EXPECT_NEAR(by_type.se[i] / spread(type_delta), 1.0, 0.1) << i;
    EXPECT_NEAR(by_scene.se[i] / spread(scene_delta), 1.0, 0.1) << i;
  }
  // Without clusters every view is its own group: the pairs count twice and the SE shrinks.
  for (SweepScene& v : data.scenes) v.cluster.clear();
  const SceneJackknife by_view = sceneJackknife(data, fit, kPaperCoeffs);
  EXPECT_EQ(by_view.scenes, views.size());
  EXPECT_LT(by_view.se[4], 0.85 * by_scene.se[4]);
}

}  // namespace
}  // namespace gtbake
