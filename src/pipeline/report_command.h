// `gtbake report`: the pictures and pages of an output directory in the layout of `gtbake all`
// (docs/reproducibility.md "Layout", "Reports from the data"), drawn again from its data files.
#pragma once

#include <filesystem>

namespace gtbake {

struct ReportOptions {
  std::filesystem::path luts;  // an output directory of `gtbake all` (its data files)
  std::filesystem::path out;   // where the pictures and pages go, in the same layout (may be luts)
  int threads = 0;             // 0 = all cores
  bool progress = true;
};

// Redraws every PNG, SVG and HTML file the manifests under `luts` list (the sweep's previews and
// the gtso slices from their data, the reports of fit, screen-ao, tune, validate-gtso and the
// profiles by running their analyses on the sweep and tables of `luts`, and index.html) into a
// scratch directory, checks each against the SHA-256 its manifest records, and only then writes
// them into `out`. Throws gtbake::Error (one line) on a missing or altered data file, a flat
// layout, or a picture that does not reproduce; nothing is written then.
void runReport(const ReportOptions& options);

}  // namespace gtbake
