// `gtbake fit` and `gtbake validate`: Equation 10 from a sweep (docs/fit.md §1, docs/index.md
// "Pipeline").
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "fit/curve_verdict.h"
#include "fit/multibounce_coeffs.h"
#include "fit/normal_equations.h"
#include "fit/screen_estimate.h"
#include "fit/sweep_data.h"

namespace gtbake {

struct FitOptions {
  std::filesystem::path sweep;                  // directory written by `gtbake sweep`
  std::filesystem::path out;                    // fit.json
  std::optional<std::filesystem::path> report;  // HTML report directory (default: beside `out`)
  bool write_report = true;                     // false: fit.json alone
  bool write_validate_data = true;  // validate_data.json beside fit.json (docs/fit.md §10)
  MultiBounceCoeffs shipped = kPaperCoeffs;  // the constants compared against the refit
  bool eiv_correction = true;  // SIMEX correction of the bias from noise in A (docs/fit.md §4)
  Weighting weighting = Weighting::kPixel;
  bool constrain_open = false;  // a − b + c = 1 for every ρ (G(1, ρ) = 1)
  AoInput input;                // ray-traced A, or a screen-space estimator's (a profile)
  bool progress = true;
  bool print_summary = true;  // false: stdout stays silent (fits run side by side in gtbake all)
  const LoadedSweeps* loaded_sweeps = nullptr;  // `sweep` already read (sweep_data.h), or none
};

struct FitResult {
  MultiBounceCoeffs linear{};
  MultiBounceCoeffs linear_se{};  // Monte Carlo (another seed, same pixels)
  MultiBounceCoeffs scene_se{};   // scene jackknife (zero without one)
  double band_max = 0.0;          // largest scene-jackknife SE of G(A, ρ)
  std::string verdict;            // the shipped constants' verdict by range of A (headline)
  double rmse = 0.0;              // of G with the refit, every point and albedo
  double held_out_rmse = 0.0;     // the same, each scene scored by the fit without it (0: none)
  double shipped_rmse = 0.0;      // of G with the shipped constants
};

// Writes fit.json and the report; prints the summary table to stdout unless told not to.
FitResult runFit(const FitOptions& options);

struct ValidateOptions {
  // Exactly one of the two: a sweep (everything recomputed from its images), or a fit's output
  // directory holding validate_data.json (luts/: no image needed, docs/fit.md §10).
  std::filesystem::path sweep;
  std::filesystem::path luts;
  MultiBounceCoeffs coeffs = kPaperCoeffs;
  Weighting weighting = Weighting::kPixel;
  AoInput input;  // ray-traced A, or a screen-space estimator's (docs/profiles.md)
  VerdictRule rule;
  std::optional<std::filesystem::path> json;  // --json FILE: the report as JSON
  bool progress = true;
};

// Prints the verdict on `coeffs` by range of A, their error table beside the refit's, and writes
// the JSON report if asked. Returns the verdict (the shell maps it to the exit code).
Verdict runValidate(const ValidateOptions& options);

}  // namespace gtbake
