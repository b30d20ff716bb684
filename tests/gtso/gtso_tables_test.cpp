// Tables: axis maps, bake determinism, the runtime lookup against direct integration, S4 = S3 at
// beta = theta_o through the lookups, texel formats, the cone-aperture fit and the command.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/rng.h"
#include "common/threads.h"
#include "export/runtime/gtso_lookup.h"
#include "gtso/cone_fit.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"

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
    EXPECT_NEAR(gtsoThetaUnwarp(gtsoThetaWarp(s)), s, 1e-9);
    EXPECT_NEAR(gtsoRoughUnwarp(gtsoRoughWarp(rp)), rp, 1e-12);
    const double beta = (s + kHalfPi) * u[3], tB = 10.0 / 31.0;
    EXPECT_NEAR(gtsoBetaUnwarp(gtsoBetaWarp(beta, s, tB), s, tB), beta, 1e-9);
  }
  // End texels: A = 0 and A = 1, and the mirror step on texel tS.
  EXPECT_EQ(gtsoStepWarp(0.0, 0.7, 0.01, 15.0 / 31.0), 0.0);
  EXPECT_EQ(gtsoStepWarp(kHalfPi, 0.7, 0.01, 15.0 / 31.0), 1.0);
  EXPECT_EQ(gtsoStepWarp(0.7, 0.7, 0.01, 15.0 / 31.0), 15.0 / 31.0);
}

TEST(GtsoTables, SizeMustBeAMultipleOfFour) {
  EXPECT_THROW(validateTableSize(6), Error);
  EXPECT_THROW(validateTableSize(0), Error);
  EXPECT_THROW(validateTableSize(260), Error);
  EXPECT_NO_THROW(validateTableSize(32));
}

// Texels of an empty axis segment (beta > pi/2: alpha_v clamped to pi/2 above A = 1; theta_o = 0:
// no beta below theta_o) repeat a neighbour's physical point and are not where the lookup reads.
bool duplicated(const Table& t, const std::array<int, 4>& i) {
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
  const EncodedTable f = encodeTable(one, TexelFormat::kFloat32);
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
  const EncodedTable f3 = encodeTable(s3, TexelFormat::kFloat32);
  const EncodedTable f4 = encodeTable(s4, TexelFormat::kFloat32);
  const CounterRng rng(4, 0);
  for (int k = 0; k < 500; ++k) {
    const auto u = rng.uniform4(k, 0);
    const double thetaO = std::acos(static_cast<double>(u[1]));
    const GtsoPoint p{u[0], thetaO, u[2], thetaO};
    EXPECT_NEAR(runtimeLookup(s4, f4, p), runtimeLookup(s3, f3, p), 1e-5) << k;
  }
}

// The shipped layout (32 per axis) through the runtime lookup against direct integration at the
// same lobe discretisation (coarse here to keep the test fast): the float-table bars.
TEST(GtsoTables, ShippedLayoutLookupMatchesDirectIntegration) {
  constexpr int kCells = 24;
  const Table s3 = bakeTable(3, 32, kCells, nullptr);
  const ErrorPoints pts = makeErrorPoints(3, PointSet::kUniform, 64, 16, 9, kCells);
  const ErrorStats e = lookupError(s3, encodeTable(s3, TexelFormat::kFloat32), pts);
  EXPECT_LT(e.max, 0.02);
  EXPECT_LT(e.rms, 0.002);
  for (std::size_t i = 0; i < 16; ++i) {  // the exact values are evaluateS
    EXPECT_NEAR(pts.exact[i], evaluateS(3, pts.points[i], kCells), 1e-12);
  }
}

TEST(GtsoTables, UnormFormatsQuantiseTheTexels) {
  const Table t = bakeTable(3, 8, 8, nullptr);
  const EncodedTable r16 = encodeTable(t, TexelFormat::kR16);
  const EncodedTable r8 = encodeTable(t, TexelFormat::kR8);
  EXPECT_EQ(r16.bytes.size(), 2u * 512);
  EXPECT_EQ(r8.bytes.size(), 512u);
  EXPECT_LE(r16.texel_max, 0.5 / 65535 + 1e-7);
  EXPECT_LE(r8.texel_max, 0.5 / 255 + 1e-7);
  EXPECT_GT(r8.texel_max, 0.25 / 255);  // not exact by accident
  const EncodedTable bc4 = encodeTable(t, TexelFormat::kBc4);
  EXPECT_EQ(bc4.bytes.size(), 256u);  // 8 bytes per 4x4 block: half a byte per texel
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
  const GtsoResult r = runGtso(o);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso3d.f32"), 4u * 8 * 8 * 8);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso4d.f32"), 4u * 8 * 8 * 8 * 8);
  const auto json = nlohmann::json::parse(readFile(dir / "gtso.json"));
  EXPECT_EQ(json["tables"]["4d"]["axes"].size(), 4u);
  EXPECT_EQ(json["tables"]["3d"]["lobe_grid_rectangles"], 128);
  EXPECT_DOUBLE_EQ(json["cone"]["u"].get<double>(), r.u);
  const auto& e2e = json["end_to_end"];
  EXPECT_EQ(e2e["points"]["uniform"], 16 * 16);
  const std::pair<const char*, std::size_t> bytes[] = {
      {"float32", 4 * 512}, {"bc4", 256}, {"r16", 2 * 512}, {"r8", 512}};
  for (const auto& [format, size] : bytes) {
    const auto& f = e2e["3d"]["formats"][format];
    EXPECT_EQ(f["bytes"].get<std::size_t>(), size) << format;
    EXPECT_EQ(f["uniform"]["per_seed"].size(), 2u);
    const double m0 = f["uniform"]["per_seed"][0]["max"], m1 = f["uniform"]["per_seed"][1]["max"];
    EXPECT_DOUBLE_EQ(f["uniform"]["max"].get<double>(), std::max(m0, m1));
    EXPECT_LE(f["uniform"]["rms"].get<double>(), f["uniform"]["max"].get<double>());
    EXPECT_TRUE(e2e["4d"]["formats"].contains(format));
  }
  EXPECT_TRUE(e2e["3d"]["formats"].contains(e2e["3d"]["recommended"].get<std::string>()));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gtbake
