// The reader of `gtbake validate-gtso`'s result on the ray-traced inputs (docs/validate_gtso.md
// §5): the cone-aperture constant u fitted to path-traced S and its scene-level interval, which
// export ships (applyValidateGtsoU) and validate-gtso --estimator scores. Every problem is one
// gtbake::Error line.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "gtso/gtso_set.h"

namespace gtbake {

struct ValidateGtsoU {
  double u = 0.0;     // cos αs = u^(α²/2), fitted to path-traced S
  double u_se = 0.0;  // its scene-level SE (0 when the file carries none)
  double low = 0.0;   // its scene-level 95% interval, [low, high] ⊂ (0, 1]
  double high = 0.0;
  nlohmann::json json;  // validate_gtso.json verbatim (provenance)
};

// validate_gtso.json (its manifest verified). Throws unless u lies in (0, 1) inside u_interval
// and u_interval in (0, 1].
ValidateGtsoU readValidateGtsoU(const std::filesystem::path& file);

// Takes u, its SE and u_interval from validate_gtso.json (readValidateGtsoU) into `gtso`.
void applyValidateGtsoU(const std::filesystem::path& file, GtsoInput* gtso);

}  // namespace gtbake
