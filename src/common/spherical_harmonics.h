// Real spherical harmonics of order L = 2 (9 coefficients), the basis of the sweep's transfer
// channels and of gtbake lighting's environments (docs/lighting.md §2).
//
// Basis. Index i = l(l + 1) + m, orthonormal over the unit sphere (∫ Y_i Y_j dω = δ_ij), written
// on the world axes (x, y, z) of the unit direction ω (glTF's frame, +y up; docs/sweep.md §3):
//   Y0 = ½√(1/π)
//   Y1 = √(3/4π) y,   Y2 = √(3/4π) z,   Y3 = √(3/4π) x
//   Y4 = ½√(15/π) xy, Y5 = ½√(15/π) yz, Y6 = ¼√(5/π)(3z² − 1), Y7 = ½√(15/π) xz,
//   Y8 = ¼√(15/π)(x² − y²)
// (the usual real basis, e.g. Sloan 2008, "Stupid Spherical Harmonics Tricks", Appendix A2).
// Projection: f_i = ∫ f(ω) Y_i(ω) dω, so ∫ f g dω = Σ_i f_i g_i for band-limited f or g.
#pragma once

#include <array>

#include "common/math_constants.h"

namespace gtbake {

inline constexpr int kShCoefficients = 9;
using ShVector = std::array<double, kShCoefficients>;

// The band l of coefficient i (0, 1, 1, 1, 2, 2, 2, 2, 2).
inline int shBand(int i) {
  return i == 0 ? 0 : (i < 4 ? 1 : 2);
}

// Y_0 … Y_8 at the direction (x, y, z) (taken as given; unit for the basis to mean anything).
// Double arithmetic in a fixed order, so the same direction gives the same bits everywhere.
inline void shBasis(double x, double y, double z, double* out) {
  constexpr double c0 = 0.28209479177387814;  // ½√(1/π)
  constexpr double c1 = 0.48860251190291992;  // √(3/4π)
  constexpr double c2 = 1.0925484305920792;   // ½√(15/π)
  constexpr double c3 = 0.31539156525252005;  // ¼√(5/π)
  constexpr double c4 = 0.54627421529603959;  // ¼√(15/π)
  out[0] = c0;
  out[1] = c1 * y;
  out[2] = c1 * z;
  out[3] = c1 * x;
  out[4] = c2 * (x * y);
  out[5] = c2 * (y * z);
  out[6] = c3 * (3.0 * (z * z) - 1.0);
  out[7] = c2 * (x * z);
  out[8] = c4 * (x * x - y * y);
}

// Funk–Hecke factors of the clamped cosine max(0, n·ω) per band: ∫ max(0, n·ω) Y_i(ω) dω =
// Â_l Y_i(n) with Â_0 = π, Â_1 = 2π/3, Â_2 = π/4 (Ramamoorthi & Hanrahan 2001).
inline double clampedCosineBand(int l) {
  return l == 0 ? kPi : (l == 1 ? 2.0 * kPi / 3.0 : kPi / 4.0);
}

}  // namespace gtbake
