// The volumes `gtbake encode` wrote, read back for the stages after it (validate-gtso reads them
// as a shader would, export embeds the BC4 blocks in the C++ header): encode.json's layouts and
// BC4 errors and every DDS file, each verified against encode.manifest.json and read through the
// texture library's reader. docs/export.md "The encode step".
#pragma once

#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "gtso/gtso_set.h"
#include "runtime/gtso_runtime.h"
#include "texture/texture_containers.h"

namespace gtbake {

struct ShippedVolume {
  GtsoLayout layout = kGtsoIdentityLayout;  // table axes on texture x, y, z; 4D tiles
  std::array<int, 3> volume{};              // texture extent in that layout
  VolumeData bc4, r16, r8;                  // gtso3d{,_r16,_r8}.dds (or gtso4d*)
  double bc4_rmse = 0.0, bc4_max = 0.0;     // decoded BC4 texels vs the float table
  double bc4_seconds = 0.0;                 // encoder time
  nlohmann::json layout_json;               // encode.json layouts/<3d|4d> verbatim
};

struct ShippedVolumes {
  ShippedVolume t3, t4;
  nlohmann::json json;  // encode.json verbatim
};

// Reads <dir>/encode.json and the six DDS volumes, checking that they were encoded from `gtso`'s
// tables (encode.json inputs = the SHA-256 of gtso3d.f32 / gtso4d.f32 in gtso.manifest.json) and
// that every volume has the format and the extent of its table in its layout. One-line
// gtbake::Error otherwise ("rerun `gtbake encode`").
ShippedVolumes readShippedVolumes(const std::filesystem::path& dir, const GtsoInput& gtso);

// The SHA-256 gtso.manifest.json records for a table file of the gtso set in `gtso_dir`.
std::string gtsoTableHash(const std::filesystem::path& gtso_dir, const std::string& file);

}  // namespace gtbake
