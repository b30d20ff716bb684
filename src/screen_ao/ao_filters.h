// The runtime pass's denoisers over RGBA8 AO images (docs/screen_ao.md, "gtao-runtime"): the 5×5
// bilateral blur with path-accumulated depth edge weights and the temporal EMA with three
// rejection layers, and the decode of the final RGBA8 image.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "screen_ao/gtao_runtime.h"

namespace gtbake {

// x clamped to [0, 1] as a byte: lround(x·255). The value is in [0, 255], where its whole part
// and the fraction left are exact, so rounding half away from zero is a comparison of that fraction
// with ½ (lround itself, a call, only for NaN).
inline std::uint8_t unorm8(double x) {
  const double y = std::clamp(x, 0.0, 1.0) * 255.0;
  if (!(y >= 0.0)) return static_cast<std::uint8_t>(std::lround(y));
  const int whole = static_cast<int>(y);
  return static_cast<std::uint8_t>(whole + (y - whole >= 0.5 ? 1 : 0));
}

// clamp(1 − |z1 − z2|/(max(z1, z2)·0.05), 0, 1) on linear depths.
double depthEdgeWeight(double z1, double z2);

// What the filters read of the G-buffer alone, the same for every frame and run of one image
// (computed once per image, docs/screen_ao.md "gtao-runtime").
struct FilterSetup {
  // [25p + tap], taps row by row from (−2, −2): the Gaussian spatial weight (σ = 1.5) times the
  // product of the depth edge weights along the grid path from the centre to the tap (horizontal
  // leg first, then vertical at the tap's column); 0 where a step is masked or off the image.
  std::vector<double> blur;
  // [p] the pixel the history is read from: the reprojection into the previous frame (the static
  // camera maps a pixel to itself), −1 where it is off-screen (layer 1) or its depth differs by
  // more than 5 % (layer 2).
  std::vector<std::ptrdiff_t> history;
  // [p] bit 3(dy + 1) + dx + 1 set where the 3×3 neighbour (dx, dy) is on the image and unmasked:
  // the pixels of the temporal filter's clamp.
  std::vector<std::uint16_t> around;
};
FilterSetup filterSetup(const GBuffer& g);

// The 5×5 bilateral blur with f.blur's weights; masked pixels stay 0. Output rounded to RGBA8.
// kAoOnly: the A channel alone (RGB stays 0; each channel is blurred on its own).
Rgba8Image bilateralBlur(const GBuffer& g, const FilterSetup& f, const Rgba8Image& in,
                         EstimateParts parts);

// One temporal step: where f.history holds a pixel, the history AO read there is clamped to the
// 3×3 min/max of `current` (layer 3), then out = current + blend·(history − current) per
// channel; the bent normal is decoded, renormalised and re-encoded (not with kAoOnly: RGB stays
// 0, A never reads it). Elsewhere, on an empty history or with blend 0: out = current.
Rgba8Image temporalFilter(const GBuffer& g, const FilterSetup& f, const Rgba8Image& current,
                          const Rgba8Image& history, double blend, EstimateParts parts);

// Â = A/255 and the bent normal (RGB·2/255 − 1, view space) rotated to world space, normalised.
// kAoOnly: Â alone.
AoEstimate decodeRgba8(const GBuffer& g, const Rgba8Image& image, EstimateParts parts);

}  // namespace gtbake
