#include "tune/tune_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"

namespace gtbake {

namespace {

// The settings searched per estimator, their axes and default grids (docs/tune.md §1). Each grid
// holds the estimator's default (radius 1 m, intensity 1, thin_compensation 0, thickness 0.5 m);
// radius and intensity reach 16 m and 8 because the error of G still falls at 4 m and 2.
struct GridSpec {
  const char* key;
  bool log_axis;
  std::vector<double> values;
};

std::vector<GridSpec> gridSpecs(const std::string& estimator) {
  if (estimator == "gtao-runtime") {
    // Factors of two for the lengths and the exponent (each value is a full run of the pass,
    // 11 runs beyond the defaults' in all): the optimum is refined by the parabola (§3).
    return {{"radius", true, {0.5, 1.0, 2.0, 4.0, 8.0, 16.0}},
            {"intensity", true, {0.5, 1.0, 2.0, 4.0, 8.0}},
            {"thin_compensation", false, {0.0, 0.5, 1.0}}};
  }
  return {{"thickness", true, {0.125, 0.25, 0.5, 1.0, 2.0, 4.0}}};
}

std::string settingText(const std::string& estimator, const std::string& key, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return estimator + "." + key + "=" + buffer;
}

double defaultValue(const std::string& estimator, const std::string& key) {
  return settingsJson(ScreenAoSettings{}, estimator).at(key).get<double>();
}

// Parses "v1,v2,..." through applySetting (so a value parses exactly as --setting would) and
// checks each against the estimator's ranges.
std::vector<double> parseValues(const SettingGrid& g, const std::string& list,
                                const std::string& text) {
  std::vector<double> values;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = list.find(',', begin);
    const std::string word = list.substr(begin, end == std::string::npos ? end : end - begin);
    ScreenAoSettings s;
    try {
      applySetting(&s, g.estimator + "." + g.key + "=" + word);
      validateSettings(s);
    } catch (const Error& e) {
      throw Error("--grid " + text + ": " + e.what());
    }
    values.push_back(settingsJson(s, g.estimator).at(g.key).get<double>());
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return values;
}

}  // namespace

const std::vector<std::string>& tunedEstimatorNames() {
  static const std::vector<std::string> names = {"gtao-runtime", "bitmask-uniform",
                                                 "bitmask-cosine"};
  return names;
}

std::vector<SettingGrid> defaultGrids(const std::vector<std::string>& estimators) {
  const auto& known = tunedEstimatorNames();
  std::vector<SettingGrid> grids;
  for (const std::string& e : estimators) {
    if (std::find(known.begin(), known.end(), e) == known.end()) {
      throw Error("--estimators: tune does not search '" + e +
                  "' (it searches gtao-runtime, bitmask-uniform, bitmask-cosine)");
    }
    for (const GridSpec& spec : gridSpecs(e)) {
      grids.push_back({e, spec.key, spec.log_axis, defaultValue(e, spec.key), spec.values});
    }
  }
  return grids;
}

void applyGridOption(std::vector<SettingGrid>* grids, const std::string& text) {
  const std::size_t dot = text.find('.');
  const std::size_t eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
    throw Error("--grid must look like ESTIMATOR.KEY=v1,v2,..., got '" + text + "'");
  }
  const std::string estimator = text.substr(0, dot);
  const std::string key = text.substr(dot + 1, eq - dot - 1);
  bool estimator_known = false;
  SettingGrid* grid = nullptr;
  for (SettingGrid& g : *grids) {
    estimator_known = estimator_known || g.estimator == estimator;
    if (g.estimator == estimator && g.key == key) grid = &g;
  }
  if (!estimator_known) {
    throw Error("--grid " + text + ": estimator '" + estimator +
                "' is not tuned in this run (tune searches gtao-runtime, bitmask-uniform, "
                "bitmask-cosine; see --estimators)");
  }
  if (grid == nullptr) {
    throw Error(
        "--grid " + text + ": tune does not search " + estimator + "." + key + " (" +
        (estimator == "gtao-runtime" ? "radius, intensity, thin_compensation" : "thickness") + ")");
  }
  std::vector<double> values = parseValues(*grid, text.substr(eq + 1), text);
  std::sort(values.begin(), values.end());
  if (std::adjacent_find(values.begin(), values.end()) != values.end()) {
    throw Error("--grid " + text + ": a value is listed twice");
  }
  if (values.size() < 2) throw Error("--grid " + text + ": needs at least two values");
  if (std::find(values.begin(), values.end(), grid->default_value) == values.end()) {
    throw Error("--grid " + text + ": the grid must hold the default " +
                settingText(estimator, key, grid->default_value) +
                " (every other setting's curve is taken there)");
  }
  grid->values = values;
}

ScreenAoSettings settingsAt(const SettingGrid& grid, double value) {
  ScreenAoSettings s;
  applySetting(&s, settingText(grid.estimator, grid.key, value));
  return s;
}

double axisValue(const SettingGrid& grid, double value) {
  return grid.log_axis ? std::log10(value) : value;
}

double valueOnAxis(const SettingGrid& grid, double z) {
  return grid.log_axis ? std::pow(10.0, z) : z;
}

}  // namespace gtbake
