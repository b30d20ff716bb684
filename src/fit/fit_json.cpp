// fit.json: stable keys read by `export` (linear, linear_se, errors, shipped, sweep, version) and
// by the docs markers (docs/fit.md §8 lists every key).
#include <algorithm>
#include <cmath>

#include "common/atomic_file.h"
#include "fit/fit_outputs.h"
#include "fit/validate_output.h"
#include "gtbake_version.h"

namespace gtbake {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json coeffsJson(const MultiBounceCoeffs& k) {
  json out = json::object();
  for (int i = 0; i < 6; ++i) out[kCoeffNames[i]] = k[i];
  return out;
}

json cubicJson(const Cubic& t) {
  json out = json::object();
  for (int q = 0; q < 3; ++q) out[kCubicNames[q]] = t[q];
  return out;
}

json matrixJson(const std::array<double, 36>& m) {
  json rows = json::array();
  for (int r = 0; r < 6; ++r) {
    json row = json::array();
    for (int c = 0; c < 6; ++c) row.push_back(m[6 * r + c]);
    rows.push_back(row);
  }
  return rows;
}

json curveJson(const CurveDifference& d) {
  return {{"value", d.value}, {"A", d.A}, {"rho", d.rho}};
}

json gridJson(const GridPoint& p) {
  return {{"value", p.value}, {"A", p.A}, {"rho", p.rho}};
}

json errorJson(const ErrorTable& table) {
  json out = {{"rmse", table.rmse}, {"max_abs", table.max_abs}};
  out["per_albedo"] = json::array();
  for (const ErrorRow& row : table.per_albedo) {
    out["per_albedo"].push_back({{"rho", row.rho}, {"rmse", row.rmse}, {"max_abs", row.max_abs}});
  }
  out["per_view"] = json::array();  // one row per view (docs/scenes.md "Vocabulary")
  for (const ErrorRow& row : table.per_scene) {
    out["per_view"].push_back({{"view", row.label}, {"rmse", row.rmse}, {"max_abs", row.max_abs}});
  }
  return out;
}

double maxRatio(const MultiBounceCoeffs& values, const MultiBounceCoeffs& se) {
  double ratio = 0.0;
  for (int i = 0; i < 6; ++i) ratio = std::max(ratio, std::abs(values[i]) / se[i]);
  return ratio;
}

json perAlbedoJson(const MultiBounceFit& fit) {
  json rows = json::array();
  for (const AlbedoFit& f : fit.per_albedo) {
    rows.push_back({{"rho", f.rho},
                    {"a", f.theta[0]},
                    {"b", f.theta[1]},
                    {"c", f.theta[2]},
                    {"se", cubicJson(f.se)},
                    {"se_iid", cubicJson(f.se_iid)},
                    {"uncorrected", cubicJson(f.uncorrected)},
                    {"rmse", f.rmse},
                    {"max_abs", f.max_abs},
                    {"points", f.points}});
  }
  return rows;
}

json eivJson(const MultiBounceFit& fit) {
  const LinearFit& lin = fit.linear;
  json rows = json::array();
  for (const AlbedoFit& f : fit.per_albedo) {
    Cubic ratio;
    for (int q = 0; q < 3; ++q) ratio[q] = std::abs(f.eiv_bias[q]) / f.se[q];
    rows.push_back({{"rho", f.rho},
                    {"bias", cubicJson(f.eiv_bias)},
                    {"half_mean", cubicJson(f.half_mean)},
                    {"bias_quadratic", cubicJson(f.eiv_bias_quadratic)},
                    {"bias_two_point", cubicJson(f.eiv_bias_two_point)},
                    {"ratio_to_se", cubicJson(ratio)}});
  }
  MultiBounceCoeffs ratio, residual;
  for (int i = 0; i < 6; ++i) {
    ratio[i] = std::abs(lin.eiv_bias[i]) / lin.se[i];
    residual[i] =
        remainingBias(lin.eiv_bias[i], lin.eiv_bias_quadratic[i], fit.settings.eiv_correction);
  }
  return {{"method",
           "SIMEX with the sweep's own noise: fits at noise variance v = 1 (full), 2 (halves), 3 "
           "(full +- sqrt(2)(H0-H1)/2), 4 (full +- sqrt(3)(H0-H1)/2), cubic extrapolation to "
           "v = 0; bias = fit(full) - extrapolation; linear_quadratic: the same by quadratic "
           "extrapolation through v = 1..3; residual_bound = |linear - linear_quadratic|; "
           "linear_two_point = mean(fit(H0),fit(H1)) - fit(full)"},
          {"corrected", fit.settings.eiv_correction},
          {"a_noise_free", fit.a_noise_free},
          {"linear", coeffsJson(lin.eiv_bias)},
          {"linear_quadratic", coeffsJson(lin.eiv_bias_quadratic)},
          {"linear_two_point", coeffsJson(lin.eiv_bias_two_point)},
          {"linear_ratio_to_se", coeffsJson(ratio)},
          {"max_ratio_to_se", maxRatio(lin.eiv_bias, lin.se)},
          {"residual_bound", coeffsJson(residual)},
          {"max_residual_ratio_to_se", maxRatio(residual, lin.se)},
          {"per_albedo", rows}};
}

json jackknifeJson(const SceneJackknife& jk) {
  json rows = json::array();
  for (const LeaveOneOut& r : jk.leave_one_out) {
    rows.push_back({{"left_out", r.left_out},
                    {"linear", coeffsJson(r.linear)},
                    {"max_curve_difference_vs_refit", curveJson(r.vs_refit)},
                    {"max_curve_difference_vs_shipped", curveJson(r.vs_shipped)}});
  }
  json out = {
      {"method",
       "delete-one-" + jk.unit +
           " jackknife: Cov = (S-1)/S sum_s (k_(s) - mean)(k_(s) - "
           "mean)^T over the refits without " +
           jk.unit +
           " s (all its views; same weighting, "
           "constraint and EIV setting); band = sqrt(g^T Cov g), g = dG/dk, on A = 0.005..1 "
           "step 0.005, rho = 0.1..0.9 step 0.01"},
      {"available", jk.available},
      {"unit", jk.unit},
      {"n", jk.scenes},
      {"leave_one_out", rows},
      {"monte_carlo_band_max", gridJson(jk.mc_band_max)}};
  if (!jk.available) {
    out["message"] = jk.message;
    return out;
  }
  out["se"] = coeffsJson(jk.se);
  out["covariance"] = matrixJson(jk.covariance);
  out["correlation"] = matrixJson(jk.correlation);
  out["band_max"] = gridJson(jk.band_max);
  out["t_quantile"] = jk.pointwise_threshold;
  out["simultaneous_threshold"] = jk.threshold;
  out["pointwise_t_false_alarm_rate"] = jk.pointwise_false_alarm;
  out["range_thresholds"] = jk.range_thresholds;
  out["ranges_of_A"] = jk.rule.ranges;
  return out;
}

json scoreJson(const BandScore& s) {
  return {{"max_ratio_to_band", s.max_ratio.value},
          {"A", s.max_ratio.A},
          {"rho", s.max_ratio.rho},
          {"shipped_minus_refit", s.difference},
          {"band", s.band},
          {"threshold", s.threshold},
          {"method", kMaxTMethod},
          {"pointwise_t_threshold", s.pointwise_threshold},
          {"scored_points", s.scored_points},
          {"excluded_points", s.excluded_points},
          {"worst_point",
           {{"A", s.max_ratio.A},
            {"rho", s.max_ratio.rho},
            {"ratio_to_band", s.max_ratio.value},
            {"detectable_difference", s.threshold * s.band}}},
          {"detectable_difference",
           {{"smallest", gridJson(s.smallest_detectable)},
            {"largest", gridJson(s.largest_undetectable)}}},
          {"consistent", s.consistent},
          {"verdict", s.verdict}};
}

json openJson(const OpenSurface& o) {
  return {{"G1_intercept", o.intercept},
          {"G1_slope", o.slope},
          {"max_abs_G1_minus_1", o.max_deviation}};
}

json alternativesJson(const FitAnalysis& a) {
  json w = json::array();
  for (const Alternative& alt : a.weightings) {
    w.push_back({{"weighting", alt.name},
                 {"linear", coeffsJson(alt.linear)},
                 {"max_curve_difference_vs_pixel", curveJson(alt.vs_default)},
                 {"rmse", alt.rmse}});
  }
  return w;
}

json floorJson(const FitAnalysis& a) {
  json albedos = json::array();
  for (std::size_t j = 0; j < a.floor.per_albedo.size(); ++j) {
    albedos.push_back({{"rho", a.floor.per_albedo[j].rho},
                       {"floor", a.floor.per_albedo[j].floor},
                       {"eq10_rmse", a.refit_errors.per_albedo[j].rmse}});
  }
  json views = json::array();
  for (std::size_t s = 0; s < a.floor.per_scene.size(); ++s) {
    views.push_back({{"view", a.floor.per_scene[s].label},
                     {"floor", a.floor.per_scene[s].floor},
                     {"eq10_rmse", a.refit_errors.per_scene[s].rmse}});
  }
  return {{"method",
           "RMSE about the conditional mean of G in 1024 equal bins of A per albedo, divided by "
           "n - occupied bins (the best function of (A, rho) alone)"},
          {"bins", kFloorBins},
          {"rmse", a.floor.rmse},
          {"eq10_rmse", a.refit_errors.rmse},
          {"floor_share_of_eq10_mse",
           a.floor.rmse * a.floor.rmse / (a.refit_errors.rmse * a.refit_errors.rmse)},
          {"per_albedo", albedos},
          {"per_view", views}};
}

// The shape checks, adequacy, monotone table and gate of an engine profile (docs/profiles.md
// §7-§9).
json profileJson(const ProfileChecks& p, bool solver_converged) {
  const ShapeChecks& s = p.shape;
  json rows = json::array();
  for (std::size_t j = 0; j < p.table.table.rhos.size(); ++j) {
    const auto begin = p.table.table.values.begin() + static_cast<std::ptrdiff_t>(j * kTableNodes);
    rows.push_back(std::vector<double>(begin, begin + kTableNodes));
  }
  json table = {{"needed", !p.adequate},
                {"A_nodes", kTableNodes},
                {"rho", p.table.table.rhos},
                {"values", rows},
                {"rmse", p.table.rmse}};
  if (p.table.held_out) table["held_out_by_scene_rmse"] = p.table.held_out_rmse;
  return {{"solver",
           {{"method", "primal active set, exact on the 4-unknown QP (docs/profiles.md §7)"},
            {"converged", solver_converged}}},
          {"shape",
           {{"grid", {{"A_nodes", kShapeGridNodes}, {"rho", kShapeRhos}}},
            {"min_dG_dA", s.min_slope},
            {"min_dG_dA_at", {{"A", s.min_slope_A}, {"rho", s.min_slope_rho}}},
            {"G1_max_abs_deviation", s.open_max_deviation},
            {"min_G", s.min_G},
            {"monotone", s.monotone},
            {"open", s.open},
            {"nonnegative", s.nonnegative},
            {"tolerances", {{"G1", kOpenTolerance}, {"slope_and_G", kShapeTolerance}}}}},
          {"adequacy",
           {{"cubic_rmse", p.cubic_rmse},
            {"floor_rmse", p.floor_rmse},
            {"ratio", p.ratio},
            {"threshold", kAdequacyRatio},
            {"adequate", p.adequate}}},
          {"table", table},
          {"gate", {{"shipped", p.gate.shipped}, {"reason", p.gate.reason}}}};
}

// The constraint's alternative, and a profile's setting and checks (absent from the ray-traced
// fit.json, whose shape_constrained is false).
void addConstraintJson(const FitAnalysis& a, json& out) {
  json alternative = {{"linear", coeffsJson(a.constraint.linear)},
                      {"rmse", a.constraint.rmse},
                      {"rmse_cost_of_constraint", constraintCost(a)},
                      {"max_curve_difference_vs_refit", curveJson(a.constraint.vs_default)},
                      {"open_surface", openJson(openSurface(a.constraint.linear))}};
  if (a.fit.settings.shape_constrained) {
    out["settings"]["shape_constrained"] = true;
    out["unconstrained_alternative"] = alternative;
    out["profile"] = profileJson(*a.profile, a.fit.linear.solver_converged);
  } else {
    alternative["constrain_open"] = !a.fit.settings.constrain_open;
    out["constrain_open_alternative"] = alternative;
  }
}

// What the fit's A was: the sweep's ray-traced A, or a screen-space estimator's Â (a profile).
json inputJson(const AoInput& input, const fs::path& base) {
  if (input.rayTraced()) return {{"A", "ray-traced"}};
  return {{"A", "screen-space"},
          {"estimator", input.estimator},
          {"screen_ao", relativePath(input.screen_ao, base)}};
}

}  // namespace

json fitJson(const fs::path& json_path, const FitAnalysis& a, const MultiBounceCoeffs& shipped,
             const ValidateReport& shipped_report) {
  const MultiBounceFit& fit = a.fit;
  json out;
  out["settings"] = {{"weighting", weightingName(fit.settings.weighting)},
                     {"constrain_open", fit.settings.constrain_open},
                     {"eiv_correction", fit.settings.eiv_correction}};
  out["per_albedo"] = perAlbedoJson(fit);
  out["linear"] = coeffsJson(fit.linear.coeffs);
  out["linear_se"] = coeffsJson(fit.linear.se);
  out["linear_uncorrected"] = coeffsJson(fit.linear.uncorrected);
  out["se_definition"] =
      "linear_se and per_albedo se: Monte Carlo (another seed, same pixels), a sandwich "
      "C (sum w^2 psi psi^T) C with C = Ceres covariance (J^T J)^-1 and psi from half-sample "
      "differences (noise in G, in A and their correlation), propagated through the lines with "
      "the full cross-albedo covariance; se_iid = Ceres covariance x sum w r^2/(n-N). The "
      "scene-level uncertainty is scene_jackknife";
  out["scene_jackknife"] = jackknifeJson(a.jackknife);
  out["scene_jackknife"]["scenes"] = a.jackknife.scenes;
  out["type_jackknife"] = jackknifeJson(a.type_jackknife);
  out["rho_line_lack_of_fit"] = {
      {"meaning",
       "residuals of the per-albedo a, b, c about their lines in rho: model error of the "
       "linear-in-rho law, not an uncertainty of the coefficients"},
      {"rms", cubicJson(fit.linear.lack_of_fit_rms)},
      {"max_abs", cubicJson(fit.linear.lack_of_fit_max)}};
  out["open_surface"] = openJson(a.open_surface);
  addConstraintJson(a, out);
  out["weighting_alternatives"] = alternativesJson(a);
  json weights = json::array();
  for (const ViewWeight& w : a.view_weights) {
    weights.push_back({{"view", w.scene}, {"points", w.points}, {"weight_share", w.share}});
  }
  out["view_weights"] = weights;
  out["floor"] = floorJson(a);
  out["errors"] = {{"refit", errorJson(a.refit_errors)}, {"shipped", errorJson(a.shipped_errors)}};
  if (a.held_out_errors) {
    out["errors"]["held_out_by_scene"] = errorJson(*a.held_out_errors);
    // Positive: the refit beats the shipped constants on scenes it was not fitted on.
    out["errors"]["shipped_minus_held_out_rmse"] = a.shipped_errors.rmse - a.held_out_errors->rmse;
  }
  // What G is (docs/sweep.md "Near-field truth"), and beside near-field errors the unbounded ones.
  out["truth"] = a.truth_radius ? json{{"kind", "near-field"}, {"radius", *a.truth_radius}}
                                : json{{"kind", "unbounded"}, {"radius", nullptr}};
  if (a.unbounded) {
    out["errors"]["unbounded_truth"] = {{"shipped_rmse", a.unbounded->shipped_rmse},
                                        {"refit_rmse", a.unbounded->refit_rmse}};
  }
  out["shipped"] = {{"coeffs", coeffsJson(shipped)},
                    {"max_curve_difference",
                     {{"value", a.shipped_difference.value},
                      {"A", a.shipped_difference.A},
                      {"rho", a.shipped_difference.rho},
                      {"refit_minus_shipped", a.shipped_difference.signed_value}}},
                    {"against_band", scoreJson(a.shipped_score)}};
  // The verdict by range of A and the pixel-weighted difference (docs/fit.md §5, §10).
  out["shipped"]["verdict"] = json::parse(curveVerdictJson(shipped_report.verdict).dump());
  out["shipped"]["pixel_rms_difference"] = {
      {"value", shipped_report.rms_difference.rms},
      {"scene_se", shipped_report.rms_difference.se},
      {"interval_95", {shipped_report.rms_difference.lo, shipped_report.rms_difference.hi}}};
  if (a.jackknife.available) {
    MultiBounceCoeffs z;
    for (int i = 0; i < 6; ++i) z[i] = (shipped[i] - fit.linear.coeffs[i]) / a.jackknife.se[i];
    out["shipped"]["minus_refit_over_scene_se"] = coeffsJson(z);
  }
  out["eiv_bias"] = eivJson(fit);
  json scenes = json::array();
  for (const SweepScene& s : a.data.scenes) scenes.push_back(s.name);
  out["sweep"] = {{"dir", relativePath(a.data.dir, fs::absolute(json_path).parent_path())},
                  {"spp", a.data.spp},
                  {"bounces", a.data.bounces},
                  {"views", scenes},
                  {"points", a.data.points()}};
  out["input"] = inputJson(a.input, fs::absolute(json_path).parent_path());
  out["version"] = GTBAKE_VERSION;
  return out;
}

}  // namespace gtbake
