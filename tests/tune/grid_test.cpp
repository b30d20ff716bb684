// tune's grids (docs/tune.md §1): settingsAt sets a tuned setting as a number through its
// descriptor's field; checked against the --setting text path (applySetting on "%.17g", which
// round-trips a double), so a field bound to the wrong member or estimator fails here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.h"
#include "screen_ao/screen_ao_settings.h"
#include "tune/tune_grid.h"

namespace gtbake {
namespace {

// Every estimator's settings as JSON, the whole of ScreenAoSettings that a run can see.
nlohmann::ordered_json allSettings(const ScreenAoSettings& s) {
  nlohmann::ordered_json j;
  for (const Estimator e : screenAoEstimators()) j[describe(e).name] = settingsJson(s, e);
  return j;
}

TEST(TuneGrid, SettingsAtSetsTheValueTheSettingTextSets) {
  const std::vector<SettingGrid> grids = defaultGrids(tunedEstimators());
  ASSERT_EQ(grids.size(), 5u);  // radius, intensity, thin_compensation; thickness twice
  for (const SettingGrid& grid : grids) {
    std::vector<double> values = grid.values;
    values.insert(values.end(), {0.1, 1.0 / 3.0, std::nextafter(0.7, 1.0), 2.5e-3});
    for (const double v : values) {
      char text[64];
      std::snprintf(text, sizeof text, "%.17g", v);
      ScreenAoSettings parsed;
      applySetting(&parsed, std::string(grid.name()) + "." + grid.key + "=" + text);
      const ScreenAoSettings set = settingsAt(grid, v);
      EXPECT_EQ(allSettings(set), allSettings(parsed)) << grid.name() << "." << grid.key << v;
      EXPECT_EQ(settingsJson(set, grid.estimator).at(grid.key).get<double>(), v);
    }
    // The default is the settings' own default (read through the JSON, not the field).
    EXPECT_EQ(grid.default_value,
              settingsJson(ScreenAoSettings{}, grid.estimator).at(grid.key).get<double>());
  }
}

TEST(TuneGrid, DefaultGridsFollowTheEstimatorsGivenAndRefuseAnUntunedOne) {
  const std::vector<SettingGrid> grids =
      defaultGrids({Estimator::kBitmaskCosine, Estimator::kGtaoRuntime});
  ASSERT_EQ(grids.size(), 4u);
  EXPECT_EQ(grids[0].estimator, Estimator::kBitmaskCosine);
  EXPECT_EQ(grids[0].key, "thickness");
  EXPECT_EQ(grids[1].estimator, Estimator::kGtaoRuntime);
  EXPECT_EQ(grids[1].key, "radius");
  try {
    defaultGrids({Estimator::kHbao});
    ADD_FAILURE() << "tune accepted hbao";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tune does not search 'hbao'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace gtbake
