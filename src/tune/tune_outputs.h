// What `gtbake tune` writes and prints (docs/tune.md §5): tune.json, report/tune.html (one SVG plot
// per searched setting) and the summary table on stdout. Formatting only; the numbers are
// tune_analysis.h's.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "tune/tune_analysis.h"

namespace gtbake {

// Where the run came from (provenance); seconds are the only fields that differ between runs.
struct TuneProvenance {
  std::string sweep;  // the --sweep path, relative to the output directory
  double seconds = 0.0;
};

nlohmann::ordered_json tuneSettingsJson(const std::vector<SettingGrid>& grids,
                                        const std::string& sweep);
nlohmann::ordered_json tuneJson(const TuneAnalysis& a, const std::vector<SettingGrid>& grids,
                                const TuneProvenance& provenance);
std::string tuneReportHtml(const TuneAnalysis& a);
void printTuneSummary(const TuneAnalysis& a);

// A value on the setting's own scale from a point of its search axis.
double optimumValue(const SettingResult& r, double z);
// An optimum as the summary and the report print it: "v [low, high]" inside the grid (" clipped"
// when the interval reached past an end), ">= v bound (n/S replicas)" at the upper limit and
// "<= v bound (...)" at the lower one (docs/tune.md §3, §5).
std::string optimumSummary(const SettingResult& r, const SceneInterval& o);

}  // namespace gtbake
