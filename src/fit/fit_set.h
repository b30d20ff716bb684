// The reader of `gtbake fit`'s result (docs/fit.md, docs/profiles.md): fit.json's six
// coefficients and their standard errors, and the engine profiles `gtbake fit --estimator` wrote
// into <profiles>/<estimator>/fit.json, read and validated into plain structs for export and
// lighting. Every problem is one gtbake::Error line.
#pragma once

#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/profile_shape.h"

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

FitInput readFitInput(const std::filesystem::path& file);
// Every <dir>/<estimator>/fit.json with a fit manifest, in name order; each must be a profile
// (fit.json /input/estimator equal to its directory's name). Throws gtbake::Error.
std::vector<ProfileInput> readProfiles(const std::filesystem::path& dir);

}  // namespace gtbake
