// Synthetic sweeps for the fit tests: in-memory point sets with known coefficients, and sweep
// directories written with gtbake::writeExr from a cosine-walk model with known p_k.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/sweep_data.h"

namespace gtbake::test {

inline const std::vector<double> kAlbedos = {0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 0.9};

// n points, A* uniform in [0, 1], G*(ρ) from Eq. 10 with `coeffs`. Each half gets independent
// noise: A_h = A* + σ_A·z, G_h = G* + σ_G·z' + `correlation`·σ_A·z (G's noise shares A's).
// The full estimate is the mean of the halves; one scene "synthetic" holds every point.
SweepData knownCoefficientSweep(const MultiBounceCoeffs& coeffs, std::size_t n, double sigma_A,
                                double sigma_G, double correlation, std::uint64_t seed);

// One scene of a pooled synthetic sweep: its name, law and draw (see knownCoefficientSweep).
struct SyntheticScene {
  std::string name;
  MultiBounceCoeffs coeffs;
  std::size_t points;
};

// Scenes drawn one by one with knownCoefficientSweep (seeds seed, seed + 1, …) and pooled like
// loadSweep pools a sweep's scenes.
SweepData pooledSweep(const std::vector<SyntheticScene>& scenes, double sigma_A, double sigma_G,
                      double correlation, std::uint64_t seed);

// Appends scene `s` of `from` to `to` (points and its range), `copies` times.
void appendScene(const SweepData& from, std::size_t s, SweepData& to, int copies = 1);

// The escape probabilities p_0..p_K of a pixel (their sum ≤ 1; the rest never escapes).
using EscapeLaw = std::function<std::vector<double>(double u)>;

// The cavity law: p_k = A (1 − A)^k, so G_K = A Σ_{k≤K} (ρ(1 − A))^k.
std::vector<double> cavityLaw(double A, int bounces);

// The cavity law's own two-stage fit, computed independently of the fit code: per albedo a QR
// least-squares cubic in x = regressor(A) on a dense uniform grid of A (the pixels of
// writeWalkSweep sample A uniformly), then a QR line through the coefficients in ρ. The
// identity regressor is the ray-traced fit's target; another one is what a fit on a biased
// estimate Â = regressor(A) should find.
MultiBounceCoeffs cavityLawOwnFit(int bounces, const std::function<double(double)>& regressor = {});

// Writes dir/sweep.json and one EXR per scene: each pixel draws u = (pixel + 0.5)/pixels (mask 1
// except the first row), p = law(u), then `spp` walks from that multinomial, even samples into
// H0, odd into H1, full = the mean.
void writeWalkSweep(const std::filesystem::path& dir, const std::vector<std::string>& scenes,
                    int width, int height, int spp, int bounces, const EscapeLaw& law,
                    std::uint64_t seed);

// A fresh empty directory under this test process's own temp root, which is removed when the
// test program ends (a gtest global environment).
std::filesystem::path freshDir(const std::string& name);

}  // namespace gtbake::test
