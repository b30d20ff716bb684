// The six constants of Equation 10 (paper Section 5, docs/fit.md §1) and the one evaluation of G.
//
//   G(A, ρ) = a(ρ)·A³ − b(ρ)·A² + c(ρ)·A,   a(ρ) = a1·ρ + a0, b(ρ) = b1·ρ + b0, c(ρ) = c1·ρ + c0.
//
// Coefficient order everywhere: {a1, a0, b1, b0, c1, c0}; the paper's sign convention (minus in
// front of b).
#pragma once

#include <array>

namespace gtbake {

using MultiBounceCoeffs = std::array<double, 6>;  // {a1, a0, b1, b0, c1, c0}
using Cubic = std::array<double, 3>;              // (a, b, c) at one albedo

inline constexpr MultiBounceCoeffs kPaperCoeffs = {2.0404,  -0.3324, 4.7951,
                                                   -0.6417, 2.7552,  0.6903};
// The paper's albedo range (docs/fit.md §1), over which curves are compared and the band is
// searched.
inline constexpr double kRhoMin = 0.1;
inline constexpr double kRhoMax = 0.9;

inline constexpr std::array<const char*, 6> kCoeffNames = {"a1", "a0", "b1", "b0", "c1", "c0"};
inline constexpr std::array<const char*, 3> kCubicNames = {"a", "b", "c"};

// G = a·A³ − b·A² + c·A by Horner's rule.
constexpr double evalCubic(const Cubic& theta, double A) {
  return ((theta[0] * A - theta[1]) * A + theta[2]) * A;
}

// (a(ρ), b(ρ), c(ρ)) of the linear coefficients.
constexpr Cubic cubicAt(const MultiBounceCoeffs& k, double rho) {
  return {k[0] * rho + k[1], k[2] * rho + k[3], k[4] * rho + k[5]};
}

// Eq. 10: G(A, ρ) for the linear coefficients.
constexpr double evalMultiBounce(const MultiBounceCoeffs& k, double A, double rho) {
  return evalCubic(cubicAt(k, rho), A);
}

// ∂G/∂k at (A, ρ): G is linear in k, so G(A, ρ; k) = gradient · k and Var G = gᵀ Σ g.
constexpr MultiBounceCoeffs multiBounceGradient(double A, double rho) {
  const double A2 = A * A, A3 = A2 * A;
  return {rho * A3, A3, -rho * A2, -A2, rho * A, A};
}

}  // namespace gtbake
