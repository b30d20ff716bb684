// `gtbake export`: BC4 tables, DDS and KTX2 files, the C++ header and shader includes (SPEC §1.5).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace gtbake {

struct GtsoLayouts;  // export/bc4_layout.h

struct ExportOptions {
  std::filesystem::path fit;   // fit.json from `gtbake fit`
  std::filesystem::path gtso;  // directory from `gtbake gtso`
  std::filesystem::path out;   // gtbake_tables.h, gtbake_tables.hlsl/.glsl, *.dds, *.ktx2
  // validate_gtso.json from `gtbake validate-gtso`: its u (fitted to path-traced S) is shipped
  // instead of gtso.json's table fit. Empty: the table fit.
  std::filesystem::path validate_gtso;
  std::string command_line;  // recorded in the provenance blocks
  int threads = 0;
  bool progress = true;
  // BC4 layout choice (bc4_layout.h): uniform lobes of its point set (16 points each), and, for
  // tests, layouts forced instead of chosen ({x, y, z} table axes; empty: choose).
  int layout_lobes = 512;
  std::vector<int> force_layout_3d, force_layout_4d;
  // Layouts already chosen for these tables (`gtbake all` chooses once for validate-gtso and
  // export); null: choose here.
  std::shared_ptr<const GtsoLayouts> layouts;
};

struct ExportResult {
  double bc4_rmse_3d = 0.0;
  double bc4_max_3d = 0.0;
  double bc4_rmse_4d = 0.0;
  double bc4_max_4d = 0.0;
};

ExportResult runExport(const ExportOptions& options);

}  // namespace gtbake
