// `gtbake tune`: which settings of an engine's screen-space AO pass minimise the error of
// multi-bounce G (Equation 10) against path tracing, with the paper's constants and with the
// profile refitted on the pass's Â, and how sure each optimum is at the scene level
// (docs/tune.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tune/tune_analysis.h"
#include "tune/tune_grid.h"

namespace gtbake {

// The radius of the near-field truth tune scores against by default: every tuned estimator's
// default radius (screen_ao_settings.h), in metres.
inline constexpr double kTuneTruthRadius = 1.0;

struct TuneOptions {
  std::filesystem::path sweep;  // a directory written by gtbake sweep (with G-buffer channels)
  std::filesystem::path out;
  std::vector<Estimator> estimators = tunedEstimators();
  std::vector<std::string> grids;  // "ESTIMATOR.KEY=v1,v2,..." replacing a default grid
  // A screen-ao set of the same sweep (empty = none): each estimator it ran at tune's defaults
  // has its default run read from it instead of run again (docs/tune.md §7).
  std::filesystem::path screen_ao;
  // The truth every value is scored against: the near-field truth at the estimators' default
  // radius (docs/tune.md §1, the radius the pass is asked to be ground truth within), or with
  // unbounded_truth the unbounded G (for comparison, or sweeps without near-field channels).
  double truth_radius = kTuneTruthRadius;
  bool unbounded_truth = false;
  // Compute the first widening step's values in each grid's pass where that costs little
  // (docs/tune.md §7); the results are the same without (which the tests compare).
  bool compute_ahead = true;
  int threads = 0;
  bool progress = true;
};

struct TuneResult {
  std::filesystem::path json;
  double seconds = 0.0;
};

// Writes <out>/tune.json and <out>/report/tune.html as one output set (tune.manifest.json) and
// prints the optima. Bad input (an unknown estimator or key, a bad grid, a sweep without G-buffer
// channels, fewer than three scenes) throws a one-line gtbake::Error with nothing written
// (TuneNotApplicable for a valid sweep that has too few scenes for the intervals).
TuneResult runTune(const TuneOptions& options);

// The grids of a run: the defaults of options.estimators with options.grids applied.
std::vector<SettingGrid> tuneGrids(const TuneOptions& options);

}  // namespace gtbake
