// `hbao`: horizon-based ambient occlusion as Bavoil, Sainz and Dimitrov (2008) describe it
// (docs/screen_ao.md, "hbao"): A = 1 − (1/2π)∫ (sin h(θ) − sin t(θ)) W(θ) dθ (their Eq. 3), with
// the zenith on the view vector V, t(θ) the tangent angle (from the view ray of the next texel in
// direction θ intersected with the tangent plane), h(θ) = max(t, α(S_i)) over Ns texel-snapped
// steps of equal length across the projected radius (samples farther than R ignored), and
// W = max(0, 1 − r/R) with r the distance to the horizon point. Nd directions with a per-pixel
// random rotation and step jitter (Philox on the pixel index). The bent normal: the mean
// unoccluded direction of the same slices, cosine-weighted as gtao-reference's (HBAO defines none).
#pragma once

#include <cstdint>

#include "screen_ao/estimate.h"

namespace gtbake {

struct HbaoSettings {
  double radius = 1.0;  // R, metres
  int directions = 8;   // Nd (their Figure 1)
  int steps = 8;        // Ns
  std::uint64_t seed = 1;
};

void validate(const HbaoSettings& s);
AoEstimate hbao(const GBuffer& g, const HbaoSettings& s);

}  // namespace gtbake
