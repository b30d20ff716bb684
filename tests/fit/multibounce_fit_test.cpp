// The two-stage fit against closed forms and synthetic data with known coefficients.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "common/error.h"
#include "common/threads.h"
#include "fit/multibounce_fit.h"
#include "fit/scene_jackknife.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

using test::knownCoefficientSweep;

// Ceres' cubic solve and covariance equal the normal-equations answer computed by Eigen QR.
TEST(MultiBounceFit, CeresMatchesClosedFormLeastSquares) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::size_t n = 5001;  // not a multiple of the residual chunk
  std::vector<double> A(n), G(n);
  Eigen::MatrixXd X(n, 3);
  Eigen::VectorXd y(n);
  for (std::size_t i = 0; i < n; ++i) {
    A[i] = uniform(rng);
    G[i] = 0.9 * A[i] * A[i] * A[i] - 1.7 * A[i] * A[i] + 1.6 * A[i] + 0.05 * (uniform(rng) - 0.5);
    X.row(i) << A[i] * A[i] * A[i], -A[i] * A[i], A[i];
    y[i] = G[i];
  }
  const CubicSolve solve = fitCubic(A, G);
  const Eigen::Vector3d theta = X.colPivHouseholderQr().solve(y);
  const Eigen::Matrix3d unit = (X.transpose() * X).inverse();
  for (int q = 0; q < 3; ++q) {
    EXPECT_NEAR(solve.theta[q], theta[q], 1e-9) << q;
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(solve.unit_covariance[3 * q + r], unit(q, r), 1e-7 * std::abs(unit(q, r)));
    }
  }
  EXPECT_NEAR(solve.rss, (y - X * theta).squaredNorm(), 1e-9);
}

// Noise in G only: the fit is unbiased and lands within 3 SE of the known coefficients; with iid
// noise and an exact model the sandwich SE equals Ceres' covariance × σ̂².
TEST(MultiBounceFit, RecoversKnownCoefficientsWithinThreeSE) {
  const SweepData data = knownCoefficientSweep(kPaperCoeffs, 20000, 0.0, 0.01, 0.0, 11);
  const MultiBounceFit fit = fitMultiBounce(data);
  for (const AlbedoFit& f : fit.per_albedo) {
    const Cubic truth = cubicAt(kPaperCoeffs, f.rho);
    for (int q = 0; q < 3; ++q) {
      EXPECT_LT(std::abs(f.theta[q] - truth[q]), 3.0 * f.se[q]) << f.rho << " " << q;
      EXPECT_NEAR(f.se[q] / f.se_iid[q], 1.0, 0.1);
      EXPECT_NEAR(f.eiv_bias[q], 0.0,
                  1e-4 * f.se[q]);  // G noise alone: the halves average to the full
    }
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT(std::abs(fit.linear.coeffs[i] - kPaperCoeffs[i]), 3.0 * fit.linear.se[i]) << i;
  }
}

// The reported SE of every linear coefficient matches the scatter over independent seeds.
TEST(MultiBounceFit, StandardErrorMatchesScatterOverSeeds) {
  constexpr int kSeeds = 40;
  double sum[6] = {}, sum2[6] = {}, se[6] = {};
  for (int s = 0; s < kSeeds; ++s) {
    const SweepData data = knownCoefficientSweep(kPaperCoeffs, 3000, 0.01, 0.02, 0.5, 100 + s);
    const MultiBounceFit fit = fitMultiBounce(data);
    for (int i = 0; i < 6; ++i) {
      sum[i] += fit.linear.coeffs[i];
      sum2[i] += fit.linear.coeffs[i] * fit.linear.coeffs[i];
      se[i] += fit.linear.se[i] / kSeeds;
    }
  }
  for (int i = 0; i < 6; ++i) {
    const double mean = sum[i] / kSeeds;
    const double scatter = std::sqrt((sum2[i] / kSeeds - mean * mean) * kSeeds / (kSeeds - 1));
    EXPECT_GT(scatter / se[i], 0.7) << i;
    EXPECT_LT(scatter / se[i], 1.3) << i;
  }
}

// Planted noise in the regressor A: the uncorrected fit is biased by many SE, the split-half
// measurement finds that bias, and the corrected fit is back within 3 SE of the truth.
TEST(MultiBounceFit, EivBiasDetectsPlantedRegressorNoise) {
  const SweepData data = knownCoefficientSweep(kPaperCoeffs, 40000, 0.035, 0.005, 0.3, 23);
  const MultiBounceFit fit = fitMultiBounce(data);
  double worst_raw = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double actual = fit.linear.uncorrected[i] - kPaperCoeffs[i];
    worst_raw = std::max(worst_raw, std::abs(actual) / fit.linear.se[i]);
    EXPECT_NEAR(fit.linear.eiv_bias[i], actual, 0.15 * std::abs(actual) + 3.0 * fit.linear.se[i])
        << i;
    EXPECT_LT(std::abs(fit.linear.coeffs[i] - kPaperCoeffs[i]), 3.0 * fit.linear.se[i]) << i;
  }
  EXPECT_GT(worst_raw, 5.0);
}

// What the correction leaves, against planted truth: heavy regressor noise (σ_A = 0.045 to 0.075
// per half, so the bias has cubic and higher terms) on 400 000 points, where the Monte Carlo SE is
// small beside the bias. The reported bound |cubic − quadratic extrapolation| must cover the
// corrected fit's actual error, and not by a factor that makes it meaningless.
TEST(MultiBounceFit, EivResidualBoundCoversTheCorrectedFitsError) {
  double worst_share = 0.0;  // the largest |actual error| / bound among the informative cases
  for (const std::uint64_t seed : {31, 32}) {
    for (const double sigma : {0.045, 0.06, 0.075}) {
      const SweepData data = knownCoefficientSweep(kPaperCoeffs, 400000, sigma, 0.005, 0.3, seed);
      const MultiBounceFit fit = fitMultiBounce(data);
      for (int i = 0; i < 6; ++i) {
        const double actual = std::abs(fit.linear.coeffs[i] - kPaperCoeffs[i]);
        const double bound =
            remainingBias(fit.linear.eiv_bias[i], fit.linear.eiv_bias_quadratic[i], true);
        const double se = fit.linear.se[i];
        EXPECT_LT(actual, bound + se) << "sigma " << sigma << " coefficient " << i;
        if (bound > 3.0 * se) worst_share = std::max(worst_share, actual / bound);
      }
    }
  }
  // Not vacuous: where the bound stands clear of the noise, the actual error reaches a real
  // part of it (measured 0.86 at σ_A = 0.075).
  EXPECT_GT(worst_share, 0.5);
}

// A without noise (a screen-space estimate: both halves carry the full A) has no
// errors-in-variables bias: the levels differ only in G, in which least squares is linear. The fit
// reports exact zeros, not the levels' rounding, and the corrected and plain fits are one; a
// single noisy point in A turns the detection off.
TEST(MultiBounceFit, EivBiasIsExactlyZeroForNoiseFreeA) {
  SweepData data = knownCoefficientSweep(kPaperCoeffs, 20000, 0.0, 0.02, 0.0, 17);
  const MultiBounceFit fit = fitMultiBounce(data);
  EXPECT_TRUE(fit.a_noise_free);
  for (const AlbedoFit& f : fit.per_albedo) {
    for (int q = 0; q < 3; ++q) {
      EXPECT_EQ(f.eiv_bias[q], 0.0);
      EXPECT_EQ(f.eiv_bias_quadratic[q], 0.0);
      EXPECT_EQ(f.eiv_bias_two_point[q], 0.0);
      EXPECT_EQ(f.theta[q], f.uncorrected[q]);
    }
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(fit.linear.eiv_bias[i], 0.0);
    EXPECT_EQ(fit.linear.coeffs[i], fit.linear.uncorrected[i]);
  }
  data.half[0].A[123] += 1e-3;
  data.half[1].A[123] -= 1e-3;
  const MultiBounceFit noisy = fitMultiBounce(data);
  EXPECT_FALSE(noisy.a_noise_free);
  double largest = 0.0;
  for (int i = 0; i < 6; ++i) largest = std::max(largest, std::abs(noisy.linear.eiv_bias[i]));
  EXPECT_GT(largest, 0.0);
}

// The fit from per-scene sums equals an independent raw-point implementation of the same
// estimator (per level a QR least-squares cubic on the raw points, SIMEX extrapolation, QR lines)
// to 1e-9 relative: the reduction to normal equations changes no coefficient.
TEST(MultiBounceFit, SufficientStatisticsMatchRawPointLeastSquares) {
  const SweepData data = test::pooledSweep(
      {{"s1", kPaperCoeffs, 7000}, {"s2", {3.0, -0.2, 6.0, -0.5, 3.2, 0.7}, 5000}}, 0.03, 0.01, 0.4,
      5);
  const MultiBounceFit fit = fitMultiBounce(data);
  const std::size_t n = data.points(), M = data.albedos.size();
  std::vector<std::array<double, 3>> level_theta[kLevels];
  for (int l = 0; l < kLevels; ++l) {
    const double c = 0.5 * kLevelScale[l];
    Eigen::MatrixXd X(n, 3);
    for (std::size_t i = 0; i < n; ++i) {
      const double A = data.full.A[i] + c * (data.half[0].A[i] - data.half[1].A[i]);
      X.row(i) << A * A * A, -A * A, A;
    }
    const auto qr = X.colPivHouseholderQr();
    for (std::size_t j = 0; j < M; ++j) {
      Eigen::VectorXd y(n);
      for (std::size_t i = 0; i < n; ++i) {
        y[i] = data.full.G[j][i] + c * (data.half[0].G[j][i] - data.half[1].G[j][i]);
      }
      const Eigen::Vector3d t = qr.solve(y);
      level_theta[l].push_back({t[0], t[1], t[2]});
    }
  }
  Eigen::MatrixXd R(M, 2), theta(M, 3);
  for (std::size_t j = 0; j < M; ++j) {
    R.row(j) << data.albedos[j], 1.0;
    for (int q = 0; q < 3; ++q) {
      const double t1 = level_theta[0][j][q];
      const double t2 = 0.5 * (level_theta[1][j][q] + level_theta[2][j][q]);
      const double t3 = 0.5 * (level_theta[3][j][q] + level_theta[4][j][q]);
      const double t4 = 0.5 * (level_theta[5][j][q] + level_theta[6][j][q]);
      theta(j, q) = 4.0 * t1 - 6.0 * t2 + 4.0 * t3 - t4;
      EXPECT_NEAR(fit.per_albedo[j].theta[q], theta(j, q), 1e-9 * std::abs(theta(j, q)));
    }
  }
  for (int q = 0; q < 3; ++q) {
    const Eigen::Vector2d line = R.colPivHouseholderQr().solve(theta.col(q));
    for (int e = 0; e < 2; ++e) {
      EXPECT_NEAR(fit.linear.coeffs[2 * q + e], line[e], 1e-9 * std::abs(line[e])) << q << e;
    }
  }
}

// --constrain-open: every per-albedo cubic and the lines satisfy a − b + c = 1, so G(1, ρ) = 1 to
// rounding; the constrained cubic equals an independent QR solve of G − A ≈ a(A³ − A) − b(A² − A);
// and the constraint cannot lower the least-squares RSS.
TEST(MultiBounceFit, ConstrainOpenGivesOneAtAEqualsOne) {
  const SweepData data = test::pooledSweep(
      {{"s1", kPaperCoeffs, 6000}, {"s2", {3.0, -0.2, 6.0, -0.5, 3.2, 0.6}, 6000}}, 0.0, 0.01, 0.0,
      9);
  FitSettings settings;
  settings.eiv_correction = false;
  const MultiBounceFit free_fit = fitMultiBounce(data, settings);
  settings.constrain_open = true;
  const MultiBounceFit fit = fitMultiBounce(data, settings);
  for (double rho = 0.0; rho <= 1.0; rho += 0.05) {
    EXPECT_NEAR(evalMultiBounce(fit.linear.coeffs, 1.0, rho), 1.0, 1e-13) << rho;
  }
  // The free fit on this data is not open (a − b + c differs from 1), so the test can fail.
  EXPECT_GT(std::abs(evalMultiBounce(free_fit.linear.coeffs, 1.0, 0.9) - 1.0), 1e-3);
  const std::size_t n = data.points();
  Eigen::MatrixXd X(n, 2);
  for (std::size_t i = 0; i < n; ++i) {
    const double A = data.full.A[i];
    X.row(i) << A * A * A - A, -(A * A - A);
  }
  const auto qr = X.colPivHouseholderQr();
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    Eigen::VectorXd y(n);
    for (std::size_t i = 0; i < n; ++i) y[i] = data.full.G[j][i] - data.full.A[i];
    const Eigen::Vector2d ab = qr.solve(y);
    const Cubic& t = fit.per_albedo[j].theta;
    EXPECT_NEAR(t[0], ab[0], 1e-9 * std::abs(ab[0]));
    EXPECT_NEAR(t[1], ab[1], 1e-9 * std::abs(ab[1]));
    EXPECT_NEAR(t[2], 1.0 - ab[0] + ab[1], 1e-9);
    EXPECT_GE(fit.per_albedo[j].rmse, free_fit.per_albedo[j].rmse);
  }
}

// Every point at the same A cannot determine a cubic: a one-line gtbake::Error, not numbers.
TEST(MultiBounceFit, DegenerateDataIsAnError) {
  const std::vector<double> A(3000, 0.5);  // cannot determine a cubic
  std::vector<double> G(3000);
  for (std::size_t i = 0; i < G.size(); ++i) G[i] = 0.4 + 1e-3 * static_cast<double>(i % 7);
  EXPECT_THROW(fitCubic(A, G), Error);
}

// Same data, 1 or 2 threads: bit-identical coefficients, Monte Carlo and scene-jackknife SEs.
TEST(MultiBounceFit, DeterministicAcrossThreadCounts) {
  const SweepData data = test::pooledSweep({{"s1", kPaperCoeffs, 2000},
                                            {"s2", {3.0, -0.2, 6.0, -0.5, 3.2, 0.7}, 1500},
                                            {"s3", kPaperCoeffs, 1800}},
                                           0.02, 0.01, 0.5, 31);
  MultiBounceFit fits[2];
  SceneJackknife jk[2];
  for (int t = 0; t < 2; ++t) {
    ThreadLimit limit(t + 1);
    fits[t] = fitMultiBounce(data);
    jk[t] = sceneJackknife(data, fits[t], kPaperCoeffs);
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(fits[0].linear.coeffs[i], fits[1].linear.coeffs[i]);
    EXPECT_EQ(fits[0].linear.se[i], fits[1].linear.se[i]);
    EXPECT_EQ(fits[0].linear.eiv_bias[i], fits[1].linear.eiv_bias[i]);
    EXPECT_EQ(jk[0].se[i], jk[1].se[i]);
  }
  EXPECT_EQ(jk[0].band_max.value, jk[1].band_max.value);
}

}  // namespace
}  // namespace gtbake
