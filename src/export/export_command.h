// `gtbake export` (docs/export.md): the C++ header and the HLSL/GLSL includes, from fit.json, the
// gtso tables and the volumes of `gtbake encode`.
#pragma once

#include <filesystem>
#include <string>

namespace gtbake {

struct ExportOptions {
  std::filesystem::path fit;   // fit.json from `gtbake fit`
  std::filesystem::path gtso;  // directory from `gtbake gtso`
  std::filesystem::path out;   // gtbake_tables.h, gtbake_tables.hlsl/.glsl
  // The directory of `gtbake encode` (encode.json, gtso*.dds); empty: `out`. When it is another
  // directory its volumes are copied into `out` beside the header (docs/export.md).
  std::filesystem::path encode;
  // validate_gtso.json from `gtbake validate-gtso`: its u (fitted to path-traced S) is shipped
  // instead of gtso.json's table fit. Empty: the table fit.
  std::filesystem::path validate_gtso;
  // The profiles of `gtbake fit --estimator` (<dir>/<estimator>/fit.json, docs/profiles.md),
  // shipped as kMultiBounceProfiles. Empty: no profiles.
  std::filesystem::path profiles;
  // tune.json of `gtbake tune` (docs/tune.md): the tuned settings, shipped as kTunedSettings with
  // the profile refitted at each. Empty: none.
  std::filesystem::path tune;
  std::string command_line;  // recorded in the provenance blocks
};

struct ExportResult {
  double bc4_rmse_3d = 0.0;
  double bc4_max_3d = 0.0;
  double bc4_rmse_4d = 0.0;
  double bc4_max_4d = 0.0;
};

ExportResult runExport(const ExportOptions& options);

}  // namespace gtbake
