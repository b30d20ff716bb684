// `gtao-runtime`: the runtime GTAO pass (docs/screen_ao.md, "gtao-runtime"), as its description
// gives it: per frame the horizon search with interleaved gradient noise and the golden-ratio
// frame offset, quadratic step spacing, the flat-inner/linear-outer falloff (range 0.615), thin
// compensation, the analytic slice integral and Alg. 2's bent normal, the intensity power, an
// R10G10B10A2 normal buffer in and RGBA8 out; then the 5×5 path-accumulated bilateral blur and
// the temporal EMA with its three rejection layers, over `frames` frames of a static camera.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "screen_ao/estimate.h"

namespace gtbake {

struct GtaoRuntimeSettings {
  double radius = 1.0;             // metres (typical 0.1 – 5)
  int directions = 4;              // slices per frame (2 / 4 / 8)
  int steps = 4;                   // steps per side (2 / 4 / 8)
  double thin_compensation = 0.0;  // 0 = off (typical 0 – 0.7)
  double intensity = 1.0;          // power-curve exponent (typical 0.5 – 3; 1 leaves A as is)
  double temporal_blend = 0.9;     // history weight (0 – 0.98)
  int frames = 6;                  // frames of the static camera (the paper's 6 rotations)
  bool blur = true;                // the spatial pass
};

inline constexpr double kFalloffRange = 0.615;
inline constexpr double kGoldenRatioFraction = 0.61803398874989484820;

void validate(const GtaoRuntimeSettings& s);

// An RGBA8 image as the passes store it: per pixel (R, G, B) = bent normal·½ + ½ (view space) and
// A = AO, each a byte.
using Rgba8Image = std::vector<std::array<std::uint8_t, 4>>;

// Interleaved gradient noise of integer pixel (x, y): fract(52.9829189·fract(0.06711056·x +
// 0.00583715·y)).
double interleavedGradientNoise(int x, int y);
// fract(ign + (frame mod 64)·φ) (φ's fractional part), ign the pixel's interleavedGradientNoise.
double frameNoise(double ign, int frame);

// The R10G10B10A2 normal buffer's decode of world normal n: n·½ + ½ rounded to 10 bits, back to
// [−1, 1], normalised.
Eigen::Vector3d r10g10b10Normal(const Eigen::Vector3d& n);

// All passes over s.frames frames; the final ao_filtered decoded (A = byte/255, bent normal
// decoded, rotated to world space and normalised).
AoEstimate gtaoRuntime(const GBuffer& g, const GtaoRuntimeSettings& s);

// gtaoRuntime at each of several settings in one pass over the frames (docs/tune.md §7): the
// runs must share `directions` and `frames` (a one-line gtbake::Error otherwise). Each pixel's
// slices are shared by every run, its horizon samples by the runs with the same radius and steps
// (thin_compensation only changes each sample's falloff weight), its horizons by those with the
// same thin_compensation too (intensity only raises their sum to a power), and the filters' depth
// weights and reprojection by every frame and run; each result has the bytes gtaoRuntime gives at
// its settings. With kAoOnly the bent normal is neither computed, stored in RGB nor filtered: no
// stage's A reads it, so Â keeps its bytes.
std::vector<AoEstimate> gtaoRuntimeRuns(const GBuffer& g,
                                        const std::vector<GtaoRuntimeSettings>& runs,
                                        EstimateParts parts = EstimateParts::kAoAndBent);

}  // namespace gtbake
