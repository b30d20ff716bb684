// Consumes a generated gtbake_tables.h exactly as an engine would: the build runs
// export_fixture_gen on the synthetic fixture and this file #includes the result, alone (no other
// gtbake header besides the fixture's value function). Decoded tables must match the float
// tables within the BC4 error the header reports; lookups must land on texel centres; the cone
// model's cap intersection must match Monte Carlo; the R16/R8/float variants read the same layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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

// The volumes as stored: texture order of the header's layouts (kGtso3DLayout, kGtso4DLayout).
const gtbake::GtsoVolume kVolume3D{gtbake::GtsoTexelFormat::kBc4, gtbake::kGtso3DBC4,
                                   gtbake::kGtso3DVolumeSize[0], gtbake::kGtso3DVolumeSize[1],
                                   gtbake::kGtso3DVolumeSize[2]};
const gtbake::GtsoVolume kVolume4D{gtbake::GtsoTexelFormat::kBc4, gtbake::kGtso4DBC4,
                                   gtbake::kGtso4DVolumeSize[0], gtbake::kGtso4DVolumeSize[1],
                                   gtbake::kGtso4DVolumeSize[2]};
// The fixture is exported in non-identity layouts (export_fixture.h), so every check below
// reads permuted volumes.
static_assert(gtbake::kGtso3DLayout.axis[0] == 1 && gtbake::kGtso3DLayout.axis[1] == 0,
              "3D fixture layout: x = theta_o, y = A");
static_assert(gtbake::kGtso4DLayout.axis[0] == 1 && gtbake::kGtso4DLayout.axis[2] == 0,
              "4D fixture layout: x = beta, z = A");
// ... and its 4D volume is a 2 x 2 atlas of 8x4x8 tiles (export_fixture.h), one tile empty.
static_assert(gtbake::kGtso4DLayout.tilesX == 2 && gtbake::kGtso4DVolumeSize[0] == 16 &&
                  gtbake::kGtso4DVolumeSize[1] == 4 && gtbake::kGtso4DVolumeSize[2] == 16,
              "4D fixture: atlas 2 x 2 tiles");

// Texture position (x, y, z) of table texel i = (A, theta_o | beta, r_p[, theta_o]).
struct Texel {
  int x, y, z;
};
Texel texel3D(const int* i) {
  const auto& l = gtbake::kGtso3DLayout;
  return {i[l.axis[0]], i[l.axis[1]], i[l.axis[2]]};
}
// 4D: the tile of theta_o slice i[3] (tilesX across x, docs/export.md §2c).
Texel texel4D(const int* i) {
  const auto& l = gtbake::kGtso4DLayout;
  const int* n = gtbake::kGtso4DSize;
  return {i[l.axis[0]] + n[l.axis[0]] * (i[3] % l.tilesX), i[l.axis[1]],
          i[l.axis[2]] + n[l.axis[2]] * (i[3] / l.tilesX)};
}
float decoded3D(const int* i) {
  const Texel t = texel3D(i);
  return gtbake::gtsoFetchTexel(kVolume3D, t.x, t.y, t.z);
}
float decoded4D(const int* i) {
  const Texel t = texel4D(i);
  return gtbake::gtsoFetchTexel(kVolume4D, t.x, t.y, t.z);
}
// A table in table order (x fastest; 4D folded) rewritten in texture order.
template <class T>
std::vector<T> toTexture(const std::vector<T>& table, int dims) {
  const int* n = dims == 3 ? gtbake::kGtso3DSize : gtbake::kGtso4DSize;
  const int* v = dims == 3 ? gtbake::kGtso3DVolumeSize : gtbake::kGtso4DVolumeSize;
  std::vector<T> out(static_cast<std::size_t>(v[0]) * v[1] * v[2]);  // 4D: tiles past w are 0
  std::size_t at = 0;
  for (int w = 0; w < (dims == 4 ? n[3] : 1); ++w)
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          const int i[4] = {x, y, z, w};
          const Texel t = dims == 3 ? texel3D(i) : texel4D(i);
          out[(static_cast<std::size_t>(t.z) * v[1] + t.y) * v[0] + t.x] = table[at++];
        }
  return out;
}
// Texel centres are read back through the physical-input lookups up to the float rounding of
// the inputs: near the mirror step the A axis is scaled by sigma = rp^2 + 1e-5 rad, where
// one float ulp of A moves the coordinate by up to ~1% of a texel of the smooth fixture.
constexpr float kCentreTolerance = 2e-3f;

TEST(GeneratedHeader, DecodedTablesWithinReportedBc4Error) {
  const std::vector<float> t3 = gtbake::test::fixtureTable3D();
  const std::vector<float> t4 = gtbake::test::fixtureTable4D();
  const int* n3 = gtbake::kGtso3DSize;
  const int* n4 = gtbake::kGtso4DSize;
  float worst3 = 0.0f, worst4 = 0.0f;
  std::size_t at = 0;
  for (int z = 0; z < n3[2]; ++z)
    for (int y = 0; y < n3[1]; ++y)
      for (int x = 0; x < n3[0]; ++x) {
        const int i[3] = {x, y, z};
        worst3 = std::max(worst3, std::fabs(decoded3D(i) - t3[at++]));
      }
  at = 0;
  for (int w = 0; w < n4[3]; ++w)
    for (int z = 0; z < n4[2]; ++z)
      for (int y = 0; y < n4[1]; ++y)
        for (int x = 0; x < n4[0]; ++x) {
          const int i[4] = {x, y, z, w};
          worst4 = std::max(worst4, std::fabs(decoded4D(i) - t4[at++]));
        }
  EXPECT_LE(worst3, gtbake::kGtso3DBC4MaxAbsError * (1.0f + 1e-6f));
  EXPECT_LE(worst4, gtbake::kGtso4DBC4MaxAbsError * (1.0f + 1e-6f));
  EXPECT_GT(worst3, 0.5f * gtbake::kGtso3DBC4MaxAbsError);  // the reported figure is not loose
  EXPECT_LT(gtbake::kGtso4DBC4MaxAbsError, 0.05f);          // coarse 8-texel fixture
}

// Texels the physical-input lookup does not read at their own point: the continuation texels
// beyond A = 0 and A = 1 (alpha_v outside [0, pi/2], their A clamped), and, where an axis segment
// is empty (4D theta_o = 0: no beta below theta_o), texels sharing a neighbour's point along x
// or y.
template <int Dims>
bool duplicated(const int* i, const int* n) {
  const auto p = gtbake::gtsoTexelPhysical<double>(Dims, i, n);
  if (p.alphaV < 0.0 || p.alphaV > gtbake::kGtsoPi / 2) return true;
  for (int axis = 0; axis < 2; ++axis)
    for (int step : {-1, 1}) {
      int j[4] = {i[0], i[1], i[2], Dims == 4 ? i[3] : 0};
      j[axis] += step;
      if (j[axis] < 0 || j[axis] >= n[axis]) continue;
      const auto q = gtbake::gtsoTexelPhysical<double>(Dims, j, n);
      if (std::abs(p.A - q.A) < 1e-12 && std::abs(p.beta - q.beta) < 1e-12) return true;
    }
  return false;
}

// The physical parameters of every texel (the bake's inverse axis maps) look up that texel.
TEST(GeneratedHeader, Lookup3DAtTexelCentresReturnsTexels) {
  const int* n = gtbake::kGtso3DSize;
  int checked = 0;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        const int i[3] = {x, y, z};
        if (duplicated<3>(i, n)) continue;
        ++checked;
        const auto p = gtbake::gtsoTexelPhysical<double>(3, i, n);
        const float got =
            gtbake::gtso3DLookup(static_cast<float>(p.A), static_cast<float>(std::cos(p.beta)),
                                 static_cast<float>(p.rp));
        ASSERT_NEAR(got, decoded3D(i), kCentreTolerance) << x << " " << y << " " << z;
      }
  EXPECT_GT(checked, n[0] * n[1] * n[2] * 3 / 5);  // the rest: continuation texels
}

// The 4D atlas: table texel (A, beta, r_p, theta_o) sits in the tile of its theta_o slice.
TEST(GeneratedHeader, Lookup4DAtTexelCentresReadsTheTiledVolume) {
  const int* n = gtbake::kGtso4DSize;
  int checked = 0;
  for (int w = 0; w < n[3]; ++w)
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          const int i[4] = {x, y, z, w};
          if (duplicated<4>(i, n)) continue;
          ++checked;
          const auto p = gtbake::gtsoTexelPhysical<double>(4, i, n);
          const float got = gtbake::gtso4DLookup(
              static_cast<float>(p.A), static_cast<float>(std::cos(p.beta)),
              static_cast<float>(p.rp), static_cast<float>(std::cos(p.thetaO)));
          ASSERT_NEAR(got, decoded4D(i), kCentreTolerance) << x << " " << y << " " << z << " " << w;
        }
  EXPECT_GT(checked, n[0] * n[1] * n[2] * n[3] / 3);  // beta > pi/2 rows: continuation texels
}

// The per-format variants read the same layout: R16 / R8 texels of the float fixture (in the
// header's layouts) give the float lookup (table order) within their quantisation step.
TEST(GeneratedHeader, PerFormatVariantsAgreeWithFloat) {
  const std::vector<float> t3 = gtbake::test::fixtureTable3D();
  const std::vector<float> t4 = gtbake::test::fixtureTable4D();
  auto quantize = [](const std::vector<float>& v, double scale, auto type) {
    std::vector<decltype(type)> q;
    for (float f : v) q.push_back(static_cast<decltype(type)>(std::lround(f * scale)));
    return q;
  };
  // R16 / R8 volumes are stored in the layouts like BC4; float32 (gtso's .f32) in table order.
  const auto r16_3 = toTexture(quantize(t3, 65535.0, std::uint16_t{}), 3),
             r16_4 = toTexture(quantize(t4, 65535.0, std::uint16_t{}), 4);
  const auto r8_3 = toTexture(quantize(t3, 255.0, std::uint8_t{}), 3),
             r8_4 = toTexture(quantize(t4, 255.0, std::uint8_t{}), 4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  for (int k = 0; k < 2000; ++k) {
    const float A = u01(rng), cb = u11(rng), rp = u01(rng), co = u01(rng);
    const float f3 = gtbake::gtso3DLookupFloat(t3.data(), A, cb, rp);
    const float f4 = gtbake::gtso4DLookupFloat(t4.data(), A, cb, rp, co);
    EXPECT_NEAR(gtbake::gtso3DLookupR16(r16_3.data(), A, cb, rp), f3, 0.5f / 65535.0f + 1e-6f);
    EXPECT_NEAR(gtbake::gtso4DLookupR16(r16_4.data(), A, cb, rp, co), f4, 0.5f / 65535.0f + 1e-6f);
    EXPECT_NEAR(gtbake::gtso3DLookupR8(r8_3.data(), A, cb, rp), f3, 0.5f / 255.0f + 1e-6f);
    EXPECT_NEAR(gtbake::gtso4DLookupR8(r8_4.data(), A, cb, rp, co), f4, 0.5f / 255.0f + 1e-6f);
    EXPECT_NEAR(gtbake::gtso3DLookup(A, cb, rp), f3, gtbake::kGtso3DBC4MaxAbsError + 1e-6f);
    EXPECT_NEAR(gtbake::gtso4DLookup(A, cb, rp, co), f4, gtbake::kGtso4DBC4MaxAbsError + 1e-6f);
  }
}

TEST(GeneratedHeader, MultiBounceIsEquation10) {
  const double* k = gtbake::test::kFixtureCoeffs;
  for (double rho = 0.1; rho < 0.95; rho += 0.2)
    for (double A = 0.0; A <= 1.0; A += 0.125) {
      const double a = k[0] * rho + k[1], b = k[2] * rho + k[3], c = k[4] * rho + k[5];
      const double g = a * A * A * A - b * A * A + c * A;
      EXPECT_NEAR(gtbake::multiBounce(float(A), float(rho)), g, 2e-6) << A << " " << rho;
    }
}

// The engine profiles: names in order, each one's Equation 10 with its own coefficients, and the
// RMSEs it was shipped with.
TEST(GeneratedHeader, ProfilesAreEquation10WithTheirOwnConstants) {
  ASSERT_EQ(gtbake::kMultiBounceProfileCount, 2);
  for (int p = 0; p < 2; ++p) {
    const gtbake::GtbakeMultiBounceProfile& profile = gtbake::kMultiBounceProfiles[p];
    EXPECT_STREQ(profile.estimator, gtbake::test::kFixtureProfiles[p]);
    EXPECT_FLOAT_EQ(profile.rmsePaper, float(gtbake::test::kFixtureProfilePaperRmse));
    EXPECT_FLOAT_EQ(profile.rmseHeldOut, float(gtbake::test::kFixtureProfileHeldOutRmse));
    const std::array<double, 6> k = gtbake::test::fixtureProfileCoeffs(p);
    for (double rho = 0.1; rho < 0.95; rho += 0.2)
      for (double A = 0.0; A <= 1.0; A += 0.125) {
        const double a = k[0] * rho + k[1], b = k[2] * rho + k[3], c = k[4] * rho + k[5];
        const double g = a * A * A * A - b * A * A + c * A;
        EXPECT_NEAR(gtbake::multiBounce(profile, float(A), float(rho)), g, 2e-6) << p << " " << A;
      }
  }
}

// The paper's constants under their own name (Jimenez et al. 2016, Eq. 10, as printed there).
TEST(GeneratedHeader, PaperConstantsKeepTheirOwnName) {
  const double k[6] = {2.0404, -0.3324, 4.7951, -0.6417, 2.7552, 0.6903};
  for (double rho = 0.1; rho < 0.95; rho += 0.2)
    for (double A = 0.0; A <= 1.0; A += 0.125) {
      const double a = k[0] * rho + k[1], b = k[2] * rho + k[3], c = k[4] * rho + k[5];
      EXPECT_NEAR(gtbake::multiBouncePaper(float(A), float(rho)), a * A * A * A - b * A * A + c * A,
                  2e-6);
    }
}

// The profile tables, one per fixture profile in name order: each lookup is linear in A between
// nodes and in the albedo between rows, clamped to the rows (fixtureTableLookup).
TEST(GeneratedHeader, ProfileTableIsBilinearInAAndAlbedo) {
  ASSERT_EQ(gtbake::kMultiBounceTableCount, 2);
  for (int k = 0; k < 2; ++k) {
    const gtbake::GtbakeMultiBounceTable& t = gtbake::kMultiBounceTables[k];
    EXPECT_STREQ(t.estimator, gtbake::test::kFixtureProfiles[k]);
    EXPECT_FLOAT_EQ(t.rmseHeldOut, float(gtbake::test::kFixtureTableHeldOutRmse[k]));
    for (double albedo : {0.0, 0.2, 0.35, 0.5, 0.8, 1.0})
      for (double A : {-0.5, 0.0, 0.1, 1.0 / 3.0, 0.5, 0.9, 1.0, 1.5}) {
        EXPECT_NEAR(gtbake::multiBounce(t, float(A), float(albedo)),
                    gtbake::test::fixtureTableLookup(k, A, albedo), 1e-6)
            << k << " " << albedo << " " << A;
      }
    EXPECT_FLOAT_EQ(gtbake::multiBounce(t, 1.0f, 0.5f), 1.0f);  // an open surface
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
    EXPECT_NEAR(gtbake::gtsoCapIntersection(float(c[0]), float(c[1]), float(c[2])), 4.0 * kPi * p,
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
