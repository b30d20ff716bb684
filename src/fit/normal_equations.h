// Sufficient statistics of the per-albedo cubic fits, built once per scene (docs/fit.md §3).
//
// Stage 1 minimises Σ_i w_i (G_ij − x_iᵀθ)², x_i = (A_i³, −A_i², A_i), so everything it needs from
// the points is the Gram matrix S = Σ w x xᵀ and the moments b_j = Σ w x G_j. They are sums, so the
// statistics of any union of scenes is the sum of the scenes' (a leave-one-scene-out refit is the
// total minus one scene), and a refit costs a 3 × 3 solve instead of a pass over the points. The
// sums are two-level: blocks of kSumBlock points in double (relative error ≤ kSumBlock·2⁻⁵³ ≈ 7e-15
// per entry, in registers), the blocks accumulated in long double (64-bit mantissa). S has
// condition ~1e5, so the solution stays within ~1e-10 relative of a QR solve on the raw points
// (measured: 3e-11 on the shipped sweep).
//
// One set of sums per errors-in-variables noise level (multibounce_fit.h): level l uses
// A + c_l·dA and G + c_l·dG with d = (h0 − h1)/2 and c_l = 0, +1, −1, +√2, −√2 (half of
// kLevelScale below).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/sweep_data.h"

namespace gtbake {

inline constexpr int kLevels = 7;
// c_l of the noise levels: full + c·(h0 − h1)/2 has (1 + c²) times the full estimate's variance
// (v = 1, 2, 2, 3, 3, 4, 4).
inline const std::array<double, kLevels> kLevelScale = {0.0,
                                                        1.0,
                                                        -1.0,
                                                        1.4142135623730951,
                                                        -1.4142135623730951,
                                                        1.7320508075688772,
                                                        -1.7320508075688772};

struct NormalEquations {
  std::array<long double, 9> gram{};               // Σ w x xᵀ, row-major 3 × 3
  std::vector<std::array<long double, 3>> moment;  // [albedo] Σ w x G_j
  long double weight = 0.0L;                       // Σ w
  std::size_t points = 0;

  NormalEquations& operator+=(const NormalEquations& other);
  NormalEquations scaled(long double factor) const;
};

// Points per double-precision partial sum (see above).
inline constexpr std::size_t kSumBlock = 64;

// Adds `count` points with weights w, regressor A and G[albedo][point] to `sums`.
void accumulate(NormalEquations& sums, const double* w, const double* A,
                const std::vector<const double*>& G, std::size_t count);

// [level] statistics of one set of points.
using LevelStatistics = std::array<NormalEquations, kLevels>;

// Point weighting of the fit (docs/fit.md §1): every pixel equal (the paper's "combination of all
// points"), every view (one image) equal whatever its pixel count, or flat in A (each of kFlatABins
// equal bins of the full estimate's A carries the same total weight).
enum class Weighting { kPixel, kView, kFlatA };
inline constexpr std::array<Weighting, 3> kWeightings = {Weighting::kPixel, Weighting::kView,
                                                         Weighting::kFlatA};
inline constexpr int kFlatABins = 20;  // bins of width 0.05 in A
std::string weightingName(Weighting w);
// Throws a one-line gtbake::Error for anything but pixel, view, flat-a.
Weighting parseWeighting(const std::string& name);

// Per-point weights, mean 1 over the sweep (so Σ w = n and weighted RMSEs read like plain ones).
std::vector<double> pointWeights(const SweepData& data, Weighting weighting);

// [scene] statistics with the given per-point weights. Scenes are summed in parallel, each in
// point order, so the result does not depend on the thread count.
std::vector<LevelStatistics> sceneStatistics(const SweepData& data,
                                             const std::vector<double>& weights);

// Σ over the scenes whose `include` flag is set.
LevelStatistics sumScenes(const std::vector<LevelStatistics>& scenes,
                          const std::vector<bool>& include);

// The cubic's parameters as an affine image θ = T φ + t0 of N free ones: the plain fit (N = 3,
// T = I, t0 = 0) or the open-surface constraint a − b + c = 1, i.e. G(1) = 1 (N = 2, φ = (a, b),
// c = 1 − a + b). T is row-major 3 × N.
struct CubicParameterization {
  int N = 3;
  std::vector<double> T;
  Cubic t0{};
  Cubic theta(const std::vector<double>& phi) const;
};
CubicParameterization freeCubic();
CubicParameterization openConstrainedCubic();

// The reduced least-squares problem of a parameterization: Σ w (G − xᵀθ)² = ‖R φ − z‖² + const with
// TᵀST = RᵀR (Cholesky in long double) and Rᵀz = Tᵀ(b − S t0). R is row-major N × N. Throws a
// one-line gtbake::Error when TᵀST is not positive definite to working precision (every A equal, or
// too few distinct A).
struct ReducedProblem {
  std::vector<double> R;
  std::vector<double> z;
};
ReducedProblem reduceProblem(const NormalEquations& s, std::size_t albedo,
                             const CubicParameterization& p);

}  // namespace gtbake
