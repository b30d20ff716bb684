// The scene-level statistics of validate-gtso against known answers: the sign-flip test's exact
// p-values and its agreement with the t distribution, u recovered per scene and per law from
// synthetic cone truths, the floor of a truth that is a known function of the inputs (and of one
// that is pure noise), and the out-of-plane table leaving open pixels out.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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

// The count from byte tables of partial sums equals a direct scene-by-scene count of |Σ ±d| ≥
// target, pattern by pattern: exact enumeration (S ≤ 20) and drawn words whose bits past S are
// random (S not a multiple of 8, and S > 64 on two or three words). Targets are the test's own
// (|Σ d| less the slack) and a drawn pattern's |sum| less the slack, and the d include values on
// a 0.1 grid, where many patterns tie with the target in exact arithmetic but not in rounding.
TEST(PairedSignFlip, TableCountEqualsSceneBySceneCount) {
  std::mt19937_64 gen(31);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> small(-4, 4);
  const auto direct = [](const std::vector<double>& d, double target,
                         const std::vector<std::uint64_t>& words, std::uint64_t k) {
    const std::size_t n = (d.size() + 63) / 64;
    double sum = 0.0;
    for (std::size_t s = 0; s < d.size(); ++s) {
      const std::uint64_t w = words.empty() ? k : words[k * n + s / 64];
      sum += (w >> (s % 64)) & 1u ? -d[s] : d[s];
    }
    return std::abs(sum) >= target;
  };
  for (const std::size_t S : {2, 7, 13, 16, 20, 21, 24, 37, 64, 65, 72, 150}) {
    const bool exact = S <= kExactSignFlipScenes;
    const std::uint64_t patterns = exact ? std::uint64_t{1} << S : 4096;
    std::vector<std::uint64_t> words(exact ? 0 : patterns * ((S + 63) / 64));
    for (std::uint64_t& w : words) w = gen();
    for (int trial = 0; trial < (S >= 16 && exact ? 2 : 12); ++trial) {
      std::vector<double> d(S);
      for (double& v : d) {
        v = trial % 3 == 0 ? 0.1 * small(gen) : 1e-3 * (normal(gen) + 0.3 * (trial % 2));
      }
      double sum = 0.0, scale = 0.0;
      for (double v : d) sum += v, scale += std::abs(v);
      const std::uint64_t probe = gen() % patterns;
      double probe_sum = 0.0;
      for (std::size_t s = 0; s < S; ++s) {
        const std::uint64_t w = exact ? probe : words[probe * ((S + 63) / 64) + s / 64];
        probe_sum += (w >> (s % 64)) & 1u ? -d[s] : d[s];
      }
      for (const double target :
           {std::abs(sum) - 1e-12 * scale, std::abs(probe_sum) - 1e-12 * scale}) {
        std::uint64_t expected = 0;
        for (std::uint64_t k = 0; k < patterns; ++k) expected += direct(d, target, words, k);
        EXPECT_EQ(signFlipCountAtLeast(d, target, exact ? nullptr : words.data(), patterns),
                  expected)
            << "S = " << S << ", trial " << trial;
      }
    }
  }
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

// heldOutSquaredErrors against a direct leave-one-cluster-out: each sample's equal-count bins
// computed from the sorted inputs, and its prediction the mean truth less base of the other
// clusters' samples in its cell (else its half-bins cell, else every other cluster's sample),
// averaged sample by sample. Clusters map several scenes, out of scene order; the index skips
// samples; few samples per cell leave some fine and coarse cells empty for a cluster.
TEST(SoFloor, HeldOutErrorsMatchADirectLeaveOneClusterOut) {
  std::mt19937 gen(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<SpecularSample> samples;
  std::vector<float> base;
  for (int k = 0; k < 900; ++k) {
    SpecularSample s = sample(k % 7, 0, unit(gen), kPi * unit(gen), unit(gen), unit(gen));
    s.truth = static_cast<float>(unit(gen));
    samples.push_back(s);
    base.push_back(static_cast<float>(0.5 * unit(gen)));
  }
  const std::vector<int> cluster_of = {2, 0, 1, 2, 0, 1, 2};
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (i % 5 != 3) index.push_back(i);
  }
  const auto input = [&](std::size_t i, int f) {
    const SpecularSample& s = samples[i];
    const double v[4] = {s.A, s.n_dot_b, s.cos_beta, s.n_dot_v};
    return v[f];
  };
  for (const int bins : {3, 4, 6}) {
    for (const bool with_base : {false, true}) {
      // bin[k][f] of index[k]: how many of the bins − 1 equal-count edges are at or below it.
      std::vector<std::array<int, 4>> bin(index.size());
      for (int f = 0; f < 4; ++f) {
        std::vector<double> sorted;
        for (std::size_t i : index) sorted.push_back(input(i, f));
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t k = 0; k < index.size(); ++k) {
          bin[k][f] = 0;
          for (int e = 1; e < bins; ++e)
            bin[k][f] += sorted[sorted.size() * e / bins] <= input(index[k], f);
        }
      }
      const auto same = [&](std::size_t a, std::size_t k, int divisor) {
        for (int f = 0; f < 4; ++f) {
          if (bin[a][f] / divisor != bin[k][f] / divisor) return false;
        }
        return true;
      };
      const std::vector<double> e2 = heldOutSquaredErrors(samples, index, cluster_of, 3, bins,
                                                          with_base ? base : std::vector<float>{});
      ASSERT_EQ(e2.size(), index.size());
      for (std::size_t k = 0; k < index.size(); ++k) {
        const int own = cluster_of[samples[index[k]].scene];
        const double b = with_base ? base[index[k]] : 0.0;
        double prediction = 0.0;
        for (const int divisor : {1, 2, 0}) {
          double sum = 0.0, n = 0.0;
          for (std::size_t a = 0; a < index.size(); ++a) {
            if (cluster_of[samples[index[a]].scene] == own) continue;
            if (divisor > 0 && !same(a, k, divisor)) continue;
            sum += static_cast<double>(samples[index[a]].truth) -
                   (with_base ? static_cast<double>(base[index[a]]) : 0.0);
            n += 1.0;
          }
          if (n > 0.0) {
            prediction = sum / n;
            break;
          }
        }
        const double e = prediction + b - samples[index[k]].truth;
        EXPECT_NEAR(e2[k], e * e, 1e-12) << "bins " << bins << ", base " << with_base << ", " << k;
      }
    }
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
