// Tables: axis maps, bake determinism, the runtime lookup against direct integration, S4 = S3 at
// beta = theta_o through the lookups, texel formats, the cone-aperture fit and the command.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/rng.h"
#include "common/threads.h"
#include "gtso/cone_fit.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"
#include "runtime/gtso_runtime.h"

namespace gtbake::gtso {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;

// Forward then inverse map of every axis gives the physical value back (double).
TEST(GtsoTables, AxisMapsRoundTrip) {
  const CounterRng rng(3, 0);
  for (int k = 0; k < 2000; ++k) {
    const auto u = rng.uniform4(k, 0);
    const double s = kHalfPi * u[0], av = kHalfPi * u[1], rp = u[2], tS = 15.0 / 31.0;
    const double sigma = gtsoSigma(rp);
    EXPECT_NEAR(gtsoStepUnwarp(gtsoStepWarp(av, s, sigma, tS), s, sigma, tS), av, 1e-9);
    EXPECT_NEAR(gtsoThetaUnwarp(gtsoThetaWarp(s, rp), rp), s, 1e-9);
    EXPECT_NEAR(gtsoRoughUnwarp(gtsoRoughWarp(rp)), rp, 1e-12);
    const double beta = (s + kHalfPi) * u[3], tB = 10.0 / 31.0;
    EXPECT_NEAR(gtsoBetaUnwarp(gtsoBetaWarp(beta, s, rp, tB), s, rp, tB), beta, 1e-9);
    // The A range lies inside the axis for every step: t = 0 and t = 1 are at or beyond A = 0
    // and A = 1 (beyond: the continuation texels), and the step is on texel tS.
    EXPECT_LE(gtsoStepUnwarp(0.0, s, sigma, tS), 0.0);
    EXPECT_GE(gtsoStepUnwarp(1.0, s, sigma, tS), kHalfPi);
    EXPECT_EQ(gtsoStepWarp(s, s, sigma, tS), tS);
    // Both ends of theta_o and beta are end or split texels.
    EXPECT_EQ(gtsoThetaWarp(0.0, rp), 0.0);
    EXPECT_NEAR(gtsoThetaWarp(kHalfPi, rp), 1.0, 1e-15);
    EXPECT_NEAR(gtsoBetaWarp(s, s, rp, tB), tB, 1e-15);
  }
  // No side of the step collapses where it meets an end of the A range: the span floor keeps
  // the first texel above the step at least ~c away in asinh units even at s = pi/2.
  // At a fixed t the distance from the step changes by < 1% between s = pi/2 and s = pi/2 - 0.01
  // (and between s = 0 and s = 0.01); without the floor it fell to 0 at the end.
  const double sigma = gtsoSigma(0.1), tS = 15.0 / 31.0, t1 = tS + 4.0 / 31.0;
  const double atEnd = gtsoStepUnwarp(t1, kHalfPi, sigma, tS) - kHalfPi;
  const double nearEnd = gtsoStepUnwarp(t1, kHalfPi - 0.01, sigma, tS) - (kHalfPi - 0.01);
  EXPECT_NEAR(atEnd / nearEnd, 1.0, 0.01);
  const double t0 = tS - 4.0 / 31.0;
  EXPECT_NEAR(gtsoStepUnwarp(t0, 0.0, sigma, tS) / (gtsoStepUnwarp(t0, 0.01, sigma, tS) - 0.01),
              1.0, 0.01);
}

// Texels beyond the A range hold the continuation of S in alpha_v: an empty cone below A = 0
// (S = 0) and, in 3D (b = n), a cap wider than the hemisphere above A = 1 (S = 1).
double along(const GtsoPoint& p, TableAxis axis) {
  switch (axis) {
    case TableAxis::kA:
      return p.A;
    case TableAxis::kThetaO:
      return p.theta_o;
    case TableAxis::kBeta:
      return p.beta;
    case TableAxis::kRoughness:
      return p.r_p;
  }
  return 0.0;
}

// Each axis's name is a physical parameter that grows along it, texel after texel (the axes are
// warped: A's step warp and theta_o's map depend on the other coordinates too, docs/gtso.md §1).
TEST(GtsoTables, AxisNamesGrowAlongTheirAxes) {
  for (int dims : {3, 4}) {
    Table t;
    t.dims = dims;
    t.size = 8;
    for (int axis = 0; axis < dims; ++axis) {
      const TableAxis named = tableAxis(dims, axis);
      std::array<int, 4> i = {3, 3, 3, 3};
      double last = -1.0;
      for (int k = 1; k + 1 < t.size; ++k) {  // the continuation texels at the ends repeat
        i[axis] = k;
        const double value = along(t.point(i), named);
        EXPECT_GT(value, last) << dims << "D " << axisName(named) << " at texel " << k;
        last = value;
      }
    }
  }
  EXPECT_STREQ(axisName(tableAxis(4, 1)), "beta");
  EXPECT_STREQ(axisName(tableAxis(4, 3)), "theta_o");
  EXPECT_STREQ(axisName(tableAxis(3, 1)), "theta_o");
  EXPECT_STREQ(axisName(tableAxis(3, 2)), "r_p");
  EXPECT_THROW(tableAxis(3, 3), Error);
}

TEST(GtsoTables, ContinuationTexelsHoldTheLimits) {
  const Table t = bakeTable(3, 8, 8, nullptr);
  const int n[4] = {8, 8, 8, 1};
  int below = 0, above = 0;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const int i[4] = {x, y, z, 0};
        const GtsoPhysical<double> p = gtsoTexelPhysical<double>(3, i, n);
        const double v = t.values[t.index({x, y, z, 0})];
        if (p.alphaV <= 0.0) {
          ++below;
          EXPECT_EQ(v, 0.0) << x << " " << y << " " << z;
        }
        if (p.alphaV >= kHalfPi) {
          ++above;
          EXPECT_NEAR(v, 1.0, 1e-12) << x << " " << y << " " << z;
        }
      }
  EXPECT_GE(below, 64);  // at least t = 0 on every (theta_o, r_p) line
  EXPECT_GE(above, 64);
}

TEST(GtsoTables, SizeMustBeAMultipleOfFour) {
  EXPECT_THROW(validateTableSize(6), Error);
  EXPECT_THROW(validateTableSize(0), Error);
  EXPECT_THROW(validateTableSize(260), Error);
  EXPECT_NO_THROW(validateTableSize(32));
}

// Texels whose physical point repeats a neighbour's (the continuation texels beyond A = 0 and
// A = 1, where A is clamped; theta_o = 0: no beta below theta_o) are not where the lookup reads.
bool duplicated(const Table& t, const std::array<int, 4>& i) {
  const int n[4] = {t.size, t.size, t.size, t.dims == 4 ? t.size : 1};
  const double alphaV = gtsoTexelPhysical<double>(t.dims, i.data(), n).alphaV;
  if (alphaV < 0.0 || alphaV > kHalfPi) return true;
  const GtsoPoint p = t.point(i);
  for (int axis = 0; axis < 2; ++axis)
    for (int step : {-1, 1}) {
      std::array<int, 4> j = i;
      j[axis] += step;
      if (j[axis] < 0 || j[axis] >= t.size) continue;
      const GtsoPoint q = t.point(j);
      if (std::abs(p.A - q.A) < 1e-12 && std::abs(p.beta - q.beta) < 1e-12) return true;
    }
  return false;
}

TEST(GtsoTables, BakeIsDeterministicAndLookupHitsTexelCentres) {
  Table one, two;
  {
    const ThreadLimit limit(1);
    one = bakeTable(4, 8, 8, nullptr);
  }
  {
    const ThreadLimit limit(2);
    two = bakeTable(4, 8, 8, nullptr);
  }
  EXPECT_EQ(one.values, two.values);
  const EncodedTable f = floatTable(one);
  int checked = 0;
  for (int i = 1; i < 7; i += 2)
    for (int j = 1; j < 7; j += 2)
      for (int k = 1; k < 8; k += 3)
        for (int l = 1; l < 8; l += 3) {
          const std::array<int, 4> idx = {i, j, k, l};
          if (duplicated(one, idx)) continue;
          ++checked;
          EXPECT_NEAR(runtimeLookup(one, f, one.point(idx)), one.values[one.index(idx)], 2e-3)
              << i << " " << j << " " << k << " " << l;
        }
  EXPECT_GT(checked, 3 * 3 * 3 * 3 / 2);
}

// S4 at beta = theta_o reads texels baked with b = n, with the weights of the 3D lookup.
TEST(GtsoTables, FourDAtBetaEqualThetaIsThreeDThroughTheLookups) {
  const Table s3 = bakeTable(3, 8, 12, nullptr), s4 = bakeTable(4, 8, 12, nullptr);
  const EncodedTable f3 = floatTable(s3);
  const EncodedTable f4 = floatTable(s4);
  const CounterRng rng(4, 0);
  for (int k = 0; k < 500; ++k) {
    const auto u = rng.uniform4(k, 0);
    const double theta_o = std::acos(static_cast<double>(u[1]));
    const GtsoPoint p{u[0], theta_o, u[2], theta_o};
    EXPECT_NEAR(runtimeLookup(s4, f4, p), runtimeLookup(s3, f3, p), 1e-5) << k;
  }
}

// The shipped layout (32 per axis) through the runtime lookup against direct integration at the
// same lobe discretisation (coarse here to keep the test fast), on fresh points: 3D uniform and
// stress, 4D stress (the corners where the step meets an end of the A range and grazing views
// with b near wr, which the span floor and the lobe-scaled theta_o / beta axes fixed).
TEST(GtsoTables, ShippedLayoutLookupMatchesDirectIntegration) {
  constexpr int kCells = 24;
  const Table s3 = bakeTable(3, 32, kCells, nullptr);
  const EncodedTable f3 = floatTable(s3);
  const ErrorPoints pts = makeErrorPoints(3, PointSet::kUniform, 64, 16, 9, kCells);
  const ErrorStats e = lookupError(s3, f3, pts);
  const ErrorStats st =
      lookupError(s3, f3, makeErrorPoints(3, PointSet::kStress, 64, 16, 9, kCells));
  const Table s4 = bakeTable(4, 32, kCells, nullptr);
  const ErrorStats st4 =
      lookupError(s4, floatTable(s4), makeErrorPoints(4, PointSet::kStress, 64, 16, 9, kCells));
  std::printf("[ info ] 3D uniform max %.4f rms %.5f, stress max %.4f; 4D stress max %.4f\n", e.max,
              e.rms, st.max, st4.max);
  EXPECT_LT(e.max, 0.01);
  EXPECT_LT(e.rms, 0.001);
  EXPECT_LT(st.max, 0.015);
  EXPECT_LT(st4.max, 0.05);
  for (std::size_t i = 0; i < 16; ++i) {  // the exact values are evaluateS
    EXPECT_NEAR(pts.exact[i], evaluateS(3, pts.points[i], kCells), 1e-12);
  }
}

// The paired sets integrate each lobe once for both tables: the 4D set is the 4D stream's own,
// the 3D points sit on the same lobes, and every exact value is evaluateS at its point.
TEST(GtsoTables, PairedErrorPointsShareLobesAndStayExact) {
  constexpr int kCells = 12, kLobes = 8, kPerLobe = 8;
  for (PointSet set : {PointSet::kUniform, PointSet::kStress}) {
    const ErrorPointPair pair = makeErrorPointPair(set, kLobes, kPerLobe, 5, kCells);
    const ErrorPoints four = makeErrorPoints(4, set, kLobes, kPerLobe, 5, kCells);
    EXPECT_EQ(pair.four.exact, four.exact);
    ASSERT_EQ(pair.three.points.size(), four.points.size());
    for (std::size_t i = 0; i < pair.three.points.size(); ++i) {
      const GtsoPoint& p = pair.three.points[i];
      EXPECT_EQ(p.r_p, four.points[i].r_p);
      EXPECT_EQ(p.theta_o, four.points[i].theta_o);
      EXPECT_EQ(p.beta, p.theta_o);
      EXPECT_NEAR(pair.three.exact[i], evaluateS(3, p, kCells), 1e-12) << i;
      EXPECT_NEAR(pair.four.exact[i], evaluateS(4, pair.four.points[i], kCells), 1e-12) << i;
    }
  }
}

// The fit must recover u from samples generated with the cone model itself.
TEST(ConeFit, RecoversPlantedU) {
  for (auto [convention, planted] : {std::pair{RoughnessConvention::kAlpha, 0.05},
                                     std::pair{RoughnessConvention::kPerceptual, 0.2}}) {
    S3Samples s;
    const CounterRng rng(8, 0);
    for (int k = 0; k < 3000; ++k) {
      const auto u = rng.uniform4(k, 0);
      const double theta = std::acos(static_cast<double>(u[1]));
      s.points.push_back({u[0], theta, 0.05 + 0.95 * u[2], theta});
      s.values.push_back(coneModel(s.points.back(), planted, convention));
    }
    const ConeFit fit = fitConeU(s, convention);
    EXPECT_NEAR(fit.u, planted, 1e-6);
    EXPECT_LT(fit.errors.max_abs, 1e-6);
  }
}

}  // namespace
}  // namespace gtbake::gtso

namespace gtbake {
namespace {

// End to end at a tiny size: the files have the documented sizes and gtso.json the end-to-end
// block for every format; bad options are rejected before anything is written.
TEST(GtsoCommand, WritesTablesAndReport) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("gtbake_test_gtso_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  GtsoOptions bad;
  bad.out = dir;
  bad.size = 6;  // not a multiple of 4
  EXPECT_THROW(runGtso(bad), Error);
  EXPECT_FALSE(std::filesystem::exists(dir));

  GtsoOptions o;
  o.out = dir;
  o.size = 8;
  o.lobe_cells = 8;
  o.error_lobes = 16;
  o.error_seeds = 2;
  o.progress = false;
  o.closed_form_lobes = 64;  // the fit's plumbing, not its accuracy (s3_closed_form_test.cpp)
  const GtsoResult r = runGtso(o);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso3d.f32"), 4u * 8 * 8 * 8);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso4d.f32"), 4u * 8 * 8 * 8 * 8);
  const auto json = nlohmann::json::parse(readFile(dir / "gtso.json"));
  EXPECT_EQ(json["tables"]["4d"]["axes"].size(), 4u);
  EXPECT_EQ(json["tables"]["3d"]["lobe_grid_rectangles"], 128);
  EXPECT_DOUBLE_EQ(json["cone"]["u"].get<double>(), r.u);
  const auto& e2e = json["end_to_end"];
  EXPECT_EQ(e2e["points"]["uniform"], 16 * 16);
  // gtso measures only its float32 tables (the encoded formats are encode's, in their layouts).
  for (const char* key : {"3d", "4d"}) {
    const auto& formats = e2e[key]["formats"];
    EXPECT_EQ(formats.size(), 1u) << key;
    const auto& f = formats["float32"];
    EXPECT_EQ(f["bytes"].get<std::size_t>(), std::string(key) == "3d" ? 4u * 512 : 4u * 4096);
    EXPECT_EQ(f["uniform"]["per_seed"].size(), 2u);
    const double m0 = f["uniform"]["per_seed"][0]["max"], m1 = f["uniform"]["per_seed"][1]["max"];
    EXPECT_DOUBLE_EQ(f["uniform"]["max"].get<double>(), std::max(m0, m1));
    EXPECT_LE(f["uniform"]["rms"].get<double>(), f["uniform"]["max"].get<double>());
    EXPECT_FALSE(e2e[key].contains("recommended")) << key;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gtbake
