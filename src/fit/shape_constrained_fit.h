// The shape-constrained profile fit (docs/profiles.md §7): Equation 10's six coefficients by
// weighted least squares over every point and albedo,
//   minimise Σ_j Σ_i w_i (G_ij − g(Â_i, ρ_j)·k)²,   g = multiBounceGradient (G is linear in k),
// subject to G(1, ρ) = 1 for every ρ (a1 − b1 + c1 = 0, a0 − b0 + c0 = 1) and dG/dÂ ≥ 0, G ≥ 0 on
// the grid of profile_shape.h. Without the inequalities its minimiser is the two-stage fit's
// (multibounce_fit.h) with the open-surface constraint: the Hessian is (Σ_j r_j r_jᵀ) ⊗ S with
// r_j = (ρ_j, 1) and S the per-albedo Gram matrix, so the one-stage solution is the lines through
// the per-albedo cubics.
//
// The equalities are eliminated (φ = (a1, a0, b1, b0), c1 = b1 − a1, c0 = 1 − a0 + b0), leaving a
// strictly convex QP in 4 unknowns with 4 × kShapeGridNodes linear inequalities, solved exactly by
// the primal active-set method (Nocedal & Wright, Numerical Optimization, Alg. 16.3) from the
// feasible start G = Â.
#pragma once

#include <array>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/normal_equations.h"
#include "fit/profile_shape.h"

namespace gtbake {

// ½ kᵀHk − mᵀk: the objective up to a constant, divided by Σ_j Σ_i w_i (a mean square / 2).
struct ProfileObjective {
  std::array<double, 36> H{};  // row-major 6 × 6
  MultiBounceCoeffs m{};
  double value(const MultiBounceCoeffs& k) const;
};

// The objective from level 0 of the fit's sums (normal_equations.h) and the sweep's albedos.
ProfileObjective profileObjective(const NormalEquations& sums, const std::vector<double>& albedos);

// The minimiser under the shape constraints, checked on a grid of `nodes` values of Â. Every
// iterate is feasible; if the active-set iteration has not terminated after 2 iterations per
// constraint, the last (feasible, no worse than any before it) iterate is returned and
// *converged (when given) is false.
MultiBounceCoeffs solveShapeConstrained(const ProfileObjective& objective,
                                        int nodes = kShapeGridNodes, bool* converged = nullptr);

}  // namespace gtbake
