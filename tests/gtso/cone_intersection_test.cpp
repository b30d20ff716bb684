// Solid angle of two intersecting spherical caps against Monte Carlo, in every case.
#include <gtest/gtest.h>

#include <cmath>

#include "common/math_constants.h"
#include "common/rng.h"
#include "gtso/cone_intersection.h"

namespace gtbake::gtso {
namespace {

double monteCarlo(double a1, double a2, double beta, int n) {
  const CounterRng rng(11, 0);
  const double c1 = std::cos(a1), c2 = std::cos(a2), sb = std::sin(beta), cb = std::cos(beta);
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    const auto u = rng.uniform4(i, 0);
    const double z = 1.0 - 2.0 * u[0], r = std::sqrt(1.0 - z * z), phi = 2 * kPi * u[1];
    const double x = r * std::cos(phi);
    if (z >= c1 && x * sb + z * cb >= c2) ++hits;
  }
  return 4 * kPi * hits / n;
}

TEST(CapIntersection, MatchesMonteCarloInEveryCase) {
  struct Case {
    double a1, a2, beta;
  };
  const Case cases[] = {
      {0.3, 0.4, 1.0},                    // disjoint
      {0.3, 1.0, 0.5},                    // nested
      {0.6, 0.5, 0.7},                    // partial, small caps
      {1.4, 0.8, 1.2},                    // partial, near hemisphere
      {2.0, 1.8, 1.5},                    // partial, caps beyond a hemisphere
      {2.5, 2.2, 2.9},                    // union is the whole sphere
      {1.5707963, 1.5707963, 1.5707963},  // two hemispheres at right angles: a lune of pi
  };
  constexpr int kN = 2000000;
  for (const Case& c : cases) {
    const double exact = capIntersectionSolidAngle(c.a1, c.a2, c.beta);
    const double mc = monteCarlo(c.a1, c.a2, c.beta, kN);
    const double se = 4 * kPi * std::sqrt(std::max(mc / (4 * kPi), 1e-6) / kN);
    EXPECT_NEAR(exact, mc, 5 * se + 1e-9) << c.a1 << " " << c.a2 << " " << c.beta;
    EXPECT_NEAR(exact, capIntersectionSolidAngle(c.a2, c.a1, c.beta), 1e-12);  // symmetric
  }
  EXPECT_NEAR(capIntersectionSolidAngle(kPi / 2, kPi / 2, kPi / 2), kPi, 1e-12);
}

TEST(CapIntersection, ConeOcclusionLimits) {
  EXPECT_DOUBLE_EQ(coneSpecularOcclusion(1.0, 0.0, 0.5), 1.0);    // mirror inside
  EXPECT_DOUBLE_EQ(coneSpecularOcclusion(1.0, 0.0, 1.5), 0.0);    // mirror outside
  EXPECT_NEAR(coneSpecularOcclusion(1.0, 0.2, 0.3), 1.0, 1e-12);  // lobe cone inside
  EXPECT_NEAR(coneSpecularOcclusion(1e-3, 0.5, 0.0), capSolidAngle(1e-3) / capSolidAngle(0.5),
              1e-15);
  // cos(alpha_s) = u^(w^2/2): u = 0.01, w = 1 gives cos = 0.1.
  EXPECT_NEAR(std::cos(specularConeAperture(0.01, 1.0)), 0.1, 1e-12);
}

}  // namespace
}  // namespace gtbake::gtso
