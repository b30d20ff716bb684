// What `validate` reports for one set of constants, computed from ValidateData alone
// (validate_data.h), so that `validate --sweep` and `validate --luts` give the same answer
// (docs/fit.md §10).
#pragma once

#include <string>
#include <vector>

#include "fit/curve_verdict.h"
#include "fit/fit_errors.h"
#include "fit/validate_data.h"

namespace gtbake {

// The pixel-weighted RMS of ΔG = G_given − G_refit over every point and the sweep's albedos, and
// its scene-level interval: the delete-one-scene jackknife (each replica drops a scene's points
// and uses the refit without it), value ± t_{0.975, S−1} · SE, clamped at 0.
struct PixelDifference {
  double rms = 0.0;
  double se = 0.0;  // scene jackknife (0 without one)
  double lo = 0.0, hi = 0.0;
  bool interval = false;  // false without a scene jackknife
};

// RMSE of G for the given constants, the refit, and the refit held out by scene (each view scored
// by the refit without its scene), beside the floor.
struct RmseRow {
  std::string label;  // "0.10" (an albedo), a view's name, or "all"
  double given = 0.0;
  double refit = 0.0;
  double held_out = 0.0;  // 0 without a scene jackknife
  double floor = 0.0;
  double points = 0.0;
  double weight_share = 0.0;  // views only
};

struct CoefficientRow {
  const char* name = "";
  double given = 0.0;
  double refit = 0.0;
  double se_scene = 0.0;  // 0 without a scene jackknife
  double se_monte_carlo = 0.0;
};

struct ValidateReport {
  MultiBounceCoeffs given{};
  CurveVerdict verdict;  // with each range's pixel share and RMS difference filled in
  PixelDifference rms_difference;
  CurveDifference max_difference;  // max |G_refit − G_given| over A ∈ [0,1], ρ ∈ [0.1, 0.9]
  std::vector<CoefficientRow> coefficients;
  std::vector<RmseRow> per_albedo;
  std::vector<RmseRow> per_view;
  RmseRow all;
};

ValidateReport validateReport(const ValidateData& data, const MultiBounceCoeffs& given,
                              const VerdictRule& rule = {});

}  // namespace gtbake
