// `gtbake fit` and `gtbake validate` (SPEC §1.3, §2): load a sweep, fit Eq. 10, score constants,
// write fit.json and the HTML report, print a summary a person reads at a glance.
#include "fit/fit_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "fit/fit_errors.h"
#include "fit/fit_report.h"
#include "fit/multibounce_fit.h"
#include "fit/scene_mix.h"
#include "fit/sweep_data.h"
#include "gtbake_version.h"

namespace gtbake {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* const kCoeffNames[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};

json coeffsJson(const MultiBounceCoeffs& k) {
  json out = json::object();
  for (int i = 0; i < 6; ++i) out[kCoeffNames[i]] = k[i];
  return out;
}

json cubicJson(const Cubic& t) {
  return {{"a", t[0]}, {"b", t[1]}, {"c", t[2]}};
}

json errorJson(const ErrorTable& table) {
  json out = {{"rmse", table.rmse}, {"max_abs", table.max_abs}};
  out["per_albedo"] = json::array();
  for (const ErrorRow& row : table.per_albedo) {
    out["per_albedo"].push_back({{"rho", row.rho}, {"rmse", row.rmse}, {"max_abs", row.max_abs}});
  }
  out["per_scene"] = json::array();
  for (const ErrorRow& row : table.per_scene) {
    out["per_scene"].push_back(
        {{"scene", row.label}, {"rmse", row.rmse}, {"max_abs", row.max_abs}});
  }
  return out;
}

// What bias is left in the reported linear coefficients: with the correction, the gap between the
// quadratic and the two-point extrapolation (it bounds the next order, docs/fit.md §4); without
// it, the whole measured bias.
MultiBounceCoeffs residualBias(const MultiBounceFit& fit) {
  MultiBounceCoeffs out;
  for (int i = 0; i < 6; ++i) {
    out[i] = fit.eiv_corrected ? std::abs(fit.linear.eiv_bias[i] - fit.linear.eiv_bias_linear[i])
                               : std::abs(fit.linear.eiv_bias[i]);
  }
  return out;
}

double maxRatio(const MultiBounceCoeffs& values, const MultiBounceCoeffs& se) {
  double ratio = 0.0;
  for (int i = 0; i < 6; ++i) ratio = std::max(ratio, std::abs(values[i]) / se[i]);
  return ratio;
}

json curveJson(const CurveDifference& d) {
  return {{"value", d.value}, {"A", d.A}, {"rho", d.rho}};
}

json sceneMixJson(const std::vector<SceneMixRow>& mix) {
  json rows = json::array();
  for (const SceneMixRow& r : mix) {
    rows.push_back({{"left_out", r.left_out},
                    {"linear", coeffsJson(r.linear)},
                    {"max_curve_difference_vs_refit", curveJson(r.vs_refit)},
                    {"max_curve_difference_vs_shipped", curveJson(r.vs_shipped)}});
  }
  return {{"method", "refit with each scene left out, same EIV setting as the main fit"},
          {"leave_one_out", rows}};
}

json fitJson(const fs::path& json_path, const SweepData& data, const MultiBounceFit& fit,
             const MultiBounceCoeffs& shipped, const ErrorTable& refit_errors,
             const ErrorTable& shipped_errors, const CurveDifference& diff,
             const std::vector<SceneMixRow>& mix) {
  json out;
  out["per_albedo"] = json::array();
  json bias_rows = json::array();
  for (const AlbedoFit& f : fit.per_albedo) {
    out["per_albedo"].push_back({{"rho", f.rho},
                                 {"a", f.theta[0]},
                                 {"b", f.theta[1]},
                                 {"c", f.theta[2]},
                                 {"se", cubicJson(f.se)},
                                 {"se_iid", cubicJson(f.se_iid)},
                                 {"uncorrected", cubicJson(f.uncorrected)},
                                 {"rmse", f.rmse},
                                 {"max_abs", f.max_abs},
                                 {"points", f.points}});
    bias_rows.push_back({{"rho", f.rho},
                         {"bias", cubicJson(f.eiv_bias)},
                         {"half_mean", cubicJson(f.half_mean)},
                         {"bias_split_half", cubicJson(f.eiv_bias_linear)},
                         {"ratio_to_se", cubicJson({std::abs(f.eiv_bias[0]) / f.se[0],
                                                    std::abs(f.eiv_bias[1]) / f.se[1],
                                                    std::abs(f.eiv_bias[2]) / f.se[2]})}});
  }
  out["linear"] = coeffsJson(fit.linear.coeffs);
  out["linear_se"] = coeffsJson(fit.linear.se);
  out["linear_misfit"] = {{"se", coeffsJson(fit.linear.misfit_se)},
                          {"rms_residual", cubicJson(fit.linear.misfit_rms)}};
  out["linear_uncorrected"] = coeffsJson(fit.linear.uncorrected);
  out["scene_mix"] = sceneMixJson(mix);
  out["se_definition"] =
      "Monte Carlo sandwich: C (sum psi psi^T) C, C = Ceres covariance (J^T J)^-1, psi from "
      "half-sample differences (noise in G, in A and their correlation); se_iid = Ceres "
      "covariance x RSS/(n-3); linear_se propagates the full cross-albedo covariance";
  out["errors"] = {{"refit", errorJson(refit_errors)}, {"shipped", errorJson(shipped_errors)}};
  out["shipped"] = {{"coeffs", coeffsJson(shipped)},
                    {"max_curve_difference",
                     {{"value", diff.value},
                      {"A", diff.A},
                      {"rho", diff.rho},
                      {"refit_minus_shipped", diff.signed_value}}}};
  MultiBounceCoeffs ratio;
  for (int i = 0; i < 6; ++i) ratio[i] = std::abs(fit.linear.eiv_bias[i]) / fit.linear.se[i];
  const MultiBounceCoeffs residual = residualBias(fit);
  out["eiv_bias"] = {
      {"method",
       "SIMEX with the sweep's own noise: fits at noise variance v = 1 (full), 2 (halves), 3 "
       "(full +- sqrt(2)(H0-H1)/2), quadratic extrapolation to v = 0; bias = fit(full) - "
       "extrapolation; linear_split_half = the two-point estimate mean(fit(H0),fit(H1)) - "
       "fit(full)"},
      {"corrected", fit.eiv_corrected},
      {"linear", coeffsJson(fit.linear.eiv_bias)},
      {"linear_split_half", coeffsJson(fit.linear.eiv_bias_linear)},
      {"linear_ratio_to_se", coeffsJson(ratio)},
      {"max_ratio_to_se", maxRatio(fit.linear.eiv_bias, fit.linear.se)},
      {"residual_bound", coeffsJson(residual)},
      {"max_residual_ratio_to_se", maxRatio(residual, fit.linear.se)},
      {"per_albedo", bias_rows}};
  json scenes = json::array();
  for (const SweepScene& s : data.scenes) scenes.push_back(s.name);
  out["sweep"] = {{"dir", relativePath(data.dir, fs::absolute(json_path).parent_path())},
                  {"spp", data.spp},
                  {"bounces", data.bounces},
                  {"scenes", scenes},
                  {"points", data.points()}};
  out["version"] = GTBAKE_VERSION;
  return out;
}

void printErrorTables(const ErrorTable& left, const ErrorTable& right, const char* left_name,
                      const char* right_name) {
  std::printf("\n%-12s  %10s %10s   %10s %10s\n", "errors of G", left_name, "", right_name, "");
  std::printf("%-12s  %10s %10s   %10s %10s\n", "", "rmse", "max|e|", "rmse", "max|e|");
  for (std::size_t j = 0; j < left.per_albedo.size(); ++j) {
    std::printf("rho %-8s  %10.5f %10.5f   %10.5f %10.5f\n", left.per_albedo[j].label.c_str(),
                left.per_albedo[j].rmse, left.per_albedo[j].max_abs, right.per_albedo[j].rmse,
                right.per_albedo[j].max_abs);
  }
  for (std::size_t s = 0; s < left.per_scene.size(); ++s) {
    std::printf("%-12s  %10.5f %10.5f   %10.5f %10.5f\n", left.per_scene[s].label.c_str(),
                left.per_scene[s].rmse, left.per_scene[s].max_abs, right.per_scene[s].rmse,
                right.per_scene[s].max_abs);
  }
  std::printf("%-12s  %10.5f %10.5f   %10.5f %10.5f\n", "all", left.rmse, left.max_abs, right.rmse,
              right.max_abs);
}

void printSummary(const SweepData& data, const MultiBounceFit& fit,
                  const MultiBounceCoeffs& shipped, const ErrorTable& refit_errors,
                  const ErrorTable& shipped_errors, const CurveDifference& diff) {
  std::printf("fit: %zu scenes, %zu points, spp %d, %d bounces, EIV correction %s\n",
              data.scenes.size(), data.points(), data.spp, data.bounces,
              fit.eiv_corrected ? "on" : "off");
  const MultiBounceCoeffs residual = residualBias(fit);
  std::printf("\n%-5s %10s %9s %10s %8s %10s %8s %8s\n", "coef", "refit", "SE", "shipped",
              "diff/SE", "EIV bias", "bias/SE", "left/SE");
  for (int i = 0; i < 6; ++i) {
    const double se = fit.linear.se[i];
    std::printf("%-5s %10.4f %9.5f %10.4f %8.1f %+10.5f %8.2f %8.3f\n", kCoeffNames[i],
                fit.linear.coeffs[i], se, shipped[i], (fit.linear.coeffs[i] - shipped[i]) / se,
                fit.linear.eiv_bias[i], std::abs(fit.linear.eiv_bias[i]) / se, residual[i] / se);
  }
  std::printf(
      "SE: Monte Carlo (a rerun with another seed); EIV bias: measured bias of the "
      "uncorrected fit; left: bias remaining in the reported value\n");
  std::printf("\n%-5s %17s %17s %17s %9s %9s\n", "rho", "a +- SE", "b +- SE", "c +- SE", "rmse",
              "max|e|");
  for (const AlbedoFit& f : fit.per_albedo) {
    std::printf("%-5.2f %9.4f+-%6.4f %9.4f+-%6.4f %9.4f+-%6.4f %9.5f %9.5f\n", f.rho, f.theta[0],
                f.se[0], f.theta[1], f.se[1], f.theta[2], f.se[2], f.rmse, f.max_abs);
  }
  printErrorTables(refit_errors, shipped_errors, "refit", "shipped");
  std::printf("\nmax |G_refit - G_shipped| = %.5f at A = %.3f, rho = %.3f\n", diff.value, diff.A,
              diff.rho);
}

void printSceneMix(const std::vector<SceneMixRow>& mix) {
  if (mix.empty()) return;
  std::printf("\nleave one scene out   %8s %8s %8s   %-22s %-22s\n", "a1", "b1", "c1",
              "max|dG| vs refit", "max|dG| vs shipped");
  for (const SceneMixRow& r : mix) {
    std::printf("  %-19s %8.4f %8.4f %8.4f   %.4f (A %.2f, rho %.1f)   %.4f (A %.2f, rho %.1f)\n",
                r.left_out.c_str(), r.linear[0], r.linear[2], r.linear[4], r.vs_refit.value,
                r.vs_refit.A, r.vs_refit.rho, r.vs_shipped.value, r.vs_shipped.A, r.vs_shipped.rho);
  }
}

struct Scored {
  SweepData data;
  MultiBounceFit fit;
  ErrorTable refit_errors;
  ErrorTable other_errors;
  CurveDifference diff;
};

Scored loadAndScore(const fs::path& sweep, const MultiBounceCoeffs& other, bool eiv_correction,
                    bool progress) {
  requireFiniteCoeffs(other, "shipped constants");
  Progress bar("fit", 4, progress);
  Scored s{loadSweep(sweep), {}, {}, {}, {}};
  bar.add(1);
  s.fit = fitMultiBounce(s.data, eiv_correction);
  bar.add(1);
  s.refit_errors = errorTable(s.data, s.fit.linear.coeffs);
  s.other_errors = errorTable(s.data, other);
  s.diff = maxCurveDifference(s.fit.linear.coeffs, other);
  bar.add(2);
  return s;
}

}  // namespace

FitResult runFit(const FitOptions& options) {
  if (options.out.empty()) throw Error("fit: no output file given (--out FILE.json)");
  std::vector<fs::path> inputs = outputSetPaths(options.sweep, "sweep");
  inputs.push_back(options.sweep / "sweep.json");
  checkOutputFile(options.out, "--out", inputs);
  const Scored s =
      loadAndScore(options.sweep, options.shipped, options.eiv_correction, options.progress);
  const fs::path out_dir =
      options.out.parent_path().empty() ? fs::path(".") : options.out.parent_path();
  ensureDirectory(out_dir);
  const fs::path report_dir = options.report ? *options.report : out_dir / "report";
  const std::vector<SceneMixRow> mix =
      leaveOneSceneOut(s.data, options.eiv_correction, s.fit.linear.coeffs, options.shipped);
  writeFitReport(report_dir, {&s.data, &s.fit, options.shipped, &s.refit_errors, &s.other_errors,
                              s.diff, &mix});
  const json doc = fitJson(options.out, s.data, s.fit, options.shipped, s.refit_errors,
                           s.other_errors, s.diff, mix);
  OutputSet output(out_dir, "fit");  // export requires and verifies fit.manifest.json
  output.add(options.out.filename().string(), doc.dump(2) + "\n");
  output.commit();
  printSummary(s.data, s.fit, options.shipped, s.refit_errors, s.other_errors, s.diff);
  printSceneMix(mix);
  std::printf("wrote %s and %s\n", options.out.string().c_str(),
              (report_dir / "index.html").string().c_str());
  return {s.fit.linear.coeffs, s.fit.linear.se};
}

void runValidate(const ValidateOptions& options) {
  requireFiniteCoeffs(options.coeffs, "validate --coeffs");
  const Scored s = loadAndScore(options.sweep, options.coeffs, true, options.progress);
  std::printf("validate: %zu scenes, %zu points, spp %d, %d bounces\n", s.data.scenes.size(),
              s.data.points(), s.data.spp, s.data.bounces);
  std::printf("\n%-5s %10s %10s %9s %8s\n", "coef", "given", "refit", "SE", "diff/SE");
  for (int i = 0; i < 6; ++i) {
    std::printf("%-5s %10.4f %10.4f %9.5f %8.1f\n", kCoeffNames[i], options.coeffs[i],
                s.fit.linear.coeffs[i], s.fit.linear.se[i],
                (options.coeffs[i] - s.fit.linear.coeffs[i]) / s.fit.linear.se[i]);
  }
  printErrorTables(s.other_errors, s.refit_errors, "given", "refit");
  std::printf("\nmax |G_given - G_refit| = %.5f at A = %.3f, rho = %.3f\n", s.diff.value, s.diff.A,
              s.diff.rho);
}

}  // namespace gtbake
