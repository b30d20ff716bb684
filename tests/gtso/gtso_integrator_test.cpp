// The GTSO integral: closed-form limits, invariants and a brute-force check of the 2.5e-4 claim.
#include <gtest/gtest.h>

#include <cmath>

#include "common/math_constants.h"
#include "common/rng.h"
#include "gtso/gtso_integrator.h"

namespace gtbake::gtso {
namespace {

constexpr int kCells = 48;  // coarser than the default: these are invariants, not accuracy

std::vector<double> aAxis(int n) {
  std::vector<double> c(n);
  for (int j = 0; j < n; ++j) c[j] = std::sqrt(1.0 - static_cast<double>(j) / (n - 1));
  return c;
}

TEST(GtsoIntegrator, FullConeIsOneAndEmptyConeIsZero) {
  for (double rp : {0.0, 0.05, 0.4, 1.0})
    for (double cosO : {1.0, 0.5, 0.0}) {
      const auto s = specularOcclusion(rp, cosO, {{0.0, 0.0, 1.0}}, {0.0, 1.0}, kCells);
      EXPECT_NEAR(s[0], 1.0, 1e-12) << "A = 1, r_p " << rp << " cos " << cosO;
      EXPECT_EQ(s[1], 0.0) << "A = 0, r_p " << rp << " cos " << cosO;
    }
}

TEST(GtsoIntegrator, MonotoneInA) {
  const auto cs = aAxis(32);
  for (double rp : {0.0, 0.1, 0.5, 0.9})
    for (double cosO : {0.9, 0.4, 0.05}) {
      std::vector<Vec3> b;
      for (double beta : {0.0, 0.7, 1.5, 2.5}) b.push_back(bentNormal(std::acos(cosO), beta));
      const auto s = specularOcclusion(rp, cosO, b, cs, kCells);
      for (std::size_t k = 0; k < b.size(); ++k)
        for (std::size_t j = 1; j < cs.size(); ++j) EXPECT_GE(s[k * 32 + j], s[k * 32 + j - 1]);
    }
}

TEST(GtsoIntegrator, FourDAtBetaEqualThetaIsThreeD) {
  const auto cs = aAxis(16);
  for (double rp : {0.0, 0.2, 0.7})
    for (double theta_o : {0.0, 0.6, 1.3, kPi / 2}) {
      const auto s3 = specularOcclusion(rp, std::cos(theta_o), {{0.0, 0.0, 1.0}}, cs, kCells);
      const auto s4 =
          specularOcclusion(rp, std::cos(theta_o),
                            {bentNormal(theta_o, 0.3), bentNormal(theta_o, theta_o)}, cs, kCells);
      for (std::size_t j = 0; j < cs.size(); ++j) EXPECT_NEAR(s4[16 + j], s3[j], 1e-15);
    }
}

TEST(GtsoIntegrator, MirrorLimitIsDeltaVOfReflection) {
  const double theta_o = 0.5;
  const Vec3 n = {0.0, 0.0, 1.0};
  // wr makes 0.5 rad with n: inside cones wider than 0.5, outside narrower, and on the edge
  // inside (docs/gtso.md §1: DeltaV = 1 where angle <= alpha_v).
  const auto s = specularOcclusion(0.0, std::cos(theta_o), {n},
                                   {std::cos(0.6), std::cos(0.4), std::cos(theta_o)}, kCells);
  EXPECT_EQ(s[0], 1.0);
  EXPECT_EQ(s[1], 0.0);
  EXPECT_EQ(s[2], 1.0);
  // ... and the smallest roughness approaches it.
  const auto near = specularOcclusion(0.02, std::cos(theta_o), {n}, {std::cos(0.6), std::cos(0.4)});
  EXPECT_GT(near[0], 0.999);
  EXPECT_LT(near[1], 0.001);
}

// Brute force for the 2.5e-4 claim, low roughness included: visible-normal sampling (ggx.h, an
// independent code path from the quadrature) on a jittered 1024 x 1024 grid, 4 independent
// jitter replicates; S = sum W DeltaV / sum W with W = G2/G1. The replicate spread gives the SE
// (stratification makes it ~1e-5); the quadrature must agree within 2.5e-4 + 4 SE. Each texel
// also checks the cap of half-angle pi - alpha_v (cos = -c, wider than a hemisphere): the
// continuation texels beyond A = 1 of the tables (docs/gtso.md §3).
TEST(GtsoIntegrator, MatchesVisibleNormalBruteForceWithin2p5em4) {
  const CounterRng pick(21, 0);
  constexpr int kGrid = 1024, kReplicates = 4;
  for (int texel = 0; texel < 8; ++texel) {
    const auto u = pick.uniform4(texel, 0);
    const double A = 0.05 + 0.9 * u[0], beta = kPi * u[1], rp = 0.03 + 0.97 * u[2];
    const double theta_o = 1.5 * u[3], c = std::sqrt(1.0 - A);
    const Vec3 b = bentNormal(theta_o, beta), wo = viewDirection(std::cos(theta_o));
    const GgxDistribution ggx(rp * rp);
    double sum[2] = {0.0, 0.0}, sumSq[2] = {0.0, 0.0};
    for (int r = 0; r < kReplicates; ++r) {
      const CounterRng jitter(99 + r, texel);
      double num[2] = {0.0, 0.0}, den = 0.0;
      for (int i = 0; i < kGrid; ++i)
        for (int j = 0; j < kGrid; ++j) {
          const auto v = jitter.uniform4(static_cast<std::uint64_t>(i) * kGrid + j, 0);
          const Vec3 wi = ggx.sampleWi(wo, {(i + v[0]) / kGrid, (j + v[1]) / kGrid});
          const double w = ggx.weight(wo, wi);
          den += w;
          num[0] += dot(wi, b) >= c ? w : 0.0;
          num[1] += dot(wi, b) >= -c ? w : 0.0;
        }
      for (int k = 0; k < 2; ++k) {
        sum[k] += num[k] / den;
        sumSq[k] += (num[k] / den) * (num[k] / den);
      }
    }
    const std::vector<double> got =
        specularOcclusion(rp, std::cos(theta_o), {b}, std::vector<double>{c, -c});
    for (int k = 0; k < 2; ++k) {
      const double S = sum[k] / kReplicates;
      const double se =
          std::sqrt(std::max(0.0, sumSq[k] / kReplicates - S * S) / (kReplicates - 1));
      EXPECT_NEAR(got[k], S, 2.5e-4 + 4.0 * se)
          << "A " << A << " beta " << beta << " r_p " << rp << " theta_o " << theta_o << " se "
          << se << (k ? " (cap wider than a hemisphere)" : "");
    }
  }
}

}  // namespace
}  // namespace gtbake::gtso
