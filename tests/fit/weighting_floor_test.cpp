// Point weighting (pixel / scene / flat-a) and the floor of any fit, on synthetic data with known
// answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "fit/fit_errors.h"
#include "fit/fit_floor.h"
#include "fit/multibounce_fit.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

constexpr MultiBounceCoeffs kOther = {3.0, -0.2, 6.0, -0.5, 3.2, 0.6};

FitSettings weighted(Weighting w) {
  FitSettings s;
  s.weighting = w;
  return s;
}

// One scene with 10× the pixels (its points repeated ten times) of the others. Pixel weighting
// lets it set the curve; scene weighting gives exactly the fit of the sweep in which it has as
// many points as the others (repeating a scene's points and dividing their weight by ten is the
// same sum), to rounding.
TEST(Weighting, SceneWeightingRemovesTheDominanceOfALargeScene) {
  const SweepData base = test::pooledSweep(
      {{"big", kOther, 3000}, {"p1", kPaperCoeffs, 3000}, {"p2", kPaperCoeffs, 3000}}, 0.01, 0.01,
      0.3, 17);
  SweepData dominated;
  test::appendScene(base, 0, dominated, 10);
  test::appendScene(base, 1, dominated);
  test::appendScene(base, 2, dominated);
  const MultiBounceCoeffs equal = fitMultiBounce(base).linear.coeffs;
  const MultiBounceCoeffs pixel = fitMultiBounce(dominated).linear.coeffs;
  const MultiBounceCoeffs scene =
      fitMultiBounce(dominated, weighted(Weighting::kView)).linear.coeffs;
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(scene[i], equal[i], 1e-9 * std::abs(equal[i])) << i;
  // Pixel weighting: the big scene's law weighs 10/12 and the curve lies near it.
  const double pixel_to_big = maxCurveDifference(pixel, kOther).value;
  const double scene_to_big = maxCurveDifference(scene, kOther).value;
  EXPECT_LT(pixel_to_big, 0.3 * scene_to_big);
  EXPECT_GT(maxCurveDifference(pixel, scene).value, 0.02);
}

// Flat-in-A weights give every occupied bin of A the same total weight, with mean weight 1.
TEST(Weighting, FlatAGivesEveryBinOfAEqualWeight) {
  SweepData data = test::knownCoefficientSweep(kPaperCoeffs, 20000, 0.0, 0.01, 0.0, 3);
  for (double& a : data.full.A) a = a * a;  // pile the points up at low A
  const std::vector<double> w = pointWeights(data, Weighting::kFlatA);
  std::vector<double> bin_weight(kFlatABins, 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    bin_weight[std::min(kFlatABins - 1, static_cast<int>(data.full.A[i] * kFlatABins))] += w[i];
    total += w[i];
  }
  EXPECT_NEAR(total, static_cast<double>(w.size()), 1e-6);
  for (double b : bin_weight) EXPECT_NEAR(b, total / kFlatABins, 1e-8 * total);
  EXPECT_THROW(parseWeighting("area"), Error);
  EXPECT_EQ(parseWeighting("flat-a"), Weighting::kFlatA);
}

// Data exactly from Eq. 10 plus noise: no function of A beats the cubic, so the floor equals
// Eq. 10's RMSE (to the floor's binning bias, ~2e-4, and sampling, ~2e-4 relative).
TEST(FitFloor, EqualsEq10RmseOnDataFromEq10PlusNoise) {
  const SweepData data = test::knownCoefficientSweep(kPaperCoeffs, 200000, 0.0, 0.04, 0.0, 21);
  FitSettings settings;
  settings.eiv_correction = false;
  const MultiBounceCoeffs k = fitMultiBounce(data, settings).linear.coeffs;
  const ErrorTable eq10 = errorTable(data, k);
  const FitFloor floor = fitFloor(data);
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    EXPECT_NEAR(floor.per_albedo[j].floor / eq10.per_albedo[j].rmse, 1.0, 1.5e-3) << j;
  }
  EXPECT_NEAR(floor.rmse / eq10.rmse, 1.0, 1.5e-3);
}

// G = m(A) + noise with m not a cubic: the floor recovers the noise (known: σ_G/√2 for the mean
// of two halves) and stays below Eq. 10's RMSE, which also carries the cubic's misfit.
TEST(FitFloor, RecoversTheNoiseAndIsNeverAboveEq10) {
  SweepData data =
      test::pooledSweep({{"p", kPaperCoeffs, 60000}, {"o", kOther, 60000}}, 0.0, 0.02, 0.0, 5);
  // Replace G by a law no cubic fits: m(A) = √A·(1 + ρ/2), plus each half's own noise.
  std::mt19937_64 rng(8);
  std::normal_distribution<double> normal(0.0, 0.02);
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    for (std::size_t i = 0; i < data.points(); ++i) {
      const double m = std::sqrt(data.full.A[i]) * (1.0 + 0.5 * data.albedos[j]);
      data.half[0].G[j][i] = m + normal(rng);
      data.half[1].G[j][i] = m + normal(rng);
      data.full.G[j][i] = 0.5 * (data.half[0].G[j][i] + data.half[1].G[j][i]);
    }
  }
  const MultiBounceCoeffs k = fitMultiBounce(data).linear.coeffs;
  const ErrorTable eq10 = errorTable(data, k);
  const FitFloor floor = fitFloor(data);
  const double sigma = 0.02 / std::sqrt(2.0);
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    EXPECT_LE(floor.per_albedo[j].floor, eq10.per_albedo[j].rmse) << j;
    // √A has slope 1/(2√A): binning adds (m'h)²/12, large only in the first bins.
    EXPECT_NEAR(floor.per_albedo[j].floor / sigma, 1.0, 0.02) << j;
  }
  EXPECT_LT(floor.rmse, 0.8 * eq10.rmse);
}

}  // namespace
}  // namespace gtbake
