// `gtbake fit` and `gtbake validate` (docs/fit.md §1, docs/index.md "Pipeline"): analyse a sweep
// (fit_analysis.h), then write fit.json and the HTML report and print a summary a person reads at a
// glance.
#include "fit/fit_command.h"

#include <cstdio>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "fit/fit_outputs.h"
#include "fit/fit_report.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

FitSettings settingsOf(const FitOptions& o) {
  FitSettings s;
  s.eiv_correction = o.eiv_correction;
  s.weighting = o.weighting;
  s.constrain_open = o.constrain_open;
  return s;
}

}  // namespace

FitResult runFit(const FitOptions& options) {
  if (options.out.empty()) throw Error("fit: no output file given (--out FILE.json)");
  requireFiniteCoeffs(options.shipped, "shipped constants");
  std::vector<fs::path> inputs = outputSetPaths(options.sweep, "sweep");
  inputs.push_back(options.sweep / "sweep.json");
  if (!options.input.rayTraced()) {
    for (const fs::path& p : outputSetPaths(options.input.screen_ao, "screen_ao")) {
      inputs.push_back(p);
    }
  }
  checkOutputFile(options.out, "--out", inputs);
  const fs::path out_dir =
      options.out.parent_path().empty() ? fs::path(".") : options.out.parent_path();
  const OutputLock lock(out_dir);  // for the whole run (output_lock.h)
  // Stages: the analysis, the report, fit.json.
  Progress bar("fit", kAnalysisStages + 2, options.progress);
  const FitAnalysis a =
      analyzeSweep(options.sweep, settingsOf(options), options.shipped, &bar, options.input);
  ensureDirectory(out_dir);
  const fs::path report_dir = options.report ? *options.report : out_dir / "report";
  // The report is part of the fit set when it lies inside out_dir (gtbake all: luts/report/);
  // elsewhere it is a set of its own (fit_report.manifest.json), committed first.
  std::string inside =
      fs::path(relativePath(report_dir, out_dir)).lexically_normal().generic_string();
  while (!inside.empty() && inside.back() == '/') inside.pop_back();
  const bool own = inside.empty() || inside == "." || inside.rfind("..", 0) == 0 ||
                   fs::path(inside).is_absolute();
  OutputSet output(out_dir, "fit");  // export requires and verifies fit.manifest.json
  if (options.write_report && own) {
    OutputSet report(report_dir, "fit_report");
    writeFitReport(report, "", report_dir, a, options.shipped);
    report.commit();
  } else if (options.write_report) {
    writeFitReport(output, inside + "/", report_dir, a, options.shipped);
  }
  bar.add(1);
  output.add(options.out.filename().string(),
             fitJson(options.out, a, options.shipped).dump(2) + "\n");
  output.commit();
  bar.add(1);
  bar.finish();
  if (options.print_summary) {
    printFitSummary(a, options.shipped);
    if (options.write_report) {
      std::printf("wrote %s and %s\n", options.out.string().c_str(),
                  (report_dir / "index.html").string().c_str());
    } else {
      std::printf("wrote %s\n", options.out.string().c_str());
    }
  }
  return {a.fit.linear.coeffs,
          a.fit.linear.se,
          a.jackknife.se,
          a.jackknife.band_max.value,
          a.shipped_score.verdict,
          a.refit_errors.rmse,
          a.held_out_errors ? a.held_out_errors->rmse : 0.0,
          a.shipped_errors.rmse};
}

void runValidate(const ValidateOptions& options) {
  requireFiniteCoeffs(options.coeffs, "validate --coeffs");
  FitSettings settings;
  settings.weighting = options.weighting;
  Progress bar("validate", kAnalysisStages, options.progress);
  const FitAnalysis a = analyzeSweep(options.sweep, settings, options.coeffs, &bar, options.input);
  bar.finish();
  printValidateSummary(a, options.coeffs);
}

}  // namespace gtbake
