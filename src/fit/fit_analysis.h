// Everything `fit` and `validate` compute from a sweep, in named steps (the commands only format
// it): the fit, its scene jackknife and band, the score of the shipped constants, the weighting
// and open-surface alternatives, the floor and the error tables.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "fit/fit_errors.h"
#include "fit/fit_floor.h"
#include "fit/multibounce_fit.h"
#include "fit/profile_shape.h"
#include "fit/profile_table.h"
#include "fit/scene_jackknife.h"
#include "fit/screen_estimate.h"
#include "fit/sweep_data.h"

namespace gtbake {

// G(1, ρ) = (a1 − b1 + c1)ρ + (a0 − b0 + c0): an open surface (A = 1) should give exactly 1.
struct OpenSurface {
  double intercept = 0.0;      // a0 − b0 + c0
  double slope = 0.0;          // a1 − b1 + c1
  double max_deviation = 0.0;  // max |G(1, ρ) − 1| over ρ ∈ [0.1, 0.9]
};
OpenSurface openSurface(const MultiBounceCoeffs& k);

// The same fit under another setting, against the reported one.
struct Alternative {
  std::string
      name;  // "pixel", "scene", "flat-a", "constrain-open on|off" or "shape-constrained off"
  MultiBounceCoeffs linear{};
  CurveDifference vs_default;  // max |G_alternative − G_default| (default: pixel weighting)
  double rmse = 0.0;           // unweighted RMSE of G over every point and albedo
};

// A scene's share of the fit's total weight.
struct ViewWeight {
  std::string scene;
  std::size_t points = 0;
  double share = 0.0;  // Σ_{i ∈ scene} w_i / Σ w_i
};

// An engine profile's shape, adequacy and gate (docs/profiles.md §7–§9).
struct ProfileChecks {
  ShapeChecks shape;        // of the reported coefficients
  double cubic_rmse = 0.0;  // in sample (refit_errors.rmse)
  double floor_rmse = 0.0;  // floor.rmse
  double ratio = 0.0;       // cubic_rmse / floor_rmse
  bool adequate = false;    // ratio ≤ kAdequacyRatio
  TableFit table;           // the monotone 2D table, its in-sample and held-out RMSE
  ProfileGate gate;         // the cubic's
};

// The same constants scored against the unbounded G (docs/profiles.md §1): beside a fit against
// near-field truth, what the far field no screen-space pass sees adds to its error.
struct UnboundedComparison {
  double shipped_rmse = 0.0;  // the shipped (paper's) constants
  double refit_rmse = 0.0;    // the refit (fitted against the near-field truth)
};

struct FitAnalysis {
  SweepData data;
  MultiBounceFit fit;
  SceneJackknife jackknife;       // delete-one-scene
  SceneJackknife type_jackknife;  // delete-one-type
  AoInput input;  // the A the fit read (ray-traced, or a screen-space estimator's Â)
  ErrorTable refit_errors;
  // Every view scored with the refit that left its scene out (docs/fit.md §9): the error on
  // content the constants were not fitted on. Empty without leave-one-scene-out replicas.
  std::optional<ErrorTable> held_out_errors;
  ErrorTable shipped_errors;
  CurveDifference shipped_difference;   // max |G_refit − G_shipped|
  BandScore shipped_score;              // the shipped constants against the band
  OpenSurface open_surface;             // of the refit
  std::vector<Alternative> weightings;  // pixel, view, flat-a (same constraint setting)
  Alternative constraint;               // the other constrain-open setting, same weighting
  FitFloor floor;
  std::vector<ViewWeight> view_weights;
  std::optional<ProfileChecks> profile;          // shape-constrained fits (engine profiles) only
  std::optional<double> truth_radius;            // near-field truth radius of G (none: unbounded)
  std::optional<UnboundedComparison> unbounded;  // with truth_radius only
};

// Stages of analyzeSweep, for a progress bar (kAnalysisStages units).
inline constexpr int kAnalysisStages = 7;

// `input` chooses the regressor: the sweep's A, or a screen-space estimator's Â (profiles).
// `loaded`: the sweep's images already read (sweep_data.h), used where they hold the truth needed.
FitAnalysis analyzeSweep(const std::filesystem::path& sweep, const FitSettings& settings,
                         const MultiBounceCoeffs& shipped, Progress* progress,
                         const AoInput& input = {}, const LoadedSweeps* loaded = nullptr);

// Everything after the load, on points already in memory (analyzeSweep's steps 2..7, with the
// band's grid and simultaneous rule `rule`); the tests and fuzz targets build their analyses here.
FitAnalysis analyzePoints(SweepData data, const FitSettings& settings,
                          const MultiBounceCoeffs& shipped, const BandRule& rule = {},
                          Progress* progress = nullptr);

// The steps, each testable alone.
std::vector<ViewWeight> viewWeights(const SweepData& data, const std::vector<double>& weights);
std::vector<Alternative> weightingAlternatives(const SweepData& data, const MultiBounceFit& fit);
Alternative constraintAlternative(const SweepData& data, const MultiBounceFit& fit);
std::optional<ErrorTable> heldOutErrors(const SweepData& data, const SceneJackknife& by_scene);
// Needs a's fit, errors and floor.
ProfileChecks profileChecks(const FitAnalysis& a);
// RMSE of G the constraint costs: constrained refit minus unconstrained (either order of
// fit.settings and its alternative).
double constraintCost(const FitAnalysis& a);
// The constraint of `settings` (or the one its alternative adds), as the summary names it.
const char* constraintName(const FitSettings& settings);

}  // namespace gtbake
