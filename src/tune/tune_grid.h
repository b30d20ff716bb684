// The settings `gtbake tune` searches and their grids (docs/tune.md §1): one setting of one
// screen-space estimator at a time, every other setting at the estimator's default, on a grid that
// holds the default value.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "screen_ao/screen_ao_settings.h"

namespace gtbake {

struct SettingGrid {
  Estimator estimator = Estimator::kGtaoRuntime;
  std::string key;  // its setting ("radius")
  // The setting in ScreenAoSettings (its TunedKey's field): settingsAt sets it as a number.
  double& (*field)(ScreenAoSettings& s) = nullptr;
  bool log_axis = false;  // searched and plotted on log10 of the value (lengths in metres)
  double default_value = 0.0;
  std::vector<double> values;  // ascending, distinct, holding default_value, within the limits
  SettingLimit lower, upper;   // values never pass them
  // The estimator's name, as tune.json, the report and the console spell it.
  const char* name() const { return describe(estimator).name; }
};

// Widening steps allowed at each end of a grid (docs/tune.md §3).
inline constexpr int kMaxWidenings = 4;

// The value one widening step beyond the grid's lower (upper = false) or upper end: the end
// times the ratio of the end to its neighbour on a log axis, the end plus the end's spacing on a
// linear one, clipped to the limit; nullopt when the end is the limit.
std::optional<double> widenedEnd(const SettingGrid& grid, bool upper);

// The estimators tune covers, in output order: gtao-runtime, bitmask-uniform, bitmask-cosine.
const std::vector<Estimator>& tunedEstimators();

// The default grids of the estimators listed (every one must be a tuned estimator; throws a
// one-line gtbake::Error naming it otherwise), estimator by estimator, settings in a fixed order.
std::vector<SettingGrid> defaultGrids(const std::vector<Estimator>& estimators);

// Applies one "ESTIMATOR.KEY=v1,v2,..." to `grids` (replacing that setting's values). Throws a
// one-line gtbake::Error for an estimator not in `grids`, a key tune does not search, a value that
// does not parse or is out of range (validateSettings) or outside the setting's limits, a
// repeated value, fewer than two values or a grid without the default.
void applyGridOption(std::vector<SettingGrid>* grids, const std::string& text);

// The defaults with `grid`'s setting at `value` (set as a number through grid.field).
ScreenAoSettings settingsAt(const SettingGrid& grid, double value);

// The value on the grid's search axis: log10(value) on a log axis, else the value.
double axisValue(const SettingGrid& grid, double value);
double valueOnAxis(const SettingGrid& grid, double z);

}  // namespace gtbake
