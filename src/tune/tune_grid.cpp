#include "tune/tune_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

std::string settingText(const std::string& estimator, const std::string& key, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return estimator + "." + key + "=" + buffer;
}

// The tuned setting's default value.
double defaultValue(const TunedKey& spec) {
  ScreenAoSettings s;
  return spec.field(s);
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
      applySetting(&s, std::string(g.name()) + "." + g.key + "=" + word);
      validateSettings(s);
    } catch (const Error& e) {
      throw Error("--grid " + text + ": " + e.what());
    }
    values.push_back(g.field(s));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return values;
}

// The tuned estimators' names, comma-separated, for an error.
std::string tunedList() {
  return estimatorListText(tunedEstimators(), ", ");
}

}  // namespace

const std::vector<Estimator>& tunedEstimators() {
  static const std::vector<Estimator> list = [] {
    std::vector<Estimator> out;
    for (const EstimatorDescriptor& d : estimatorDescriptors()) {
      if (!d.tuned.empty()) out.push_back(d.id);
    }
    return out;
  }();
  return list;
}

std::vector<SettingGrid> defaultGrids(const std::vector<Estimator>& estimators) {
  std::vector<SettingGrid> grids;
  for (const Estimator e : estimators) {
    const EstimatorDescriptor& d = describe(e);
    if (d.tuned.empty()) {
      throw Error("--estimators: tune does not search '" + std::string(d.name) + "' (it searches " +
                  tunedList() + ")");
    }
    for (const TunedKey& spec : d.tuned) {
      grids.push_back({d.id, spec.key, spec.field, spec.log_axis, defaultValue(spec), spec.grid,
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
  const std::optional<Estimator> named = findEstimator(estimator);
  bool estimator_known = false;
  SettingGrid* grid = nullptr;
  for (SettingGrid& g : *grids) {
    const bool same = named && g.estimator == *named;
    estimator_known = estimator_known || same;
    if (same && g.key == key) grid = &g;
  }
  if (!estimator_known) {
    throw Error("--grid " + text + ": estimator '" + estimator +
                "' is not tuned in this run (tune searches " + tunedList() + "; see --estimators)");
  }
  if (grid == nullptr) {
    std::string keys;
    for (const TunedKey& k : describe(estimator, "--grid").tuned) {
      keys += (keys.empty() ? "" : ", ") + std::string(k.key);
    }
    throw Error("--grid " + text + ": tune does not search " + estimator + "." + key + " (" + keys +
                ")");
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
  grid.field(s) = value;
  return s;
}

double axisValue(const SettingGrid& grid, double value) {
  return grid.log_axis ? std::log10(value) : value;
}

double valueOnAxis(const SettingGrid& grid, double z) {
  return grid.log_axis ? std::pow(10.0, z) : z;
}

}  // namespace gtbake
