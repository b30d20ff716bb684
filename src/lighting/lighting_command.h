// `gtbake lighting` (docs/lighting.md): Equation 10 under real environments, from a sweep's
// transfer channels. Writes <out>/lighting.json, lighting.html and images/*.png as one
// output set (lighting.manifest.json).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lighting/lighting_analysis.h"

namespace gtbake {

struct LightingOptions {
  std::filesystem::path sweep;
  std::vector<std::string> environments;  // built-in class names or equirectangular EXR files
  std::filesystem::path fit;              // gtbake fit's fit.json (optional)
  std::filesystem::path out;
  bool print_summary = true;
  bool progress = true;
};

// The analysis as lighting.json, the HTML report and the stdout summary.
nlohmann::ordered_json lightingJson(const LightingAnalysis& a, const std::string& sweep,
                                    const std::string& fit);
std::string lightingReportHtml(const LightingAnalysis& a);
void printLightingSummary(const LightingAnalysis& a);

void runLighting(const LightingOptions& options);

}  // namespace gtbake
