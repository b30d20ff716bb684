// screen_ao.json (docs/screen_ao.md, "Outputs").
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "screen_ao/gtao_reference.h"
#include "screen_ao/screen_ao_stats.h"

namespace gtbake {

struct EstimatorRun {
  std::string name;
  nlohmann::ordered_json settings;
  double radius = 0.0;
  std::string radius_channel;  // A_R… of that radius, "" if the sweep has none
  double seconds = 0.0;
  double megapixels = 0.0;
  std::vector<GroupErrors> errors;
};

nlohmann::ordered_json errorSummaryJson(const ErrorSummary& e);
nlohmann::ordered_json estimatorJson(const EstimatorRun& run);
nlohmann::ordered_json convergenceJson(const ReferenceConvergence& c);

}  // namespace gtbake
