// The estimators `gtbake screen-ao` knows, their settings and the command line's
// "--setting ESTIMATOR.KEY=VALUE" (docs/screen_ao.md, "Command").
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "screen_ao/estimator.h"

namespace gtbake {

// In output order: gtao-reference, gtao-runtime, hbao, bitmask-uniform, bitmask-cosine.
const std::vector<Estimator>& screenAoEstimators();
// Their names, in the same order.
const std::vector<std::string>& screenAoEstimatorNames();

// "a,b,c" of known names, no repeats ("all" = every one, "none" = no built-in one), parsed once by
// the shell (apps/gtbake). Throws gtbake::Error naming the word.
std::vector<Estimator> parseEstimatorList(const std::string& text);
// The names of `list` joined by `separator` (a default of --estimators, or a list in a message).
std::string estimatorListText(const std::vector<Estimator>& list, const std::string& separator);

// Applies "ESTIMATOR.KEY=VALUE" (ESTIMATOR "all" with KEY radius sets every radius); throws a
// one-line gtbake::Error on an unknown estimator or key or a value that does not parse. Ranges
// are checked by validateSettings.
void applySetting(ScreenAoSettings* s, const std::string& text);
void validateSettings(const ScreenAoSettings& s);

nlohmann::ordered_json settingsJson(const ScreenAoSettings& s, Estimator estimator);
double estimatorRadius(const ScreenAoSettings& s, Estimator estimator);

// Runs one estimator on one image.
AoEstimate runEstimator(const ScreenAoSettings& s, Estimator estimator, const GBuffer& g);

}  // namespace gtbake
