// gtbake lighting's analysis (docs/lighting.md §3): per environment, the engine's product
// "unoccluded irradiance × Equation 10(A, ρ)" against the true G(ρ, L) = Σ_k ρ^k ⟨T_k, L⟩ of the
// sweep's transfer channels, per albedo, per bin of A and per scene type; the share of pixels
// that glow; and an Equation 10 refit per environment with its scene-level band.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/scene_jackknife.h"
#include "lighting/environment.h"

namespace gtbake {

// A pixel glows when the model exceeds the truth by more than this share of its open value.
inline constexpr double kGlowShare = 0.1;
// Bins of A (equal width over [0, 1]) of the per-bin errors.
inline constexpr int kLightingABins = 10;
// Pixels whose open value is below this (an open floor = 1) do not enter the refit: G/open is
// undefined where no light arrives (docs/lighting.md §3).
inline constexpr double kRefitMinOpen = 0.05;

// Errors model − truth of a set of pixels, in units of an open floor's G.
struct LightingErrors {
  std::size_t pixels = 0;
  double sum = 0.0;
  double sum_squares = 0.0;
  std::size_t glowing = 0;
  void add(double error, double open);
  double rmse() const;
  double bias() const;
  double glowShare() const;
};

struct ModelErrors {
  std::string model;                   // paper, fit, white_sky_exact, refit
  std::vector<LightingErrors> albedo;  // per sweep albedo
  std::vector<LightingErrors> a_bins;  // at the reference albedo, kLightingABins bins of A
  std::vector<LightingErrors> types;   // at the reference albedo, per scene type
};

struct EnvironmentRefit {
  bool available = false;
  std::string message;  // why not, when not available
  std::size_t points = 0;
  MultiBounceCoeffs coeffs{};
  MultiBounceCoeffs se{};  // Monte Carlo SE of the fit
  bool band = false;       // the scene jackknife ran (≥ 3 scenes)
  double band_max = 0.0;   // largest scene-level SE of G over the grid
  BandScore paper;         // the paper's constants against the band
  std::optional<BandScore> fit;
};

struct EnvironmentResult {
  Environment environment;
  double mean_open = 0.0;  // mean open value over the pixels
  std::vector<ModelErrors> models;
  EnvironmentRefit refit;
  std::vector<std::pair<std::string, std::string>> images;  // (file name, PNG bytes)
};

struct LightingAnalysis {
  std::vector<double> albedos;
  std::size_t reference = 0;  // index of the albedo closest to 0.5
  std::vector<std::string> types;
  std::size_t pixels = 0;
  std::optional<MultiBounceCoeffs> fit;  // gtbake's refit under the white sky, when given
  std::vector<EnvironmentResult> environments;
};

// Reads the sweep (its transfer channels: a one-line gtbake::Error if it has none) and analyses
// every environment, with a progress bar (one step per view) when `progress`.
LightingAnalysis analyzeLighting(const std::filesystem::path& sweep,
                                 const std::vector<Environment>& environments,
                                 const std::optional<MultiBounceCoeffs>& fit, bool progress);

}  // namespace gtbake
