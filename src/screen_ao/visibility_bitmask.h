// `bitmask-uniform`, `bitmask-cosine`: visibility-bitmask occlusion (Therrien, Levesque and Gilet
// 2023, "Screen Space Indirect Lighting with Visibility Bitmask"; docs/screen_ao.md, "bitmask").
// Per slice the hemisphere [n − π/2, n + π/2] about the projected normal is cut into 32 sectors.
// Each sample S within the radius is a slab of constant thickness t behind it: its front point S
// and back point S − t·V give two angles from V, and the sectors between them are set. The slice's
// visibility is the fraction of sectors left clear: uniform sectors of equal angle (the paper's
// form), or cosine sectors of equal cosine-weighted mass (the GTAO slice weight
// cos(θ − n)|sin θ|, so sector k spans [C⁻¹(k/32), C⁻¹((k+1)/32)] of that weight's CDF C), then
// times |N'| and the open slice's integral as in Eq. 8. Bent normal: Alg. 2's integrals over the
// clear runs of sectors.
#pragma once

#include <vector>

#include "screen_ao/estimate.h"

namespace gtbake {

enum class SectorWeights { kUniform, kCosine };

struct BitmaskSettings {
  double radius = 1.0;     // metres
  int slices = 8;          // φ_s = π(s + ½)/slices
  int steps = 8;           // samples per side at (k + ½)/steps of the projected radius
  double thickness = 0.5;  // t, metres
  SectorWeights weights = SectorWeights::kUniform;
};

inline constexpr int kSectors = 32;

// Whether two bitmask settings trace the same samples, so one visibilityBitmasks pass can serve
// both weightings: they differ at most in weights and thickness.
inline bool sameBitmaskSamples(const BitmaskSettings& a, const BitmaskSettings& b) {
  return a.radius == b.radius && a.slices == b.slices && a.steps == b.steps;
}

void validate(const BitmaskSettings& s);
AoEstimate visibilityBitmask(const GBuffer& g, const BitmaskSettings& s);
// The estimate at each of several thicknesses (s.thickness is not read) in one pass: the samples,
// their slices and front angles are shared, and each result has the bytes visibilityBitmask gives
// at that thickness (Â alone with kAoOnly: the clear runs' bent-normal integrals are skipped).
std::vector<AoEstimate> visibilityBitmasks(const GBuffer& g, const BitmaskSettings& s,
                                           const std::vector<double>& thicknesses,
                                           EstimateParts parts = EstimateParts::kAoAndBent);
// The same for one or two sector weightings (s.weights is not read) in one pass: result[w][k] for
// weights[w] at thicknesses[k]. The samples, slices, front and back angles are shared, each
// weighting maps them to its own sectors (docs/screen_ao.md §3), and each result has the bytes of
// that weighting's run alone.
std::vector<std::vector<AoEstimate>> visibilityBitmasks(const GBuffer& g, const BitmaskSettings& s,
                                                        const std::vector<SectorWeights>& weights,
                                                        const std::vector<double>& thicknesses,
                                                        EstimateParts parts);

// Sector coordinate u ∈ [0, 1] of the slice angle θ (clamped to the hemisphere about n).
double sectorCoordinate(double theta, double n, SectorWeights weights);
// The 32-bit mask with the sectors of [min(ua, ub), max(ua, ub)] set: start ⌊32·min⌋, count
// ⌈32·(max − min)⌉ (the paper's rule).
std::uint32_t sectorBits(double ua, double ub);
// Every sector sectorBits(u, u_back) can set for a back angle past the front one (coordinate u)
// away from V on side `sign` (−1 or +1), however the two angles round: the pass skips a slab
// whose bits already hold these.
std::uint32_t reachableSectors(double u, double sign);
// A cosine c below which the angle sign·acos c lies more than 1e-6 rad past the hemisphere's end
// n + sign·π/2 (−∞ where the pass uses no such bound): the pass's test before an acos.
double pastEndCos(double n, double sign);
// A cosine c below which the angle sign·acos c lies within 5e-5 rad of the hemisphere's end
// n + sign·π/2 or past it (−∞ where the pass uses no such bound), so that a sample with that front
// angle sets no sector under either weighting: the pass skips it before any acos.
double endBandCos(double n, double sign);

}  // namespace gtbake
