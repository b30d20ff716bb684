// What a fit analysis becomes: fit.json (fit_json.cpp) and the printed summaries
// (fit_summary.cpp). The report is fit_report.h.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "fit/fit_analysis.h"

namespace gtbake {

// fit.json's document; paths are recorded relative to the directory of `json_path`.
nlohmann::json fitJson(const std::filesystem::path& json_path, const FitAnalysis& a,
                       const MultiBounceCoeffs& shipped);

// `gtbake fit`'s stdout: a table a person reads at a glance, then the details.
void printFitSummary(const FitAnalysis& a, const MultiBounceCoeffs& shipped);

// `gtbake validate`'s stdout: the given constants against the refit and its band.
void printValidateSummary(const FitAnalysis& a, const MultiBounceCoeffs& given);

}  // namespace gtbake
