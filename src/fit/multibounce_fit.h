// The multi-bounce fit of paper Section 5, Equation 10 (SPEC §1.3), in two Ceres stages.
//
// Stage 1, per albedo ρ: least squares over every unmasked point i of every scene of
//   G_i ≈ a·A_i³ − b·A_i² + c·A_i            (θ = (a, b, c), regressors x_i = (A³, −A², A)).
// Stage 2, per coefficient q ∈ {a, b, c}: least squares over the albedos of q(ρ) ≈ q1·ρ + q0.
//
// Standard errors (docs/fit.md §3). The sampling uncertainty of θ is Monte Carlo noise: the scenes
// and pixels are fixed, the walks are random. To first order θ̂ − θ = C Σ_i ψ_i with
// C = (XᵀX)⁻¹ (= Ceres' covariance, which assumes unit residual variance) and the influence
//   ψ_i = x_i δG_i + (x_i' r_i − x_i f'(A_i)) δA_i        (r_i the residual, f the cubic),
// which counts noise in G, noise in the regressor A and their correlation. δ_i is estimated per
// point from the two half-sample estimates, δ_i = (h0_i − h1_i)/2 (E δ_i² = Var of the full mean),
// so Cov(θ̂) = C (Σ ψ_i ψ_iᵀ) C — a sandwich with known per-point variance. `se` is that; `se_iid`
// is Ceres' covariance scaled by σ̂² = RSS/(n − 3) (it treats scene-to-scene misfit as iid noise).
// Stage 2 is linear in the stage-1 coefficients, so its SE propagates the full cross-albedo
// covariance exactly; the misfit of the line in ρ is reported separately (`misfit_*`).
//
// Errors in variables (docs/fit.md §4): noise in A biases θ̂ by β·v + γ·v² + … in the noise
// variance v (v = 1 for the full estimate). With d_i = (h0_i − h1_i)/2 (same variance as the
// full estimate's noise, uncorrelated with it) the sets full + c·d, c ∈ {±1, ±√2}, have v = 2, 3;
// θ̂(v) through v = 1, 2, 3 is extrapolated quadratically to v = 0 (SIMEX with the sweep's own
// noise): θ0 = 3θ1 − 3θ2 + θ3. With `eiv_correction` the reported θ is θ0; its first-order noise
// equals θ̂_full's (the ±c pairs cancel d), so the SE applies to it unchanged.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "fit/fit_command.h"
#include "fit/sweep_data.h"

namespace gtbake {

using Cubic = std::array<double, 3>;  // (a, b, c): G = a·A³ − b·A² + c·A

struct CubicSolve {
  Cubic theta{};
  std::array<double, 9> unit_covariance{};  // (JᵀJ)⁻¹ from ceres::Covariance, row-major 3×3
  double rss = 0.0;                         // Σ r_i²
  std::size_t points = 0;
};

// One Ceres least-squares solve of the cubic; throws gtbake::Error if Ceres does not converge.
// `unit_covariance` is filled only when `with_covariance`.
CubicSolve fitCubic(const std::vector<double>& A, const std::vector<double>& G,
                    bool with_covariance = true);

double evalCubic(const Cubic& theta, double A);
// Eq. 10: G(A, ρ) for the linear coefficients {a1, a0, b1, b0, c1, c0}.
double evalMultiBounce(const MultiBounceCoeffs& coeffs, double A, double rho);
Cubic cubicAt(const MultiBounceCoeffs& coeffs, double rho);

struct AlbedoFit {
  double rho = 0.0;
  Cubic theta{};        // reported coefficients (EIV-corrected when the correction is on)
  Cubic se{};           // Monte Carlo sandwich SE (see above)
  Cubic se_iid{};       // Ceres covariance × RSS/(n − 3)
  Cubic uncorrected{};  // θ̂ on the full estimate
  Cubic half_mean{};    // mean of θ̂ on the two halves
  Cubic eiv_bias{};     // measured bias of θ̂_full (quadratic extrapolation in noise variance)
  Cubic
      eiv_bias_linear{};  // the two-point (split-half jackknife) estimate: half_mean − uncorrected
  double rmse = 0.0;      // of `theta` against the full-estimate points
  double max_abs = 0.0;
  std::size_t points = 0;
};

struct LinearFit {
  MultiBounceCoeffs coeffs{};           // from the reported per-albedo θ
  MultiBounceCoeffs se{};               // propagated Monte Carlo SE
  MultiBounceCoeffs uncorrected{};      // the same line through the uncorrected θ̂_full
  MultiBounceCoeffs eiv_bias{};         // line through the per-albedo biases
  MultiBounceCoeffs eiv_bias_linear{};  // line through the split-half (two-point) biases
  MultiBounceCoeffs misfit_se{};        // classical OLS SE from the line's own residuals (5 dof)
  Cubic misfit_rms{};                   // RMS residual of a(ρ), b(ρ), c(ρ) about their lines
};

struct MultiBounceFit {
  std::vector<AlbedoFit> per_albedo;
  LinearFit linear;
  bool eiv_corrected = true;
};

MultiBounceFit fitMultiBounce(const SweepData& data, bool eiv_correction);

}  // namespace gtbake
