// `gtbake screen-ao`: screen-space A and bent normals from a sweep's G-buffer, scored against its
// ray-traced A and bent normals (docs/screen_ao.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "screen_ao/screen_ao_import.h"
#include "screen_ao/screen_ao_settings.h"

namespace gtbake {

struct ScreenAoOptions {
  std::filesystem::path sweep;  // a directory written by gtbake sweep (with G-buffer channels)
  std::filesystem::path out;
  std::vector<Estimator> estimators = screenAoEstimators();  // built-in, may be empty
  // Engines' own passes (docs/screen_ao.md §8), scored after the built-in ones, in this order.
  std::vector<ImportedEstimator> imports;
  ScreenAoSettings settings;
  int threads = 0;
  bool progress = true;
};

struct ScreenAoResult {
  std::filesystem::path json;
  double seconds = 0.0;
  double reference_rmse = 0.0;  // gtao-reference against A_R (or A), every pixel (0 if not run)
};

// Writes <out>/screen_ao.json, <out>/<image>.exr, the PNGs and <out>/screen_ao.html as one output
// set (screen_ao.manifest.json); prints one line per estimator. Throws gtbake::Error.
ScreenAoResult runScreenAo(const ScreenAoOptions& options);

}  // namespace gtbake
