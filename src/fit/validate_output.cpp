// The printed summary and the JSON (--json FILE) of `validate` (docs/fit.md §10): both only format
// a ValidateReport.
#include <cstdio>

#include "fit/validate_output.h"
#include "gtbake_version.h"

namespace gtbake {

namespace {

using nlohmann::ordered_json;

void printHeader(const ValidateData& d) {
  std::printf("validate: %zu views of %zu scenes of %zu types, %zu points, spp %d, %d bounces\n",
              d.views.size(), d.scene_jackknife.scenes, d.type_jackknife.scenes, d.points(), d.spp,
              d.bounces);
  std::printf("  data: %s\n  weighting %s, open surface %s, EIV correction %s; A: %s\n",
              d.source.c_str(), weightingName(d.settings.weighting).c_str(),
              d.settings.constrain_open ? "constrained" : "free",
              d.settings.eiv_correction ? "on" : "off", d.input.c_str());
  const SceneJackknife& jk = d.scene_jackknife;
  if (jk.available) {
    std::printf("  band: scene-jackknife SE of G at most %.4f (A = %.3f, rho = %.2f)",
                jk.band_max.value, jk.band_max.A, jk.band_max.rho);
    if (d.type_jackknife.available) {
      std::printf("; type-jackknife %.4f", d.type_jackknife.band_max.value);
    }
    std::printf("; Monte Carlo (another seed) %.2g\n", jk.mc_band_max.value);
  } else {
    std::printf("  %s\n", jk.message.c_str());
  }
}

void printRanges(const ValidateReport& r) {
  const CurveVerdict& v = r.verdict;
  std::printf(
      "\npower: the smallest |dG| the verdict detects anywhere in each range of A (thresholds "
      "simultaneous at 95 %% over the ranges and their points; judged when <= %.3g)\n",
      v.rule.powerNeeded());
  std::printf("  %-11s %8s %11s %10s %8s %13s\n", "A range", "pixels", "detectable", "threshold",
              "points", "pixel RMS dG");
  for (std::size_t i = 0; i < v.ranges.size(); ++i) {
    const RangeScore& s = v.ranges[i];
    std::printf("  %-11s %7.1f%% %11.4f %10.2f %8zu %13.5f\n", rangeLabel(v, i).c_str(),
                100.0 * s.pixel_share, s.detectable.value, s.threshold, s.scored_points,
                s.pixel_rms_difference);
  }
  std::printf("\nverdict by range of A (dG = G_given - G_refit over rho in [0.1, 0.9]):\n");
  for (std::size_t i = 0; i < v.ranges.size(); ++i) {
    std::printf("  %-11s %s\n", rangeLabel(v, i).c_str(), v.ranges[i].text.c_str());
  }
  const PixelDifference& p = r.rms_difference;
  std::printf("\npixel-weighted RMS of dG over every point and albedo: %.5f", p.rms);
  if (p.interval) std::printf(" (scene-level 95 %% interval %.5f .. %.5f)", p.lo, p.hi);
  std::printf("\n");
  if (v.available) {
    const BandScore& o = v.overall;
    std::printf(
        "worst point over the whole grid: %.2f band widths at A = %.3f, rho = %.2f (dG %+.5f, "
        "band %.2g; threshold over the whole grid %.2f)\n",
        o.max_ratio.value, o.max_ratio.A, o.max_ratio.rho, o.difference, o.band, o.threshold);
  }
  std::printf("max |G_refit - G_given| = %.5f at A = %.3f, rho = %.3f\n", r.max_difference.value,
              r.max_difference.A, r.max_difference.rho);
  std::printf("\nverdict: %s\n", v.headline.c_str());
}

void printCoefficients(const ValidateReport& r, bool scene) {
  // Layout kept for scripts (tests/cli parses the first five columns).
  std::printf("\n%-5s %10s %10s %9s %12s %9s %10s\n", "coef", "given", "refit", "SE scene",
              "diff/SEscene", "SE MC", "diff/SE MC");
  for (const CoefficientRow& c : r.coefficients) {
    char ratio[16] = "-";
    if (scene) std::snprintf(ratio, sizeof ratio, "%.1f", (c.given - c.refit) / c.se_scene);
    std::printf("%-5s %10.4f %10.4f %9.4f %12s %9.5f %10.1f\n", c.name, c.given, c.refit,
                c.se_scene, ratio, c.se_monte_carlo, (c.given - c.refit) / c.se_monte_carlo);
  }
  std::printf(
      "SE scene: delete-one-scene jackknife (what the choice of scenes moves); SE MC: Monte "
      "Carlo (what another seed moves, the pixels fixed)\n");
}

void printErrors(const ValidateReport& r) {
  std::printf("\n%-14s %9s %9s %9s %9s %9s %7s\n", "RMSE of G", "given", "refit", "held out",
              "floor", "points", "weight");
  for (const RmseRow& row : r.per_albedo) {
    std::printf("rho %-10s %9.5f %9.5f %9.5f %9.5f\n", row.label.c_str(), row.given, row.refit,
                row.held_out, row.floor);
  }
  for (const RmseRow& row : r.per_view) {
    std::printf("%-14s %9.5f %9.5f %9.5f %9.5f %9.0f %6.1f%%\n", row.label.c_str(), row.given,
                row.refit, row.held_out, row.floor, row.points, 100.0 * row.weight_share);
  }
  std::printf("%-14s %9.5f %9.5f %9.5f %9.5f %9.0f\n", "all", r.all.given, r.all.refit,
              r.all.held_out, r.all.floor, r.all.points);
  std::printf(
      "held out: each view scored by the refit without its scene; floor: the best function of "
      "(A, rho) alone (docs/fit.md section 7)\n");
}

ordered_json pointJson(const GridPoint& p) {
  return {{"value", p.value}, {"A", p.A}, {"rho", p.rho}};
}

ordered_json rangeJson(const RangeScore& s) {
  ordered_json out = {{"A_range", {s.lo, s.hi}}, {"verdict", verdictName(s.verdict)}};
  out["fails"] = s.fails;
  out["pixel_share"] = s.pixel_share;
  out["pixel_rms_difference"] = s.pixel_rms_difference;
  out["max_abs_difference"] = pointJson(s.max_difference);
  out["max_abs_difference"]["given_minus_refit"] = s.signed_difference;
  out["max_ratio_to_band"] = pointJson(s.max_ratio);
  out["max_ratio_to_band"]["given_minus_refit"] = s.ratio_difference;
  out["max_ratio_to_band"]["band"] = s.ratio_band;
  out["threshold"] = s.threshold;
  out["detectable_difference"] = pointJson(s.detectable);
  out["median_band"] = s.median_band;
  out["set_near_open_limit"] = s.near_open;
  out["max_ratio_below_open_limit"] = pointJson(s.max_ratio_away);
  out["scored_points"] = s.scored_points;
  out["text"] = s.text;
  return out;
}

ordered_json coeffsJson(const MultiBounceCoeffs& k) {
  ordered_json out = ordered_json::object();
  for (int i = 0; i < 6; ++i) out[kCoeffNames[i]] = k[i];
  return out;
}

ordered_json rmseJson(const RmseRow& row) {
  return {{"label", row.label},       {"given", row.given}, {"refit", row.refit},
          {"held_out", row.held_out}, {"floor", row.floor}, {"points", row.points}};
}

// ΔG and the band over the whole domain on a coarse grid (A = 0.05..1 step 0.05, ρ = 0.1..0.9
// step 0.1), for plots: difference[i][j] and band[i][j] at A[i], rho[j].
ordered_json domainJson(const ValidateData& d, const MultiBounceCoeffs& given) {
  ordered_json out = {{"A", ordered_json::array()}, {"rho", ordered_json::array()}};
  ordered_json difference = ordered_json::array(), band = ordered_json::array();
  for (int j = 1; j <= 9; ++j) out["rho"].push_back(0.1 * j);
  for (int i = 1; i <= 20; ++i) {
    const double A = 0.05 * i;
    out["A"].push_back(A);
    ordered_json drow = ordered_json::array(), brow = ordered_json::array();
    for (int j = 1; j <= 9; ++j) {
      const double rho = 0.1 * j;
      drow.push_back(evalMultiBounce(given, A, rho) - evalMultiBounce(d.refit, A, rho));
      brow.push_back(d.scene_jackknife.available ? jackknifeBand(d.scene_jackknife, A, rho) : 0.0);
    }
    difference.push_back(drow);
    band.push_back(brow);
  }
  out["given_minus_refit"] = difference;
  out["band"] = band;
  return out;
}

}  // namespace

ordered_json curveVerdictJson(const CurveVerdict& v) {
  ordered_json out = {{"verdict", verdictName(v.verdict)}, {"headline", v.headline}};
  out["useful_power"] = v.rule.useful_power;
  out["fail_above"] = v.rule.fail_above ? ordered_json(*v.rule.fail_above) : ordered_json();
  out["ranges"] = ordered_json::array();
  for (const RangeScore& s : v.ranges) out["ranges"].push_back(rangeJson(s));
  out["worst_point"] = pointJson(v.overall.max_ratio);
  out["worst_point"]["given_minus_refit"] = v.overall.difference;
  out["worst_point"]["band"] = v.overall.band;
  out["worst_point"]["threshold_whole_grid"] = v.overall.threshold;
  return out;
}

void printValidateReport(const ValidateData& data, const ValidateReport& report) {
  printHeader(data);
  printRanges(report);
  printCoefficients(report, data.scene_jackknife.available);
  printErrors(report);
}

ordered_json validateReportJson(const ValidateData& d, const ValidateReport& r) {
  ordered_json out = {{"version", GTBAKE_VERSION}, {"data", d.source}};
  out["views"] = d.views.size();
  out["scenes"] = d.scene_jackknife.scenes;
  out["types"] = d.type_jackknife.scenes;
  out["points"] = d.points();
  out["given"] = coeffsJson(r.given);
  out["refit"] = coeffsJson(d.refit);
  out["verdict"] = curveVerdictJson(r.verdict);
  out["pixel_rms_difference"] = {{"value", r.rms_difference.rms},
                                 {"scene_se", r.rms_difference.se},
                                 {"interval_95", {r.rms_difference.lo, r.rms_difference.hi}},
                                 {"has_interval", r.rms_difference.interval}};
  out["max_curve_difference"] = {
      {"value", r.max_difference.value}, {"A", r.max_difference.A}, {"rho", r.max_difference.rho}};
  out["domain"] = domainJson(d, r.given);
  out["coefficients"] = ordered_json::array();
  for (const CoefficientRow& c : r.coefficients) {
    out["coefficients"].push_back({{"name", c.name},
                                   {"given", c.given},
                                   {"refit", c.refit},
                                   {"se_scene", c.se_scene},
                                   {"se_monte_carlo", c.se_monte_carlo}});
  }
  out["rmse"] = {{"all", rmseJson(r.all)}};
  out["rmse"]["per_albedo"] = ordered_json::array();
  for (const RmseRow& row : r.per_albedo) out["rmse"]["per_albedo"].push_back(rmseJson(row));
  out["rmse"]["per_view"] = ordered_json::array();
  for (const RmseRow& row : r.per_view) out["rmse"]["per_view"].push_back(rmseJson(row));
  return out;
}

}  // namespace gtbake
