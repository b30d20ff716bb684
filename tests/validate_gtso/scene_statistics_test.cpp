// The scene-level statistics of validate-gtso against known answers: the sign-flip test's exact
// p-values and its agreement with the t distribution, u recovered per scene and per law from
// synthetic cone truths, the floor of a truth that is a known function of the inputs (and of one
// that is pure noise), and the out-of-plane table leaving open pixels out.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "common/math_constants.h"
#include "validate_gtso/out_of_plane.h"
#include "validate_gtso/scene_paired_test.h"
#include "validate_gtso/so_floor.h"
#include "validate_gtso/u_scene_interval.h"

namespace gtbake {
namespace {

constexpr float kRoughness[] = {0.1f, 0.25f, 0.4f, 0.6f, 0.8f};

SpecularSample sample(int scene, int j, double A, double beta, double n_dot_v, double n_dot_b) {
  SpecularSample s;
  s.scene = scene;
  s.roughness = j;
  s.r_p = kRoughness[j];
  s.A = static_cast<float>(A);
  setConeAngles(&s, beta);
  s.n_dot_v = static_cast<float>(n_dot_v);
  s.n_dot_b = static_cast<float>(n_dot_b);
  return s;
}

// Every d_s > 0 with S = 7: only the observed pattern and its mirror reach |Σ d|, p = 2/2^7.
// Mirror-symmetric differences: p = 1. Two scenes of equal |d| and opposite sign: p = 1.
TEST(PairedSignFlip, ExactSmallCases) {
  const std::vector<double> zero(7, 0.0);
  const PairedTest all_up = pairedSignFlip({0.3, 0.1, 0.2, 0.5, 0.1, 0.4, 0.2}, zero);
  EXPECT_DOUBLE_EQ(all_up.p_value, 2.0 / 128.0);
  EXPECT_TRUE(all_up.significant);
  EXPECT_GT(all_up.t, 0.0);
  // d = {3, 1, 1, 1}: |Σ ±d| ≥ 6 only for all + or all −: p = 2/16; d = {3, 1, 1, −1}: |Σ| ≥ 4
  // for (+3 with two or three of the 1s' signs giving ≥ +1) and mirrors: 8 of 16 patterns.
  EXPECT_DOUBLE_EQ(pairedSignFlip({3, 1, 1, 1}, {0, 0, 0, 0}).p_value, 2.0 / 16.0);
  EXPECT_DOUBLE_EQ(pairedSignFlip({3, 1, 1, -1}, {0, 0, 0, 0}).p_value, 8.0 / 16.0);
  EXPECT_DOUBLE_EQ(pairedSignFlip({1, -1}, {0, 0}).p_value, 1.0);
  EXPECT_DOUBLE_EQ(pairedSignFlip({2, 2, 2}, {2, 2, 2}).p_value, 1.0);
  EXPECT_THROW(pairedSignFlip({1, 2}, {1}), Error);
  EXPECT_THROW(pairedSignFlip({1}, {1}), Error);
}

// With 20 normal differences the permutation p-value approaches the paired t test's: at
// t ≈ 2.09 (19 dof) the two-sided t p-value is 0.05; the permutation one lies within 0.02 of it.
TEST(PairedSignFlip, AgreesWithTheTTestForNormalData) {
  std::mt19937_64 gen(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> d(20);
  for (double& v : d) v = normal(gen);
  double mean = 0.0, ss = 0.0;
  for (double v : d) mean += v / 20.0;
  for (double v : d) ss += (v - mean) * (v - mean);
  const double sd = std::sqrt(ss / 19.0);
  for (double& v : d) v += 2.093 * sd / std::sqrt(20.0) - mean;  // t = 2.093 exactly
  const PairedTest t = pairedSignFlip(d, std::vector<double>(20, 0.0));
  EXPECT_NEAR(t.t, 2.093, 1e-9);
  EXPECT_NEAR(t.p_value, 0.05, 0.02);
}

// Beyond 64 scenes a pattern spans several 64-bit words: with 150 normal differences at t = 1.976
// (149 dof, two-sided p = 0.05) the drawn patterns give p within 0.01 of 0.05 (2^20 draws: SE
// 0.0002), a difference carried by scenes 64..149 alone is still found, and a mirrored set
// (each d with its −d) gives p = 1.
TEST(PairedSignFlip, ManyScenesUseEveryScenesSign) {
  constexpr std::size_t S = 150;
  std::mt19937_64 gen(12);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> d(S);
  for (double& v : d) v = normal(gen);
  double mean = 0.0, ss = 0.0;
  for (double v : d) mean += v / S;
  for (double v : d) ss += (v - mean) * (v - mean);
  const double sd = std::sqrt(ss / (S - 1));
  for (double& v : d) v += 1.976 * sd / std::sqrt(double{S}) - mean;
  const std::vector<double> zero(S, 0.0);
  const PairedTest t = pairedSignFlip(d, zero);
  EXPECT_NEAR(t.t, 1.976, 1e-9);
  EXPECT_NEAR(t.p_value, 0.05, 0.01);
  // Only the high words carry the difference: the low 64 scenes are exactly zero.
  std::vector<double> high(S, 0.0);
  for (std::size_t s = 64; s < S; ++s) high[s] = 1.0 + 0.01 * static_cast<double>(s % 7);
  EXPECT_LT(pairedSignFlip(high, zero).p_value, 1e-5);
  std::vector<double> mirrored(S);
  for (std::size_t s = 0; s < S; s += 2) mirrored[s] = -(mirrored[s + 1] = 0.5 + 0.001 * s);
  EXPECT_DOUBLE_EQ(pairedSignFlip(mirrored, zero).p_value, 1.0);
  EXPECT_THROW(pairedSignFlip(std::vector<double>(kMaxPairedScenes + 1, 1.0),
                              std::vector<double>(kMaxPairedScenes + 1, 0.0)),
               Error);
}

TEST(PairedSignFlip, RankingStatementFollowsTheTests) {
  // A beats C on every scene (p = 2/128); B is best pooled and ties A (mixed signs).
  const std::vector<std::vector<double>> per_scene = {
      {0.10, 0.12, 0.11, 0.13, 0.10, 0.12, 0.11},   // A
      {0.09, 0.14, 0.10, 0.12, 0.11, 0.10, 0.10},   // B
      {0.20, 0.22, 0.21, 0.23, 0.20, 0.22, 0.21}};  // C
  const RankingTest r = rankingTest({"A", "B", "C"}, per_scene, {0.115, 0.110, 0.215});
  EXPECT_EQ(r.best, "B");
  ASSERT_EQ(r.tied, std::vector<std::string>{"A"});
  EXPECT_EQ(r.others, (std::vector<std::string>{"A", "C"}));
  EXPECT_TRUE(r.vs_best[1].significant);
  EXPECT_EQ(r.statement.rfind("B has the lowest RMSE; at the scene level it is not "
                              "distinguishable from A (p = ",
                              0),
            0u)
      << r.statement;
}

TEST(GridArgmin, ParabolaIsExactAndBoundsAreFlagged) {
  std::vector<double> x, y;
  for (int k = 0; k <= 20; ++k) {
    x.push_back(-5.0 + 0.25 * k);
    y.push_back(3.0 * (x.back() + 2.37) * (x.back() + 2.37) + 1.0);
  }
  bool at_bound = true;
  EXPECT_NEAR(gridArgmin(x, y, &at_bound), -2.37, 1e-12);
  EXPECT_FALSE(at_bound);
  for (double& v : y) v = -v;
  gridArgmin(x, y, &at_bound);
  EXPECT_TRUE(at_bound);
}

// Three scenes with cone truths of known u under the perceptual law (u = 10^−0.6, 10^−1, 10^−1.4
// plus a little noise): each scene's own optimum recovers its u, the pooled value lies between,
// the jackknife interval covers the middle, and the held-out comparison chooses the perceptual law.
TEST(USceneInterval, RecoversPerSceneUAndChoosesTheGeneratingLaw) {
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  const double log10_u[] = {-0.6, -1.0, -1.4, -0.8};
  std::vector<SpecularSample> samples;
  for (int scene = 0; scene < 4; ++scene) {
    for (int p = 0; p < 1500; ++p) {
      const double A = unit(gen), beta = 0.5 * kPi * unit(gen);
      for (int j = 0; j < 5; ++j) {
        SpecularSample s = sample(scene, j, A, beta, 0.5, 0.9);
        s.truth = coneAt(s, std::pow(10.0, log10_u[scene]), true) + noise(gen);
        samples.push_back(s);
      }
    }
  }
  const UAnalysis a = analyzeU(coneSseTable(samples, {0, 1, 2, 3}, 4, 5));
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(a.per_cluster[1][c].log10_u, log10_u[c], 0.05) << c;
  }
  const USceneInterval& iv = a.interval[1];
  EXPECT_GT(iv.log10_u, -1.4);
  EXPECT_LT(iv.log10_u, -0.6);
  EXPECT_GT(iv.log10_se, 0.0);
  EXPECT_LT(iv.low, std::pow(10.0, -0.95));
  EXPECT_GT(iv.high, std::pow(10.0, -0.95));
  EXPECT_NEAR(iv.u_se, std::pow(10.0, iv.log10_u) * std::log(10.0) * iv.log10_se, 1e-15);
  EXPECT_EQ(a.law.chosen, 1);
  EXPECT_GT(a.law.test.mean_difference, 0.0);  // alpha − perceptual held-out RMSE
  EXPECT_THROW(analyzeU(coneSseTable(samples, {0, 1, 1, 1}, 2, 5)), Error);
}

// A and n·ωr take four values each and the truth is a function of them plus noise σ = 0.05 that no
// input predicts: the held-out floor is σ (each value's cells are learnt from the other scenes; the
// cell means' own noise adds ~1 %), and a truth of pure noise has floor σ too, never less.
TEST(SoFloor, KnownFunctionOfTheInputsAndPureNoise) {
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (bool structured : {true, false}) {
    std::vector<SpecularSample> samples;
    for (int scene = 0; scene < 4; ++scene) {
      for (int p = 0; p < 6000; ++p) {
        const double A = 0.1 + 0.25 * (p % 4), nv = 0.15 + 0.2 * ((p / 4) % 4);
        SpecularSample s = sample(scene, 0, A, kPi * unit(gen), nv, unit(gen));
        const double f = structured ? 0.5 * A * A + 0.3 * nv : 0.4;
        s.truth = f + noise(gen);
        samples.push_back(s);
      }
    }
    const SoFloor floor = soFloor(samples, {0, 1, 2, 3}, 4, 1);
    EXPECT_NEAR(floor.rmse[0], 0.05, 0.005) << structured << " bins " << floor.bins;
    EXPECT_GE(floor.rmse[0], 0.049) << structured;
  }
}

TEST(OutOfPlane, OpenPixelsAreLeftOut) {
  std::vector<SpecularSample> samples;
  for (int k = 0; k < 10; ++k) {
    SpecularSample s = sample(0, 0, k < 6 ? 0.999 : 0.5, 0.3, 0.5, 0.9);
    s.out_of_plane = k < 8 ? 1.0 : 30.0;
    s.truth = 0.5;
    samples.push_back(s);
  }
  const std::vector<float> s4(10, 0.6f), s3(10, 0.7f);
  const std::vector<OutOfPlaneBin> bins = outOfPlaneOccluded(samples, s4, s3);
  EXPECT_EQ(bins[0].open_excluded, 6u);
  EXPECT_EQ(bins[0].s4.count, 2u);
  EXPECT_EQ(bins.back().s4.count, 2u);
  EXPECT_NEAR(bins[0].s3.rmse(), 0.2, 1e-6);
}

}  // namespace
}  // namespace gtbake
