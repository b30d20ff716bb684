// The shape an engine profile must have (docs/profiles.md §7): G(1, ρ) = 1 (an open pixel stays
// unoccluded), dG/dÂ ≥ 0 (more visibility never darkens) and G ≥ 0, for Â ∈ [0, 1] and
// ρ ∈ [0.1, 0.9]. Header-only: the fit enforces it (shape_constrained_fit.h) and export checks it
// before shipping a profile (docs/profiles.md §9), from the six coefficients alone.
//
// Both dG/dÂ = 3a(ρ)Â² − 2b(ρ)Â + c(ρ) and G are affine in ρ at fixed Â, so each is ≥ 0 on
// ρ ∈ [0.1, 0.9] iff it is at the two ends: the grid is kShapeGridNodes values of Â (step 1/1000)
// × ρ ∈ {0.1, 0.9}, exact in ρ. Between two Â nodes h apart dG/dÂ (a quadratic with second
// derivative 6a) dips at most 6|a|h²/8 = 0.75|a|·1e-6 below the smaller node value.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "common/text_format.h"
#include "fit/multibounce_coeffs.h"

namespace gtbake {

inline constexpr int kShapeGridNodes = 1001;  // Â = 0, 0.001, ..., 1
inline constexpr std::array<double, 2> kShapeRhos = {kRhoMin, kRhoMax};
// A shipped profile's tolerances: |G(1, ρ) − 1| ≤ kOpenTolerance, min dG/dÂ and min G on the grid
// ≥ −kShapeTolerance (rounding of the solver, whose constraints hold them at 0).
inline constexpr double kOpenTolerance = 1e-6;
inline constexpr double kShapeTolerance = 1e-9;

// Â of grid node `i` of `nodes`.
inline double shapeGridA(int i, int nodes = kShapeGridNodes) {
  return static_cast<double>(i) / static_cast<double>(nodes - 1);
}

// ∂(dG/dÂ)/∂k at (Â, ρ): dG/dÂ = slopeGradient · k (k = {a1, a0, b1, b0, c1, c0}).
inline MultiBounceCoeffs slopeGradient(double A, double rho) {
  return {3.0 * rho * A * A, 3.0 * A * A, -2.0 * rho * A, -2.0 * A, rho, 1.0};
}

inline double dot6(const MultiBounceCoeffs& x, const MultiBounceCoeffs& y) {
  double s = 0.0;
  for (int i = 0; i < 6; ++i) s += x[i] * y[i];
  return s;
}

struct ShapeChecks {
  double min_slope = 0.0;    // min dG/dÂ on the grid
  double min_slope_A = 0.0;  // where
  double min_slope_rho = 0.0;
  double open_max_deviation = 0.0;  // max |G(1, ρ) − 1| over ρ ∈ [0.1, 0.9]
  double min_G = 0.0;               // min G on the grid
  bool monotone = false, open = false, nonnegative = false;
  bool pass() const { return monotone && open && nonnegative; }
};

inline ShapeChecks shapeChecks(const MultiBounceCoeffs& k, int nodes = kShapeGridNodes) {
  ShapeChecks s;
  s.min_slope = INFINITY;
  s.min_G = INFINITY;
  for (int i = 0; i < nodes; ++i) {
    const double A = shapeGridA(i, nodes);
    for (double rho : kShapeRhos) {
      const double slope = dot6(slopeGradient(A, rho), k);
      if (slope < s.min_slope) {
        s.min_slope = slope;
        s.min_slope_A = A;
        s.min_slope_rho = rho;
      }
      s.min_G = std::min(s.min_G, evalMultiBounce(k, A, rho));
    }
  }
  for (double rho : kShapeRhos) {
    s.open_max_deviation =
        std::max(s.open_max_deviation, std::abs(evalMultiBounce(k, 1.0, rho) - 1.0));
  }
  s.monotone = s.min_slope >= -kShapeTolerance;
  s.open = s.open_max_deviation <= kOpenTolerance;
  s.nonnegative = s.min_G >= -kShapeTolerance;
  return s;
}

// The shipping gate (docs/profiles.md §9): a profile ships only with the shape above and a
// held-out RMSE of G below the paper's constants' on the same Â; `reason` says which test failed,
// or that both passed, with the numbers.
struct ProfileGate {
  bool shipped = false;
  std::string reason;
};

inline ProfileGate profileGate(const ShapeChecks& s, double held_out_rmse, double paper_rmse) {
  if (!s.monotone) {
    return {false, "not monotone in A: dG/dA = " + formatNumber(s.min_slope, "%.3g") +
                       " at A = " + formatNumber(s.min_slope_A, "%.3f") +
                       ", rho = " + formatNumber(s.min_slope_rho, "%.2f")};
  }
  if (!s.open) {
    return {false,
            "G(1, rho) is not 1: off by up to " + formatNumber(s.open_max_deviation, "%.3g")};
  }
  if (!s.nonnegative) return {false, "G < 0: down to " + formatNumber(s.min_G, "%.3g")};
  const std::string rmses =
      "held-out RMSE of G " + formatNumber(held_out_rmse) + ", paper's " + formatNumber(paper_rmse);
  if (!(held_out_rmse < paper_rmse))
    return {false, "does not beat the paper's constants: " + rmses};
  return {true, "monotone, G(1, rho) = 1, G >= 0, " + rmses};
}

}  // namespace gtbake
