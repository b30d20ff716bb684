// The inputs of `gtbake export` besides the gtso set (gtso/gtso_set.h): fit.json from `gtbake
// fit`, the engine profiles, tune.json and the u of validate_gtso.json, read and validated into
// plain structs. Every problem is one gtbake::Error line.
#pragma once

#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/profile_shape.h"
#include "gtso/gtso_set.h"

namespace gtbake {

struct FitInput {
  std::array<double, 6> linear{};     // a1, a0, b1, b0, c1, c0 (G = a·A³ − b·A² + c·A)
  std::array<double, 6> linear_se{};  // standard errors, same order
  nlohmann::json json;                // fit.json verbatim (provenance)
};

// One engine profile (docs/profiles.md): Equation 10 refitted on a screen-space estimator's Â, as
// `gtbake fit --estimator` wrote it into <profiles>/<estimator>/fit.json.
struct ProfileInput {
  std::string estimator;           // lower-case letters, digits and '-' (checked)
  std::array<double, 6> linear{};  // a1, a0, b1, b0, c1, c0
  double band_max = 0.0;           // largest scene-jackknife SE of G (0: no band)
  double rmse_paper = 0.0;         // RMSE of G with the paper's constants on that Â
  double rmse_held_out = 0.0;      // RMSE of G with the profile, each scene held out
  // The shipping gate (docs/profiles.md §9), recomputed here from the coefficients and the two
  // RMSEs: only a shipped profile enters the header and the includes.
  ProfileGate gate;
  // The monotone 2D table shipped beside the cubic where the cubic is not adequate
  // (docs/profiles.md §8; fit.json /profile/table with needed true): G at table_nodes values of Â
  // (0 … 1) per albedo of table_rhos, row-major [albedo][node]. Empty otherwise.
  int table_nodes = 0;
  std::vector<double> table_rhos;
  std::vector<double> table_values;
  double table_held_out_rmse = 0.0;
};

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

FitInput readFitInput(const std::filesystem::path& file);
// Every <dir>/<estimator>/fit.json with a fit manifest, in name order; each must be a profile
// (fit.json /input/estimator equal to its directory's name). Throws gtbake::Error.
std::vector<ProfileInput> readProfiles(const std::filesystem::path& dir);

// Every setting of tune.json (`gtbake tune`, its manifest verified), in the file's order. Throws
// gtbake::Error on a malformed file.
std::vector<TunedSettingInput> readTunedSettings(const std::filesystem::path& file);

// Takes u and u_interval from validate_gtso.json (`gtbake validate-gtso`) into `gtso`.
void applyValidateGtsoU(const std::filesystem::path& file, GtsoInput* gtso);

}  // namespace gtbake
