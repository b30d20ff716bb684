// Consumes a generated gtbake_tables.h exactly as an engine would: the build runs
// export_fixture_gen on the synthetic fixture and this file #includes the result, alone (no other
// gtbake header besides the fixture's value function). Decoded tables must match the float
// tables within the BC4 error the header reports; lookups must land on texel centres; the cone
// model's cap intersection must match Monte Carlo.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "export_fixture.h"
#include "gtbake_tables.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// Compile-time checks: the axis maps and the BC4 decode are constexpr.
static_assert(gtbake::gtsoTexelRemap(0.0f, 32) == 0.5f / 32.0f, "half-texel remap at t = 0");
static_assert(gtbake::gtsoTexelRemap(1.0f, 32) == 31.5f / 32.0f, "half-texel remap at t = 1");
// Block: red_0 = 255, red_1 = 0, texel 0 code 1 (→ 0.0), texel 1 code 2 (→ 6/7).
static_assert(gtbake::gtsoBc4DecodeTexel(0x00000000001100FFull, 0) == 0.0f, "code 1");
static_assert(gtbake::gtsoBc4DecodeTexel(0x00000000001100FFull, 1) ==
                  (6.0f * 1.0f + 1.0f * 0.0f) / 7.0f,
              "code 2 in the 8-value mode");
static_assert(sizeof(gtbake::kGtso3DBC4) == 8 * 2 * 2 * 6, "3D fixture: 2x2 blocks x 6 slices");

float decoded3D(int x, int y, int z) {
  return gtbake::gtsoFetchTexel(gtbake::kGtso3DBC4, gtbake::kGtso3DSize, x, y, z);
}
float decoded4D(int x, int y, int z) {
  return gtbake::gtsoFetchTexel(gtbake::kGtso4DBC4, gtbake::kGtso4DVolumeSize, x, y, z);
}

TEST(GeneratedHeader, DecodedTablesWithinReportedBc4Error) {
  const std::vector<float> t3 = gtbake::test::fixtureTable3D();
  const std::vector<float> t4 = gtbake::test::fixtureTable4D();
  const int* s3 = gtbake::kGtso3DSize;
  const int* s4 = gtbake::kGtso4DVolumeSize;
  float worst3 = 0.0f, worst4 = 0.0f;
  for (int z = 0; z < s3[2]; ++z)
    for (int y = 0; y < s3[1]; ++y)
      for (int x = 0; x < s3[0]; ++x)
        worst3 = std::max(worst3, std::fabs(decoded3D(x, y, z) - t3[(z * s3[1] + y) * s3[0] + x]));
  for (int z = 0; z < s4[2]; ++z)
    for (int y = 0; y < s4[1]; ++y)
      for (int x = 0; x < s4[0]; ++x)
        worst4 = std::max(worst4, std::fabs(decoded4D(x, y, z) - t4[(z * s4[1] + y) * s4[0] + x]));
  EXPECT_LE(worst3, gtbake::kGtso3DBC4MaxAbsError * (1.0f + 1e-6f));
  EXPECT_LE(worst4, gtbake::kGtso4DBC4MaxAbsError * (1.0f + 1e-6f));
  EXPECT_GT(worst3, 0.5f * gtbake::kGtso3DBC4MaxAbsError);  // the reported figure is not loose
  EXPECT_LT(gtbake::kGtso4DBC4MaxAbsError, 0.05f);          // coarse 8-texel fixture
}

// Fixture 3D axes: x = cos_alpha_v from 1 to 0, y = beta from 0 to π, z = r_p from 0 to 1.
TEST(GeneratedHeader, Lookup3DAtTexelCentresReturnsTexels) {
  const int* n = gtbake::kGtso3DSize;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        const double q = 1.0 - x / (n[0] - 1.0);
        const float A = static_cast<float>(1.0 - q * q);
        const float cosBeta = static_cast<float>(std::cos(kPi * y / (n[1] - 1.0)));
        const float rp = static_cast<float>(z / (n[2] - 1.0));
        ASSERT_NEAR(gtbake::gtso3DLookup(A, cosBeta, rp), decoded3D(x, y, z), 2e-4)
            << x << " " << y << " " << z;
      }
}

// Fixture 4D axes: x = A, y = cos_beta from −1 to 1, z = alpha = r_p², w = cos_theta_o.
TEST(GeneratedHeader, Lookup4DIsTwoFetchesAndALerp) {
  const int* n = gtbake::kGtso4DSize;
  for (int w2 = 0; w2 <= 2 * (n[3] - 1); ++w2)
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; y += 3)
        for (int x = 0; x < n[0]; x += 3) {
          const float A = static_cast<float>(x / (n[0] - 1.0));
          const float cosBeta = static_cast<float>(-1.0 + 2.0 * y / (n[1] - 1.0));
          const float rp = static_cast<float>(std::sqrt(z / (n[2] - 1.0)));
          const float cosThetaO = static_cast<float>(0.5 * w2 / (n[3] - 1.0));
          const int s0 = w2 / 2, s1 = std::min(s0 + 1, n[3] - 1);
          const float a = decoded4D(x, y, s0 * n[2] + z), b = decoded4D(x, y, s1 * n[2] + z);
          const float expect = w2 % 2 == 0 ? a : 0.5f * (a + b);
          ASSERT_NEAR(gtbake::gtso4DLookup(A, cosBeta, rp, cosThetaO), expect, 2e-4)
              << x << " " << y << " " << z << " " << w2;
        }
}

TEST(GeneratedHeader, MultiBounceIsEquation10) {
  const double* k = gtbake::test::kFixtureCoeffs;
  for (double rho = 0.1; rho < 0.95; rho += 0.2)
    for (double A = 0.0; A <= 1.0; A += 0.125) {
      const double a = k[0] * rho + k[1], b = k[2] * rho + k[3], c = k[4] * rho + k[5];
      const double g = std::max(A, a * A * A * A - b * A * A + c * A);
      EXPECT_NEAR(gtbake::multiBounce(float(A), float(rho)), g, 2e-6) << A << " " << rho;
    }
}

TEST(GeneratedHeader, CapIntersectionMatchesMonteCarlo) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const int n = 400000;
  std::vector<double> px(n), pz(n);
  for (int i = 0; i < n; ++i) {  // uniform directions: z uniform, φ uniform; keep x and z
    const double z = 2.0 * uni(rng) - 1.0, phi = 2.0 * kPi * uni(rng);
    pz[i] = z;
    px[i] = std::sqrt(1.0 - z * z) * std::cos(phi);
  }
  const double cases[][3] = {{0.5, 0.7, 0.9}, {1.2, 0.3, 1.0}, {1.5, 1.4, 2.0},
                             {0.8, 0.8, 0.1}, {1.5, 0.2, 0.1}, {0.4, 0.3, 1.2}};
  for (const auto& c : cases) {
    int hits = 0;
    for (int i = 0; i < n; ++i) {
      hits += pz[i] >= std::cos(c[0]) &&
              px[i] * std::sin(c[2]) + pz[i] * std::cos(c[2]) >= std::cos(c[1]);
    }
    const double p = double(hits) / n;
    const double sigma = 4.0 * kPi * std::sqrt(p * (1.0 - p) / n);
    EXPECT_NEAR(gtbake::coneCapIntersection(float(c[0]), float(c[1]), float(c[2])), 4.0 * kPi * p,
                4.0 * sigma + 1e-5)
        << c[0] << " " << c[1] << " " << c[2];
  }
}

TEST(GeneratedHeader, ConeModelLimits) {
  // A = 1: the visibility cone is the hemisphere around b; a narrow lobe along b is unoccluded.
  EXPECT_NEAR(gtbake::gtsoConeModel(1.0f, 1.0f, 0.5f), 1.0f, 1e-6);
  // Mirror limit r_p = 0: S = 1 inside the visibility cone, 0 outside.
  EXPECT_EQ(gtbake::gtsoConeModel(0.5f, std::cos(0.5f), 0.0f), 1.0f);  // αv = π/4 > 0.5
  EXPECT_EQ(gtbake::gtsoConeModel(0.5f, std::cos(1.0f), 0.0f), 0.0f);
  // Disjoint cones give 0; S stays in [0, 1].
  EXPECT_EQ(gtbake::gtsoConeModel(0.1f, -1.0f, 0.3f), 0.0f);
  for (float rp = 0.05f; rp < 1.0f; rp += 0.1f) {
    const float s = gtbake::gtsoConeModel(0.6f, 0.8f, rp);
    EXPECT_GE(s, 0.0f);
    EXPECT_LE(s, 1.0f + 1e-5f);
  }
}

}  // namespace
