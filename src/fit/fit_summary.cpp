// The printed summaries of `fit` and `validate` (stdout; progress goes to stderr).
#include <cmath>
#include <cstdio>
#include <string>

#include "fit/fit_outputs.h"

namespace gtbake {

namespace {

std::string sceneList(const SweepData& data) {
  std::string out;
  for (const SweepScene& s : data.scenes) out += (out.empty() ? "" : ", ") + s.name;
  return out;
}

void printHeader(const char* command, const FitAnalysis& a) {
  const FitSettings& s = a.fit.settings;
  std::printf("%s: %zu views of %zu scenes of %zu types (%s), %zu points, spp %d, %d bounces\n",
              command, a.data.scenes.size(), a.jackknife.scenes, a.type_jackknife.scenes,
              sceneList(a.data).c_str(), a.data.points(), a.data.spp, a.data.bounces);
  std::printf("  weighting %s, open surface %s, EIV correction %s\n",
              weightingName(s.weighting).c_str(), s.constrain_open ? "constrained" : "free",
              s.eiv_correction ? "on" : "off");
  if (a.input.rayTraced()) {
    std::printf("  A: the sweep's ray-traced A\n");
  } else {
    std::printf("  A: the screen-space estimate of %s (%s), against path-traced G\n",
                a.input.estimator.c_str(), a.input.screen_ao.string().c_str());
  }
}

void printBand(const FitAnalysis& a, const char* name, const BandScore& score) {
  const SceneJackknife& jk = a.jackknife;
  if (jk.available) {
    std::printf(
        "\ncurve band (scene-jackknife SE of G, A in (0,1], rho in [0.1,0.9]): max %.4f at A = "
        "%.3f, rho = %.2f\n",
        jk.band_max.value, jk.band_max.A, jk.band_max.rho);
  } else {
    std::printf("\n%s\n", jk.message.c_str());
  }
  std::printf("  Monte Carlo SE of G (another seed): max %.5f at A = %.3f, rho = %.2f\n",
              jk.mc_band_max.value, jk.mc_band_max.A, jk.mc_band_max.rho);
  const SceneJackknife& types = a.type_jackknife;
  if (types.available) {
    std::printf(
        "  type-jackknife SE of G (%zu types; content unlike any type): max %.4f at A = "
        "%.3f, rho = %.2f\n",
        types.scenes, types.band_max.value, types.band_max.A, types.band_max.rho);
  }
  if (jk.available) {
    std::printf(
        "  smallest curve difference the verdict detects everywhere (threshold %.2f x "
        "band): %.4f at A = %.3f, rho = %.2f\n",
        score.threshold, score.largest_undetectable.value, score.largest_undetectable.A,
        score.largest_undetectable.rho);
  }
  std::printf("%s constants over the whole grid: %s\n", name, score.verdict.c_str());
}

// The header, the band and the verdict on `other` (the shipped or given constants).
void printVerdict(const char* command, const FitAnalysis& a, const char* other) {
  printHeader(command, a);
  printBand(a, other, a.shipped_score);
  std::printf("  max |G_refit - G_%s| = %.5f at A = %.3f, rho = %.3f\n", other,
              a.shipped_difference.value, a.shipped_difference.A, a.shipped_difference.rho);
}

// RMSE of G: the refit on every scene, the refit held out by scene, and `other`'s constants.
void printHeldOut(const FitAnalysis& a, const char* other) {
  if (!a.held_out_errors) return;
  std::printf(
      "\nRMSE of G: refit %.5f, refit held out by scene (each scene scored by the fit without "
      "it) %.5f, %s %.5f\n",
      a.refit_errors.rmse, a.held_out_errors->rmse, other, a.shipped_errors.rmse);
}

void printCoefficients(const FitAnalysis& a, const MultiBounceCoeffs& other, const char* name) {
  const LinearFit& lin = a.fit.linear;
  const SceneJackknife& jk = a.jackknife;
  std::printf("\n%-4s %9s %9s %9s %9s %12s %10s %8s\n", "coef", "refit", "SE scene", "SE MC", name,
              "diff/SEscene", "EIV bias", "left/SE");
  for (int i = 0; i < 6; ++i) {
    const double left =
        remainingBias(lin.eiv_bias[i], lin.eiv_bias_quadratic[i], a.fit.settings.eiv_correction);
    char ratio[16] = "-";
    if (jk.available)
      std::snprintf(ratio, sizeof(ratio), "%.1f", (other[i] - lin.coeffs[i]) / jk.se[i]);
    std::printf("%-4s %9.4f %9.4f %9.5f %9.4f %12s %+10.5f %8.3f\n", kCoeffNames[i], lin.coeffs[i],
                jk.se[i], lin.se[i], other[i], ratio, lin.eiv_bias[i], left / lin.se[i]);
  }
  std::printf(
      "SE scene: delete-one-scene jackknife (what the choice of scenes moves); SE MC: Monte "
      "Carlo (what another seed moves); EIV bias: measured bias of the uncorrected fit from noise "
      "in A; left: what remains in the reported value, in SE MC\n");
  if (jk.available) {
    std::printf("\nscene-jackknife correlation %6s %6s %6s %6s %6s %6s\n", kCoeffNames[0],
                kCoeffNames[1], kCoeffNames[2], kCoeffNames[3], kCoeffNames[4], kCoeffNames[5]);
    for (int r = 0; r < 6; ++r) {
      std::printf("  %-25s", kCoeffNames[r]);
      for (int c = 0; c < 6; ++c) std::printf(" %+6.3f", jk.correlation[6 * r + c]);
      std::printf("\n");
    }
  }
}

// The shape, adequacy and gate of an engine profile (docs/profiles.md §7-§9).
void printProfileChecks(const ProfileChecks& p) {
  std::printf(
      "shape: min dG/dA %.3g, max |G(1, rho) - 1| %.1e, min G %.3g\n"
      "adequacy: cubic RMSE %.4f, floor %.4f, ratio %.3f (%s; threshold %.2f); monotone table "
      "%dx%zu RMSE %.4f, held out %.4f\n"
      "gate: %s (%s)\n",
      p.shape.min_slope, p.shape.open_max_deviation, p.shape.min_G, p.cubic_rmse, p.floor_rmse,
      p.ratio, p.adequate ? "adequate" : "not adequate", kAdequacyRatio, kTableNodes,
      p.table.table.rhos.size(), p.table.rmse, p.table.held_out_rmse,
      p.gate.shipped ? "shipped" : "not shipped", p.gate.reason.c_str());
}

void printAlternatives(const FitAnalysis& a) {
  const OpenSurface& o = a.open_surface;
  std::printf(
      "\nG(1, rho) of the refit = %.5f %+.5f rho (an open surface gives 1; max |G - 1| "
      "%.5f)\n",
      o.intercept, o.slope, o.max_deviation);
  const double cost = constraintCost(a);
  std::printf("  %s changes the unweighted RMSE by %+.2e; the curves differ by %.4f at most\n",
              constraintName(a.fit.settings), cost, a.constraint.vs_default.value);
  if (a.profile) printProfileChecks(*a.profile);
  std::printf("\n%-8s %-34s %9s %9s %9s\n", "weights", "max |dG| vs pixel weighting", "a1", "b1",
              "RMSE");
  for (const Alternative& alt : a.weightings) {
    char moved[48] = "none (same curve)";
    if (alt.vs_default.value > 0.0) {
      std::snprintf(moved, sizeof(moved), "%.4f at A = %.3f, rho = %.2f", alt.vs_default.value,
                    alt.vs_default.A, alt.vs_default.rho);
    }
    std::printf("%-8s %-34s %9.4f %9.4f %9.5f\n", alt.name.c_str(), moved, alt.linear[0],
                alt.linear[2], alt.rmse);
  }
}

void printErrorTables(const FitAnalysis& a, const ErrorTable& left, const ErrorTable& right,
                      const char* left_name, const char* right_name) {
  std::printf("\n%-12s  %10s %10s   %10s %10s   %10s %8s %7s\n", "errors of G", left_name, "",
              right_name, "", "floor", "points", "weight");
  std::printf("%-12s  %10s %10s   %10s %10s   %10s\n", "", "rmse", "max|e|", "rmse", "max|e|",
              "rmse");
  for (std::size_t j = 0; j < left.per_albedo.size(); ++j) {
    std::printf("rho %-8s  %10.5f %10.5f   %10.5f %10.5f   %10.5f\n",
                left.per_albedo[j].label.c_str(), left.per_albedo[j].rmse,
                left.per_albedo[j].max_abs, right.per_albedo[j].rmse, right.per_albedo[j].max_abs,
                a.floor.per_albedo[j].floor);
  }
  for (std::size_t s = 0; s < left.per_scene.size(); ++s) {
    std::printf("%-12s  %10.5f %10.5f   %10.5f %10.5f   %10.5f %8zu %6.1f%%\n",
                left.per_scene[s].label.c_str(), left.per_scene[s].rmse, left.per_scene[s].max_abs,
                right.per_scene[s].rmse, right.per_scene[s].max_abs, a.floor.per_scene[s].floor,
                a.view_weights[s].points, 100.0 * a.view_weights[s].share);
  }
  std::printf("%-12s  %10.5f %10.5f   %10.5f %10.5f   %10.5f\n", "all", left.rmse, left.max_abs,
              right.rmse, right.max_abs, a.floor.rmse);
  std::printf(
      "floor: RMSE of the best function of (A, rho) alone (conditional mean in %d A bins); "
      "weight: the view's share of the fit's weight\n",
      kFloorBins);
}

void printLeaveOneOut(const FitAnalysis& a) {
  if (a.jackknife.leave_one_out.empty()) return;
  std::printf("\nleave one scene out   %8s %8s %8s   %-22s %-22s\n", "a1", "b1", "c1",
              "max|dG| vs refit", "max|dG| vs shipped");
  for (const LeaveOneOut& r : a.jackknife.leave_one_out) {
    std::printf("  %-19s %8.4f %8.4f %8.4f   %.4f (A %.2f, rho %.1f)   %.4f (A %.2f, rho %.1f)\n",
                r.left_out.c_str(), r.linear[0], r.linear[2], r.linear[4], r.vs_refit.value,
                r.vs_refit.A, r.vs_refit.rho, r.vs_shipped.value, r.vs_shipped.A, r.vs_shipped.rho);
  }
}

void printPerAlbedo(const MultiBounceFit& fit) {
  std::printf("\n%-5s %17s %17s %17s %9s %9s\n", "rho", "a +- SE MC", "b +- SE MC", "c +- SE MC",
              "rmse", "max|e|");
  for (const AlbedoFit& f : fit.per_albedo) {
    std::printf("%-5.2f %9.4f+-%6.4f %9.4f+-%6.4f %9.4f+-%6.4f %9.5f %9.5f\n", f.rho, f.theta[0],
                f.se[0], f.theta[1], f.se[1], f.theta[2], f.se[2], f.rmse, f.max_abs);
  }
  const Cubic& rms = fit.linear.lack_of_fit_rms;
  std::printf(
      "lack of fit of the lines in rho (model error, not uncertainty): rms a %.4f, b %.4f, "
      "c %.4f\n",
      rms[0], rms[1], rms[2]);
}

// The shipped constants' verdict by range of A (docs/fit.md §5).
void printRanges(const ValidateReport& r) {
  const CurveVerdict& v = r.verdict;
  for (std::size_t i = 0; i < v.ranges.size(); ++i) {
    const RangeScore& s = v.ranges[i];
    std::printf("  A in %s (%4.1f%% of pixels): %s\n", rangeLabel(v, i).c_str(),
                100.0 * s.pixel_share, s.text.c_str());
  }
  std::printf("  pixel-weighted RMS of G_shipped - G_refit: %.5f", r.rms_difference.rms);
  if (r.rms_difference.interval) {
    std::printf(" (scene-level 95%% interval %.5f .. %.5f)", r.rms_difference.lo,
                r.rms_difference.hi);
  }
  std::printf("\nshipped constants by range of A: %s\n", v.headline.c_str());
}

}  // namespace

void printFitSummary(const FitAnalysis& a, const MultiBounceCoeffs& shipped,
                     const ValidateReport& shipped_report) {
  printVerdict("fit", a, "shipped");
  printRanges(shipped_report);
  printCoefficients(a, shipped, "shipped");
  printAlternatives(a);
  printErrorTables(a, a.refit_errors, a.shipped_errors, "refit", "shipped");
  printHeldOut(a, "shipped");
  printLeaveOneOut(a);
  printPerAlbedo(a.fit);
}

}  // namespace gtbake
