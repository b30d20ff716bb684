// The multi-bounce fit of paper Section 5, Equation 10 (docs/fit.md §1), in two Ceres stages.
//
// Stage 1, per albedo ρ: weighted least squares over every unmasked point i of every scene of
//   G_i ≈ a·A_i³ − b·A_i² + c·A_i            (θ = (a, b, c), regressors x_i = (A_i³, −A_i², A_i)),
// solved from the sums of normal_equations.h (a 3 × 3 reduced problem per albedo, or 2 × 2 with
// the open-surface constraint a − b + c = 1).
// Stage 2, per coefficient q ∈ {a, b, c}: least squares over the albedos of q(ρ) ≈ q1·ρ + q0.
// With the constraint every albedo has a − b + c = 1, and the lines are linear in the data, so
// a(ρ) − b(ρ) + c(ρ) = 1 for every ρ too (a1 − b1 + c1 = 0, a0 − b0 + c0 = 1).
//
// Monte Carlo standard errors (docs/fit.md §3): the scenes and pixels fixed, the walks random.
// To first order φ̂ − φ = C Σ_i w_i Tᵀψ_i with C = (TᵀSwT)⁻¹ (= Ceres' covariance of the reduced
// problem) and the influence
//   ψ_i = x_i δG_i + (x_i' r_i − x_i f'(A_i)) δA_i        (r_i the residual, f the cubic),
// which counts noise in G, noise in the regressor A and their correlation. δ_i is estimated per
// point from the two half-sample estimates, δ_i = (h0_i − h1_i)/2 (E δ_i² = Var of the full mean),
// so Cov(φ̂) = C (Σ w_i² Tᵀψ_i ψ_iᵀT) C — a sandwich with known per-point variance. `se` is that;
// `se_iid` is Ceres' covariance scaled by σ̂² = Σ w r²/(n − N). Stage 2 is linear in the stage-1
// coefficients, so its covariance propagates the full cross-albedo covariance exactly.
// The scene-level uncertainty (what the choice of scenes moves) is scene_jackknife.h.
//
// Errors in variables (docs/fit.md §6): noise in A biases θ̂ by β·v + γ·v² + … in the noise
// variance v (v = 1 for the full estimate). With d_i = (h0_i − h1_i)/2 (same variance as the
// full estimate's noise, uncorrelated with it) the sets full + c·d, c ∈ {±1, ±√2, ±√3}, have
// v = 2, 3, 4; θ̂(v) through v = 1, 2, 3, 4 is extrapolated as a cubic to v = 0 (SIMEX with the
// sweep's own noise): θ0 = 4θ1 − 6θ2 + 4θ3 − θ4. With `eiv_correction` the reported θ is θ0; its
// first-order noise equals θ̂_full's (the ±c pairs cancel d), so the SE applies to it unchanged.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/normal_equations.h"
#include "fit/sweep_data.h"

namespace gtbake {

struct FitSettings {
  bool eiv_correction = true;
  Weighting weighting = Weighting::kPixel;
  bool constrain_open = false;  // a − b + c = 1 for every ρ: an open surface has G(1, ρ) = 1
  // The six by the shape-constrained QP of shape_constrained_fit.h (G(1, ρ) = 1, dG/dA ≥ 0,
  // G ≥ 0) on the full estimate's sums, in place of the lines (engine profiles,
  // docs/profiles.md §7); the per-albedo cubics stay unconstrained.
  bool shape_constrained = false;
};

struct AlbedoFit {
  double rho = 0.0;
  Cubic theta{};               // reported coefficients (EIV-corrected when the correction is on)
  Cubic se{};                  // Monte Carlo sandwich SE (see above)
  Cubic se_iid{};              // Ceres covariance × Σ w r²/(n − N)
  Cubic uncorrected{};         // θ̂ on the full estimate
  Cubic half_mean{};           // mean of θ̂ on the two halves
  Cubic eiv_bias{};            // measured bias of θ̂_full (cubic extrapolation in v)
  Cubic eiv_bias_quadratic{};  // the same by quadratic extrapolation through v = 1..3
  Cubic eiv_bias_two_point{};  // the two-point estimate from the halves: half_mean − uncorrected
  double rmse = 0.0;           // of `theta` against the full-estimate points, unweighted
  double max_abs = 0.0;
  std::size_t points = 0;
};

struct LinearFit {
  MultiBounceCoeffs coeffs{};              // lines through the reported per-albedo θ
  MultiBounceCoeffs se{};                  // Monte Carlo SE (sqrt of mc_covariance's diagonal)
  std::array<double, 36> mc_covariance{};  // Monte Carlo covariance, row-major 6 × 6
  MultiBounceCoeffs uncorrected{};         // the same lines through the uncorrected θ̂_full
  MultiBounceCoeffs eiv_bias{};            // lines through the per-albedo biases
  MultiBounceCoeffs eiv_bias_quadratic{};  // lines through the quadratic-extrapolation biases
  MultiBounceCoeffs eiv_bias_two_point{};  // lines through the two-point biases
  // Lack of fit of "linear in ρ": RMS and max |residual| of a(ρ), b(ρ), c(ρ) about their lines.
  // Model error of the law, not an uncertainty of the six numbers.
  Cubic lack_of_fit_rms{};
  Cubic lack_of_fit_max{};
  // Shape-constrained only: whether the active-set solver terminated at the constrained minimum
  // (false: its last feasible iterate; shape_constrained_fit.h).
  bool solver_converged = true;
};

struct MultiBounceFit {
  FitSettings settings;
  std::vector<AlbedoFit> per_albedo;
  LinearFit linear;
  bool a_noise_free = false;  // every point's halves equal its full A: no errors-in-variables bias
  std::vector<double> weights;               // per point, mean 1
  std::vector<LevelStatistics> scene_stats;  // [scene] the sums the fit was solved from
};

// What remains of the errors-in-variables bias in a reported coefficient (docs/fit.md §6): with
// the correction the gap between the cubic and the quadratic extrapolations (it bounds what the
// cubic leaves), without it the whole measured bias.
double remainingBias(double bias, double bias_quadratic, bool corrected);

// Stage 1 and 2 coefficients from summed statistics, no standard errors: a refit on any union of
// scenes (the jackknife's replicas) costs ~40 Ceres solves of 2 or 3 parameters.
MultiBounceCoeffs coefficientsFromStatistics(const LevelStatistics& sums,
                                             const std::vector<double>& albedos,
                                             const FitSettings& settings);

// The full fit: weights, per-scene statistics, both stages, Monte Carlo SEs, per-albedo errors.
MultiBounceFit fitMultiBounce(const SweepData& data, const FitSettings& settings = {});

// One cubic fit of raw points with unit weights (the closed-form cross-check of the reduction):
// θ, (XᵀX)⁻¹ row-major and Σ r².
struct CubicSolve {
  Cubic theta{};
  std::array<double, 9> unit_covariance{};
  double rss = 0.0;
};
CubicSolve fitCubic(const std::vector<double>& A, const std::vector<double>& G);

}  // namespace gtbake
