// Formats what `validate` computed (validate_report.h): the printed summary and the JSON of
// `validate --json FILE` (docs/fit.md §10 lists its keys).
#pragma once

#include <nlohmann/json.hpp>

#include "fit/curve_verdict.h"
#include "fit/validate_report.h"

namespace gtbake {

void printValidateReport(const ValidateData& data, const ValidateReport& report);
nlohmann::ordered_json validateReportJson(const ValidateData& data, const ValidateReport& report);
// The verdict by range alone (fit.json's /shipped/verdict uses it too).
nlohmann::ordered_json curveVerdictJson(const CurveVerdict& verdict);

}  // namespace gtbake
