// What validate-gtso writes from analyse()'s result, formatting only (docs/validate_gtso.md §4,
// §5): validate_gtso.json, the HTML pages with the per-scene images, the one-screen summary. On
// an estimator's inputs (docs/validate_gtso.md §6) the same tables without the u fits, the floor
// and the texel-format comparison, which belong to the ray-traced run.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/output_set.h"
#include "validate_gtso/validate_gtso_analysis.h"

namespace gtbake {

// validate_gtso.json; `out` is where it is written (paths in it are relative to it).
nlohmann::ordered_json validateGtsoJson(const ValidateGtsoOptions& options,
                                        const std::filesystem::path& out, const Analysis& a,
                                        double seconds);

// report/validate_gtso.html (and on the ray-traced inputs report/validate_gtso_scenes.html), with
// one PNG per scene when `images` is set.
void addValidateGtsoReport(const Analysis& a, bool images, OutputSet& output);

void printValidateGtsoSummary(const Analysis& a, const std::filesystem::path& json);

}  // namespace gtbake
