// How well a set of Eq. 10 constants reproduces the path-traced G (docs/fit.md §1).
//
// For constants k and every unmasked point i and albedo ρ_j the error is
//   e_ij = G_ij − G(A_i, ρ_j; k),  G(A, ρ; k) = a(ρ)A³ − b(ρ)A² + c(ρ)A,
// on the full estimate. Tables: RMSE and max |e| per albedo (over points), per scene (over its
// points and every albedo) and overall. The curve distance between two sets of constants is
// max |G(A, ρ; k1) − G(A, ρ; k2)| over A ∈ [0, 1], ρ ∈ [0.1, 0.9], found on a dense grid and
// refined locally (the difference is a cubic in A times an affine function in ρ, so it is smooth
// and the grid maximum lies within one cell of the true one).
#pragma once

#include <string>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/sweep_data.h"

namespace gtbake {

struct ErrorRow {
  std::string label;  // albedo "0.10" or scene name
  double rho = 0.0;   // per-albedo rows only
  double rmse = 0.0;
  double max_abs = 0.0;
};

struct ErrorTable {
  double rmse = 0.0;
  double max_abs = 0.0;
  std::vector<ErrorRow> per_albedo;
  std::vector<ErrorRow> per_scene;
};

ErrorTable errorTable(const SweepData& data, const MultiBounceCoeffs& coeffs);
// The same with constants per view (data.scenes[s] scored with per_view[s]): a held-out table
// scores each view with the fit that left its scene out (fit_analysis.h).
ErrorTable errorTable(const SweepData& data, const std::vector<MultiBounceCoeffs>& per_view);

struct CurveDifference {
  double value = 0.0;  // max |G1 − G2|
  double A = 0.0;      // where it occurs
  double rho = 0.0;
  double signed_value = 0.0;  // G1 − G2 there
};

CurveDifference maxCurveDifference(const MultiBounceCoeffs& k1, const MultiBounceCoeffs& k2);

// Non-finite constants are bad input; throws a one-line gtbake::Error naming the coefficient.
void requireFiniteCoeffs(const MultiBounceCoeffs& coeffs, const std::string& what);

}  // namespace gtbake
