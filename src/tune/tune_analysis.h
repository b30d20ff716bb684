// `gtbake tune`'s computation (docs/tune.md §1–§3): every grid value of every searched setting
// run on every swept image, Â put in place of A, and Eq. 10's error of G scored per scene cluster
// with the paper's constants and with the profile refitted on that Â.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/progress.h"
#include "fit/multibounce_coeffs.h"
#include "fit/multibounce_fit.h"
#include "fit/sweep_data.h"
#include "screen_ao/gbuffer.h"
#include "tune/tune_grid.h"
#include "tune/tune_optimum.h"
#include "tune/tune_statistics.h"

namespace gtbake {

// The profile's fit settings (docs/profiles.md §1): pixel weights, no constraint, no
// errors-in-variables correction (Â carries no Monte Carlo noise).
FitSettings profileFitSettings();

// The scores of one estimator run (one grid value).
struct GridValueScore {
  double value = 0.0;
  MultiBounceCoeffs refit{};                // the profile on every cluster
  std::vector<double> paper_sse;            // [cluster] SSE_c with the paper's constants
  std::vector<double> profile_sse;          // [cluster] SSE_c at the refit on every cluster
  std::vector<double> held_out_sse;         // [cluster] SSE_c at the refit without c
  std::vector<double> profile_replica_sse;  // [s] Σ_{c≠s} SSE_c at the refit without s
  double paper_rmse = 0.0, profile_rmse = 0.0, held_out_rmse = 0.0;  // pooled
};

// Scores statistics of one run: S + 1 refits (clusters in parallel, each into its own slot).
// A refit without one cluster (names: the clusters') that the others do not determine throws
// TuneNotApplicable.
GridValueScore scoreRun(const std::vector<ClusterStatistics>& stats,
                        const std::vector<std::string>& names, const std::vector<double>& albedos,
                        const FitSettings& settings);

struct SettingResult {
  SettingGrid grid;
  std::vector<GridValueScore> scores;        // [grid value]
  SceneInterval paper;                       // optimum of the paper-constants RMSE
  SceneInterval profile;                     // optimum of the profile's in-sample RMSE
  int widened_lower = 0, widened_upper = 0;  // widening steps taken at each end (§3)
};

// Where an optimum lies in the searched grid (docs/tune.md §3): inside it, or at its lower or
// upper end, which after widening is the setting's limit (or where kMaxWidenings ran out).
enum class OptimumStatus { kInterior, kLowerBound, kUpperBound };
struct OptimumPlace {
  OptimumStatus status = OptimumStatus::kInterior;
  SettingLimit limit;  // at a bound: the end's value and why the search stopped there
};
OptimumPlace optimumPlace(const SettingResult& r, const SceneInterval& o);
// "interior", "lower_bound", "upper_bound".
const char* statusName(OptimumStatus status);

// The objective curves of a setting: [grid value] pooled RMSE and [s][grid value] without s.
struct ObjectiveCurves {
  std::vector<double> pooled;
  std::vector<std::vector<double>> replicas;
};
// paper: the paper's constants (a replica drops scene s's squared error); else the profile
// (a replica is refitted without s).
ObjectiveCurves objectiveCurves(const SettingResult& r, const std::vector<std::size_t>& points,
                                std::size_t albedos, bool paper);

struct TuneAnalysis {
  std::vector<std::string> clusters;
  std::vector<std::size_t> cluster_points;  // [cluster] unmasked pixels
  std::size_t points = 0;
  std::vector<double> albedos;
  std::string sweep_version;           // sweep.json's gtbake_version
  std::optional<double> truth_radius;  // near-field truth radius scored against; none: unbounded
  std::vector<SettingResult> settings;
  std::size_t estimator_runs = 0;
  std::vector<std::pair<std::string, double>> part_seconds;
};

// Scores `values` of the grids group[first .. first + count) ([grid][value]), count 2 when the
// two bitmasks widen alike and share a pass.
using WidenRun = std::function<std::vector<std::vector<GridValueScore>>(
    std::size_t first, std::size_t count, const std::vector<double>& values)>;
// Finds the optima of the group's settings (one, or both bitmasks' thickness) and widens each grid
// (docs/tune.md §3): while an optimum of either objective, pooled or a replica's, sits at an end
// that is not the setting's limit and that end has widened fewer than kMaxWidenings times, the
// value widenedEnd gives is scored by `run` and added, and the optima found again.
void widenGroup(std::vector<SettingResult>* group, const TuneAnalysis& a, const WidenRun& run);

// The sweep is valid but cannot be tuned: fewer than kMinJackknifeScenes scene clusters, or a
// refit without one of them that the others do not determine (no scene-level interval). A
// gtbake::Error like any other; `gtbake all` skips the stage on it (a user's one or two scenes).
class TuneNotApplicable : public Error {
 public:
  using Error::Error;
};

// Reads the sweep (loadSweep for G, readSweepImages for the G-buffer), scores every grid and
// widens it (docs/tune.md §3). With `screen_ao` (a screen-ao set of this sweep; empty = none),
// each estimator it ran at tune's defaults has its default run read from it, not run again.
// Scores against the truth at truth_radius (none: the unbounded G). With compute_ahead, each pass
// also computes the values its first widening step could add where that costs little, so the step
// runs no pass of its own (docs/tune.md §7); the results are the same without. Throws a one-line
// gtbake::Error on a sweep without G-buffer channels or without that radius's truth,
// TuneNotApplicable with fewer than kMinJackknifeScenes clusters (before any estimator runs).
TuneAnalysis analyzeTune(const std::filesystem::path& sweep, const std::vector<SettingGrid>& grids,
                         bool progress, const std::filesystem::path& screen_ao = {},
                         std::optional<double> truth_radius = std::nullopt,
                         bool compute_ahead = true);

// Puts the estimate of every image in place of A in data.full (unmasked pixels in point order,
// clamped within kEstimateRounding of [0, 1]; farther is a one-line error).
void useEstimates(SweepData* data, const std::vector<SweepImage>& images,
                  const std::vector<std::vector<float>>& estimates, const std::string& estimator);

}  // namespace gtbake
