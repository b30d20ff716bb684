// The layout of a `gtbake all` output directory, the committed luts/ among them
// (docs/reproducibility.md "Layout"): the files an engine ships in ship/, one folder per stage
// holding its outputs and its manifest, and index.html at the top linking every report.
#pragma once

#include <filesystem>

namespace gtbake {

// The folders of the layout, relative to the output directory.
inline constexpr const char* kShipDir = "ship";
inline constexpr const char* kSweepDir = "sweep";
inline constexpr const char* kFitDir = "fit";
inline constexpr const char* kGtsoDir = "gtso";
inline constexpr const char* kEncodeDir = "encode";
inline constexpr const char* kValidateGtsoDir = "validate_gtso";
inline constexpr const char* kScreenAoDir = "screen_ao";
inline constexpr const char* kProfilesDir = "profiles";
inline constexpr const char* kTuneDir = "tune";
inline constexpr const char* kLightingDir = "lighting";

// Throws gtbake::Error (one line saying what to do) when `dir` holds the flat layout of an older
// gtbake (sweep.json, fit.json, gtbake_tables.h, report/index.html or a stage's manifest at its
// top): its files are never mixed with the new layout's.
void refuseFlatLayout(const std::filesystem::path& dir, const char* command);

}  // namespace gtbake
