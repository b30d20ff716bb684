// Linear least squares through Ceres, the one place the fit talks to the solver.
//
// Every problem of the fit is linear in its parameters: minimise ‖M φ − y‖² with M dense m × N.
// Stage 1 hands Ceres the reduced problem of its normal equations (M = R, y = R⁻ᵀ Xᵀy with
// XᵀX = RᵀR, so the N × N problem has the same minimiser and the same (JᵀJ)⁻¹ as the n × N one);
// stage 2 hands it the lines in ρ directly (M rows (ρ_j, 1)).
#pragma once

#include <string>
#include <vector>

namespace gtbake {

struct LinearSolve {
  std::vector<double> phi;              // the minimiser, N values
  std::vector<double> unit_covariance;  // (MᵀM)⁻¹ from ceres::Covariance, row-major N × N
};

// `M` is row-major m × N, `y` has m values. Throws a one-line gtbake::Error naming `what` when
// Ceres does not converge or (with covariance) the problem is rank-deficient.
LinearSolve solveLinear(const std::vector<double>& M, const std::vector<double>& y, int N,
                        bool with_covariance, const std::string& what);

}  // namespace gtbake
