// The reader of `gtbake tune`'s result (docs/tune.md): every tuned setting of tune.json, read and
// validated into plain structs for export. Every problem is one gtbake::Error line.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace gtbake {

// One tuned setting of a screen-space estimator (docs/tune.md), from tune.json: the value that
// minimises the RMSE of G with the paper's constants and with the profile refitted at each value
// (one setting at a time), the latter's scene-level interval, and the evaluated grid value with
// the lowest RMSE under the refit, with the profile refitted there: what an engine can ship
// together.
struct TunedSettingInput {
  std::string estimator;  // lower-case letters, digits and '-' (checked)
  std::string setting;    // lower-case letters and '_' (checked)
  double default_value = 0.0;
  double paper_best = 0.0, profile_best = 0.0;
  double profile_low = 0.0, profile_high = 0.0;  // 95% scene-level interval of profile_best
  bool at_bound = false;                         // profile_best at the grid's end
  double grid_value = 0.0;         // the evaluated value with the lowest RMSE under the refit
  std::array<double, 6> linear{};  // the profile refitted at grid_value
  double rmse_held_out = 0.0;      // RMSE of G there, each scene held out
};

// Every setting of tune.json (`gtbake tune`, its manifest verified), in the file's order. Throws
// gtbake::Error on a malformed file.
std::vector<TunedSettingInput> readTunedSettings(const std::filesystem::path& file);

}  // namespace gtbake
