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
#include "fit/validate_output.h"

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
  if (options.write_validate_data && options.out.filename() == kValidateDataFile) {
    throw Error("fit: --out must not be named " + std::string(kValidateDataFile) +
                " (the fit writes that file beside it)");
  }
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
  const FitAnalysis a = analyzeSweep(options.sweep, settingsOf(options), options.shipped, &bar,
                                     options.input, options.loaded_sweeps);
  const ValidateData validate_data = validateDataOf(a);
  const ValidateReport shipped_report = validateReport(validate_data, options.shipped);
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
    writeFitReport(report, "", a, options.shipped, &shipped_report.verdict);
    report.commit();
  } else if (options.write_report) {
    writeFitReport(output, inside + "/", a, options.shipped, &shipped_report.verdict);
  }
  bar.add(1);
  output.add(options.out.filename().string(),
             fitJson(options.out, a, options.shipped, shipped_report).dump(2) + "\n");
  if (options.write_validate_data) {
    output.add(kValidateDataFile, validateDataText(validate_data));
  }
  output.commit();
  bar.add(1);
  bar.finish();
  if (options.print_summary) {
    printFitSummary(a, options.shipped, shipped_report);
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
          shipped_report.verdict.headline,
          a.refit_errors.rmse,
          a.held_out_errors ? a.held_out_errors->rmse : 0.0,
          a.shipped_errors.rmse};
}

namespace {

ValidateData validateData(const ValidateOptions& options) {
  if (options.sweep.empty() == options.luts.empty()) {
    throw Error(
        "validate: give either --sweep DIR (a sweep) or --luts DIR (a fit's output, e.g. "
        "luts)");
  }
  if (!options.sweep.empty()) {
    FitSettings settings;
    settings.weighting = options.weighting;
    Progress bar("validate", kAnalysisStages, options.progress);
    const FitAnalysis a =
        analyzeSweep(options.sweep, settings, options.coeffs, &bar, options.input);
    bar.finish();
    return validateDataOf(a);
  }
  if (!options.input.rayTraced()) {
    throw Error(
        "validate: --estimator needs --sweep DIR (luts/ ships the sums of the "
        "ray-traced fit only)");
  }
  ValidateData data = readValidateData(options.luts);
  if (data.settings.weighting != options.weighting) {
    throw Error("validate: " + data.source + " holds a fit with " +
                weightingName(data.settings.weighting) + " weighting; --weighting " +
                weightingName(options.weighting) + " needs --sweep DIR");
  }
  return data;
}

}  // namespace

Verdict runValidate(const ValidateOptions& options) {
  requireFiniteCoeffs(options.coeffs, "validate --coeffs");
  if (options.rule.fail_above && !(*options.rule.fail_above > 0.0)) {
    throw Error("validate: --fail-above must be a positive difference in G");
  }
  std::vector<fs::path> inputs;
  if (options.json) {
    inputs = options.sweep.empty() ? outputSetPaths(options.luts, "fit")
                                   : outputSetPaths(options.sweep, "sweep");
    checkOutputFile(*options.json, "--json", inputs);
  }
  const ValidateData data = validateData(options);
  const ValidateReport report = validateReport(data, options.coeffs, options.rule);
  printValidateReport(data, report);
  if (options.json) {
    writeFileAtomically(*options.json, validateReportJson(data, report).dump(2) + "\n");
    std::printf("wrote %s\n", options.json->string().c_str());
  }
  return report.verdict.verdict;
}

}  // namespace gtbake
