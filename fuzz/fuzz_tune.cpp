// Fuzz target: what tune's results and settings are read from. The first byte picks the reader;
// the rest is its input:
//   0 tune.json, sealed into a valid tune set (export --tune: readTunedSettings)
//   1 a `gtbake tune --grid ESTIMATOR.KEY=v1,v2,...` (applyGridOption on the default grids, then
//     every grid value through settingsAt, validateSettings and the search axis)
//   2 a `gtbake screen-ao --setting ESTIMATOR.KEY=VALUE` (applySetting, validateSettings) and
//     `--estimators` list (parseEstimatorList)
// Anything but a gtbake::Error is a bug.
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "fuzz_target.h"
#include "screen_ao/screen_ao_settings.h"
#include "tune/tune_grid.h"
#include "tune/tune_set.h"

namespace gtbake::fuzz {

namespace {

// One tuned setting with every field export reads (tune.json results/<estimator>/<setting>).
nlohmann::json tuneJson() {
  const nlohmann::json refit = {{"a1", 0.5}, {"a0", 1.25}, {"b1", 0.75},
                                {"b0", 1.5}, {"c1", 0.25}, {"c0", 1.0}};
  const nlohmann::json profile = {{"value", 2.5},
                                  {"interval", {2.0, 3.0}},
                                  {"at_bound", false},
                                  {"grid_best", {{"value", 2.0}, {"profile_held_out", 0.125}}},
                                  {"refit", refit}};
  const nlohmann::json setting = {{"default", 1.0},
                                  {"optimum", {{"paper", {{"value", 4.0}}}, {"profile", profile}}}};
  return {{"results",
           {{"gtao-runtime", {{"radius", setting}, {"intensity", setting}}},
            {"bitmask-cosine", {{"thickness", setting}}}}}};
}

void readGrid(const std::string& text) {
  std::vector<SettingGrid> grids = defaultGrids(tunedEstimators());
  applyGridOption(&grids, text);
  for (const SettingGrid& grid : grids) {
    for (const double value : grid.values) {
      validateSettings(settingsAt(grid, value));
      // A validated value maps onto the search axis and back (a log axis holds no value <= 0).
      if (!std::isfinite(valueOnAxis(grid, axisValue(grid, value)))) std::abort();
    }
  }
}

void readSetting(const std::string& text) {
  try {
    parseEstimatorList(text);
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  ScreenAoSettings settings;
  applySetting(&settings, text);
  validateSettings(settings);
}

}  // namespace

std::vector<std::string> seeds() {
  return {std::string(1, '\0') + tuneJson().dump(),
          std::string(1, '\1') + "gtao-runtime.radius=0.5,1,2,4",
          std::string(1, '\1') + "bitmask-cosine.thickness=0.1,0.5,1",
          std::string(1, '\2') + "hbao.radius=2",
          std::string(1, '\2') + "gtao-runtime,hbao,bitmask-uniform"};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 3) {
      case 0: {
        const std::string dir = fuzz::scratchDir() + "/tune";
        fuzz::writeSet(dir, "tune", {{"tune.json", text}});
        readTunedSettings(dir + "/tune.json");
        break;
      }
      case 1:
        fuzz::readGrid(text);
        break;
      default:
        fuzz::readSetting(text);
        break;
    }
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  return 0;
}
