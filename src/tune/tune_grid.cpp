#include "tune/tune_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

// The settings searched per estimator, their axes, default grids and limits (docs/tune.md §1).
// Each grid holds the estimator's default (radius 1 m, intensity 1, thin_compensation 0,
// thickness 0.5 m) and widens towards its limits while an optimum sits at an end (§3).
struct GridSpec {
  const char* key;
  bool log_axis;
  std::vector<double> values;
  SettingLimit lower, upper;
};

std::vector<GridSpec> gridSpecs(const std::string& estimator) {
  if (estimator == "gtao-runtime") {
    // Factors of two for the lengths and the exponent (each value is a full run of the pass):
    // the optimum is refined by the parabola (§3).
    return {{"radius",
             true,
             {0.5, 1.0, 2.0, 4.0},
             {0.0625, "search floor: 1/16 m, three halvings below the 0.5 m grid start"},
             {4.0, "screen-space maximum: 4 m, past it the horizon search leaves the view"}},
            {"intensity",
             true,
             {0.5, 1.0, 2.0, 4.0, 8.0},
             {0.25, "search floor: A^0.25, the pass's occlusion all but erased"},
             {16.0, "the pass's range: intensity <= 16 (docs/screen_ao.md)"}},
            {"thin_compensation",
             false,
             {0.0, 0.5, 1.0},
             {0.0, "physical: thin compensation >= 0 (0 is off)"},
             {10.0, "the pass's range: thin_compensation <= 10 (docs/screen_ao.md)"}}};
  }
  return {{"thickness",
           true,
           {0.125, 0.25, 0.5, 1.0, 2.0, 4.0},
           {0.03125, "search floor: 1/32 m, two halvings below the 0.125 m grid start"},
           {8.0, "physical: 8 radii, a slab that thick is an infinite one to 1 of 32 sectors"}}};
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
      grids.push_back({e, spec.key, spec.log_axis, defaultValue(e, spec.key), spec.values,
                       spec.lower, spec.upper});
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
  if (values.front() < grid->lower.value || values.back() > grid->upper.value) {
    throw Error("--grid " + text + ": values must lie within the setting's limits [" +
                formatNumber(grid->lower.value, "%g") + ", " +
                formatNumber(grid->upper.value, "%g") + "] (" +
                (values.front() < grid->lower.value ? grid->lower.reason : grid->upper.reason) +
                ")");
  }
  if (std::find(values.begin(), values.end(), grid->default_value) == values.end()) {
    throw Error("--grid " + text + ": the grid must hold the default " +
                settingText(estimator, key, grid->default_value) +
                " (every other setting's curve is taken there)");
  }
  grid->values = values;
}

std::optional<double> widenedEnd(const SettingGrid& grid, bool upper) {
  const std::vector<double>& v = grid.values;
  const double end = upper ? v.back() : v.front();
  const double next = upper ? v[v.size() - 2] : v[1];
  const SettingLimit& limit = upper ? grid.upper : grid.lower;
  if (end == limit.value) return std::nullopt;
  const double beyond = grid.log_axis ? end * (end / next) : end + (end - next);
  return upper ? std::min(beyond, limit.value) : std::max(beyond, limit.value);
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
