// `gtbake encode` (docs/export.md "The encode step"): the gtso directory -> the GTSO volumes an
// engine loads, gtso3d/gtso4d {BC4, _r16, _r8} .dds/.ktx2, in the texture layout chosen per
// table with the exact BC4 encoder (bc4_layout.h), and encode.json (layouts, candidates, BC4
// errors). validate-gtso and export read these files.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "encode/bc4_layout.h"

namespace gtbake {

struct EncodeOptions {
  std::filesystem::path gtso;  // directory from `gtbake gtso`
  std::filesystem::path out;   // gtso3d*.dds/.ktx2, gtso4d*.dds/.ktx2, encode.json
  int threads = 0;
  bool progress = true;
  std::FILE* summary = stdout;  // where the closing summary lines go (nullptr: nowhere)
  // BC4 layout choice (bc4_layout.h): uniform lobes of its point set (16 points each), and, for
  // tests, layouts forced instead of chosen ({x, y, z} table axes; empty: choose).
  int layout_lobes = 512;
  std::vector<int> force_layout_3d, force_layout_4d;
  // How the 4D table's theta_o slices are packed (--4d-layout; docs/export.md §2c) and the
  // atlas's largest extent (tests pack small tables with a smaller one).
  Layout4D layout_4d = Layout4D::kAtlas;
  int atlas_max_extent = kAtlasMaxExtent;
};

struct EncodeResult {
  double bc4_rmse_3d = 0.0, bc4_max_3d = 0.0;
  double bc4_rmse_4d = 0.0, bc4_max_4d = 0.0;
  double seconds = 0.0;
};

EncodeResult runEncode(const EncodeOptions& options);

}  // namespace gtbake
