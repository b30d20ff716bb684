// Tables: axis mapping, lookup, determinism, BC4 proxy, and the cone-aperture fit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/threads.h"
#include "gtso/cone_fit.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"

namespace gtbake::gtso {
namespace {

TEST(GtsoTables, AxisQuantitiesRoundTrip) {
  for (const char* q : {"A", "cos_alpha_v", "alpha_v", "cos_beta", "beta", "r_p", "alpha",
                        "cos_theta_o", "theta_o"}) {
    for (double v : {0.0, 0.2, 0.7, 1.0}) {
      EXPECT_NEAR(physicalToAxis(q, axisToPhysical(q, v)), v, 1e-12) << q;
    }
  }
  EXPECT_THROW(axisToPhysical("bogus", 0.5), std::exception);
}

TEST(GtsoTables, LookupAtTexelCentresIsExactAndBakeIsDeterministic) {
  Table one, two;
  {
    const ThreadLimit limit(1);
    one = bakeTable(4, Mapping::defaults(4), 6, 8, nullptr);
  }
  {
    const ThreadLimit limit(2);
    two = bakeTable(4, Mapping::defaults(4), 6, 8, nullptr);
  }
  EXPECT_EQ(one.values, two.values);
  for (int i = 0; i < 6; i += 5)
    for (int j = 0; j < 6; j += 2)
      for (int k = 0; k < 6; k += 3)
        for (int l = 0; l < 6; ++l) {
          const std::array<int, 4> idx = {i, j, k, l};
          EXPECT_NEAR(one.lookup(one.point(idx)), one.values[one.index(idx)], 1e-12);
        }
}

TEST(GtsoTables, Bc4ProxyIsExactOnConstantsAndBounded) {
  std::vector<float> flat(8 * 8 * 8, 0.25f);
  EXPECT_LT(bc4ProxyError(flat, 3, 8).max, 1.0 / 255.0);
  std::vector<float> ramp(8 * 8 * 8);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<float>((i % 64) / 63.0);
  const ErrorStats e = bc4ProxyError(ramp, 3, 8);
  EXPECT_GT(e.max, 0.0);
  EXPECT_LT(e.max, 0.5 / 7.0 + 2.0 / 255.0);  // half a palette step of the widest block
}

// The fit must recover u from a table generated with the cone model itself.
TEST(ConeFit, RecoversPlantedU) {
  for (auto [convention, planted] : {std::pair{RoughnessConvention::kAlpha, 0.05},
                                     std::pair{RoughnessConvention::kPerceptual, 0.2}}) {
    Table t;
    t.dims = 3;
    t.size = 12;
    t.mapping = Mapping::defaults(3);
    t.values.resize(12 * 12 * 12);
    for (int r = 0; r < 12; ++r)
      for (int b = 0; b < 12; ++b)
        for (int a = 0; a < 12; ++a) {
          const std::array<int, 4> i = {a, b, r, 0};
          t.values[t.index(i)] = coneModel(t.point(i), planted, convention);
        }
    const ConeFit fit = fitConeU(t, convention);
    EXPECT_NEAR(fit.u, planted, 1e-6);
    EXPECT_LT(fit.errors.max_abs, 1e-6);
  }
}

}  // namespace
}  // namespace gtbake::gtso

namespace gtbake {
namespace {

// End to end at a tiny size: the files have the documented sizes and gtso.json its keys; bad
// options are rejected before anything is written.
TEST(GtsoCommand, WritesTablesAndReport) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("gtbake_test_gtso_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  GtsoOptions bad;
  bad.out = dir;
  bad.size = 1;
  EXPECT_THROW(runGtso(bad), Error);
  EXPECT_FALSE(std::filesystem::exists(dir));

  GtsoOptions o;
  o.out = dir;
  o.size = 4;
  o.samples = 2 * 8 * 8;
  o.progress = false;
  const GtsoResult r = runGtso(o);
  EXPECT_GT(r.u, 0.0);
  EXPECT_LT(r.u, 1.0);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso3d.f32"), 4u * 4 * 4 * 4);
  EXPECT_EQ(std::filesystem::file_size(dir / "gtso4d.f32"), 4u * 4 * 4 * 4 * 4);
  const auto json = nlohmann::json::parse(readFile(dir / "gtso.json"));
  EXPECT_EQ(json["tables"]["4d"]["axes"].size(), 4u);
  EXPECT_EQ(json["tables"]["3d"]["samples"], 128);
  EXPECT_DOUBLE_EQ(json["cone"]["u"].get<double>(), r.u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gtbake
