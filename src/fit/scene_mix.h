// How the refit depends on the scene mix: leave one scene out, refit, compare curves.
//
// The Monte Carlo SE of the refit answers "what would another seed change"; it says nothing
// about which scenes were pooled, and the pooled points are the fit's data set (paper Section 5:
// "the combination of all points"). Refitting with each scene left out measures that dependence
// directly, in coefficients and, more meaningfully, in the curve G(A, ρ) itself.
#pragma once

#include <string>
#include <vector>

#include "fit/fit_command.h"
#include "fit/fit_errors.h"
#include "fit/sweep_data.h"

namespace gtbake {

struct SceneMixRow {
  std::string left_out;        // the scene not pooled
  MultiBounceCoeffs linear{};  // the refit without it
  CurveDifference vs_refit;    // max |G_without − G_all| over A ∈ [0,1], ρ ∈ [0.1, 0.9]
  CurveDifference vs_shipped;  // max |G_without − G_shipped|
};

// One refit per scene, with the same errors-in-variables setting as the main fit. Needs at
// least two scenes; returns no rows otherwise.
std::vector<SceneMixRow> leaveOneSceneOut(const SweepData& data, bool eiv_correction,
                                          const MultiBounceCoeffs& refit,
                                          const MultiBounceCoeffs& shipped);

// The sweep without scene `skip` (points and scene ranges re-indexed).
SweepData withoutScene(const SweepData& data, std::size_t skip);

}  // namespace gtbake
