// What a fit analysis becomes: fit.json (fit_json.cpp) and the printed summaries
// (fit_summary.cpp). The report is fit_report.h.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "fit/fit_analysis.h"
#include "fit/validate_report.h"

namespace gtbake {

// fit.json's document; paths are recorded relative to the directory of `json_path`.
// `shipped_report` is the shipped constants' validate report (the verdict by range of A).
nlohmann::json fitJson(const std::filesystem::path& json_path, const FitAnalysis& a,
                       const MultiBounceCoeffs& shipped, const ValidateReport& shipped_report);

// `gtbake fit`'s stdout: a table a person reads at a glance, then the details.
void printFitSummary(const FitAnalysis& a, const MultiBounceCoeffs& shipped,
                     const ValidateReport& shipped_report);

}  // namespace gtbake
