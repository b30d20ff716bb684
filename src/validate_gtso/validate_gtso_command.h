// `gtbake validate-gtso` (docs/gtso.md §1, docs/index.md "Pipeline"; docs/validate_gtso.md): scores
// the shipped GTSO tables, the cone-to-cone model and the baselines an engine would otherwise use
// against the sweep's path-traced specular occlusion, and fits the cone-aperture constant u there.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "screen_ao/screen_ao_set.h"
#include "validate_gtso/specular_sweep.h"

namespace gtbake {

struct ValidateGtsoOptions {
  std::filesystem::path sweep;  // a `gtbake sweep` directory traced with specular channels
  std::filesystem::path luts;   // holds gtso/ and encode/ (docs/reproducibility.md "Layout")
  std::filesystem::path out;    // validate_gtso.json, report/; default: luts/validate_gtso
  double u = 0.0;               // --u: also score the cone model with this u (0: not given)
  // --estimator/--screen-ao: score on a screen-space estimator's Â and b̂ instead of the ray-traced
  // A and b (docs/validate_gtso.md §6); out then defaults to luts/profiles/<estimator>.
  AoInput input;
  // The sweep already read from `sweep` (gtbake all reads it once for every estimator); null:
  // read here.
  const SpecularSweep* sweep_data = nullptr;
  // Its unbounded S, for the comparison beside a near-field truth (the same); null: read here.
  const SpecularSweep* unbounded_sweep_data = nullptr;
  bool write_images = true;   // the per-scene PNGs of the report
  bool print_summary = true;  // the one-screen summary on stdout
  bool progress = true;
};

struct ValidateGtsoResult {
  std::filesystem::path json;
  double u = 0.0;  // fitted, cos αs = u^(α²/2) with α = r_p² (docs/gtso.md §1)
  double u_low = 0.0;
  double u_high = 0.0;
  double seconds = 0.0;
  std::vector<std::pair<std::string, double>> rmse;  // every scored method's overall RMSE of S
};

ValidateGtsoResult runValidateGtso(const ValidateGtsoOptions& options);

}  // namespace gtbake
