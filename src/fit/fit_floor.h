// The floor of any fit: how small the error of the best possible function of (A, ρ) alone is on
// the same data (docs/fit.md §7).
//
// For each albedo the best function of A in mean square is the conditional mean m(A) = E[G | A].
// It is estimated by the mean Ḡ_b of G in kFloorBins equal bins of the full estimate's A, and the
// floor is the residual scatter about it with the small-sample correction of the in-sample means
// (each occupied bin spends one degree of freedom):
//   floor_ρ² = Σ_b Σ_{i∈b} (G_i − Ḡ_b)² / (n − B),   B = occupied bins.
// Binning adds at most the within-bin variation of m, (max |m'|·h)²/12 with h = 1/kFloorBins
// (≈ 9e-7 for |m'| ≤ 3.3, against floor² ~ 1e-3). Per scene: that scene's squared residuals about
// the pooled bin means over all albedos, with the same dof share n/(n − B); the pooled m is not the
// best function for a single scene, so a scene's row can exceed Eq. 10's.
#pragma once

#include <string>
#include <vector>

#include "fit/sweep_data.h"

namespace gtbake {

inline constexpr int kFloorBins = 1024;

struct FloorRow {
  std::string label;  // albedo "0.10" or scene name
  double rho = 0.0;   // per-albedo rows only
  double floor = 0.0;
};

struct FitFloor {
  double rmse = 0.0;  // over every point and albedo
  std::vector<FloorRow> per_albedo;
  std::vector<FloorRow> per_scene;
};

FitFloor fitFloor(const SweepData& data);

}  // namespace gtbake
