// The runtime pass's denoisers over RGBA8 AO images (docs/screen_ao.md, "gtao-runtime"): the 5×5
// bilateral blur with path-accumulated depth edge weights and the temporal EMA with three
// rejection layers, and the decode of the final RGBA8 image.
#pragma once

#include "screen_ao/gtao_runtime.h"

namespace gtbake {

// clamp(1 − |z1 − z2|/(max(z1, z2)·0.05), 0, 1) on linear depths.
double depthEdgeWeight(double z1, double z2);

// Gaussian spatial weights (σ = 1.5) times the product of the depth edge weights along the grid
// path from the centre to the tap (horizontal leg first, then vertical at the tap's column);
// masked pixels and taps off the image weigh 0. Output rounded to RGBA8.
Rgba8Image bilateralBlur(const GBuffer& g, const Rgba8Image& in);

// One temporal step: reprojects every pixel into the previous frame (the static camera maps it to
// itself), rejects history off-screen (layer 1) or with a relative depth difference over 5 %
// (layer 2), clamps the history AO to the 3×3 min/max of `current` (layer 3), then
// out = current + blend·(history − current) per channel; the bent normal is decoded,
// renormalised and re-encoded. Empty history or blend 0: out = current.
Rgba8Image temporalFilter(const GBuffer& g, const Rgba8Image& current, const Rgba8Image& history,
                          double blend);

// Â = A/255 and the bent normal (RGB·2/255 − 1, view space) rotated to world space, normalised.
AoEstimate decodeRgba8(const GBuffer& g, const Rgba8Image& image);

}  // namespace gtbake
