// Escape probabilities p_k of cosine random walks: the estimator behind A and G (docs/sweep.md §1,
// paper Section 5, Eq. 10's data).
//
// Integral. With every surface Lambertian of albedo ρ and a white sky of radiance 1,
//   G(x, ρ) = E(x)/π = Σ_{k=0..K} ρ^k p_k(x),
// where p_k(x) is the probability that a walk started at x — each step a direction drawn from the
// cosine density about the (oriented) normal, pdf(ω) = (n·ω)/π, continued from the next hit —
// first reaches the sky (no hit within R) right after its k-th interreflection. The cosine pdf
// cancels the cosine and the 1/π of the rendering equation, leaving the BRDF factor ρ per bounce,
// so a path that escapes after k bounces carries exactly ρ^k: one set of walks serves every
// albedo. A = p_0 = (1/π)∫_H V(x,ω)(n·ω)dω.
//
// Estimator. N = spp walks; c_k = number that escape after exactly k bounces (k = 0..K); walks
// that hit something on their (K+1)-th segment count in no c_k. Then p̂_k = c_k / N,
// Â = c_0/N and Ĝ(ρ) = Σ ρ^k c_k / N: multinomial, so Var(Â) = A(1−A)/N and
// Var(Ĝ) = (Σ ρ^{2k} p_k − G²)/N for independent walks. The walks of even and odd sample index
// form two independent half-sample estimates (H0, H1) whose mean is the full estimate.
//
// Traversal order. The walks of one point advance together, one bounce at a time: bounce k's
// rays of all walks still alive form one stream; those that escape are counted, the others carry
// their hit to bounce k + 1. Each walk's rays depend only on (seed, stream, sample, bounce), so
// this order gives exactly the counts of tracing walk after walk. The walks' state lives in
// arrays (WalkScratch), compacted after each bounce, and each bounce's random words, hit frames,
// offsets and directions are computed for all walks alive in branch-free loops that the compiler
// vectorizes (AVX2 clones picked at run time; Philox in AVX2 intrinsics, philox_lanes.h): the
// same IEEE float operations lane by lane as one walk at a time (no FMA contraction,
// -ffp-contract=off), so the rays are bit-identical on every machine and for the one-ray
// traversal.
//
// Stratified first bounce. Within each half, the first direction of walk t is drawn uniformly in
// cell t of an a×b grid over the unit square (a·b = N/2, a the largest divisor ≤ √(N/2)), then
// mapped to the cosine hemisphere by the concentric disk map (area preserving, so every cell has
// the same probability). Each half is then still an unbiased estimator, the two halves stay
// independent, and the variance is no larger than with independent directions (proportional
// allocation over equal-probability strata); tests/sweep measures a 4.4× lower Var(Â) at 64
// walks.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/rng.h"
#include "sweep/embree_tracer.h"
#include "sweep/strata.h"

namespace gtbake {

struct WalkSettings {
  int spp = 256;            // walks per point; even: half per half-sample estimate
  int bounces = 3;          // K
  float radius = INFINITY;  // sky beyond this distance (metres)
  std::uint64_t seed = 1;
  bool stratify_first_bounce = true;
  // Trace each bounce of a point's walks as one Embree stream (rtcIntersect1M / rtcOccluded1M)
  // instead of one rtcIntersect1 / rtcOccluded1 call per ray. Same rays, same counts, bit for
  // bit; the two are within measurement noise of each other (bench_sweep, docs/sweep.md).
  bool streams = true;
  // High 32 bits of every pixel's random stream (viewStreamKey of the view's name; the pixel
  // index fills the low 32 bits), so no two views share draws and a pixel's value depends only on
  // (seed, view, pixel), never on threads, tiles or shards.
  std::uint32_t view_key = 0;
  // True specular occlusion (specular_occlusion.h): perceptual roughness values r_p (α = r_p²) and
  // VNDF samples per value (even: two half-sample estimates). Empty: not traced.
  std::vector<double> specular_roughness;
  int specular_spp = 0;
  // Near-field truth at these radii R (metres, ascending; empty: none) from the same walks
  // (docs/sweep.md, "Near-field truth"): a walk escapes at radius R at its first segment that
  // misses or hits at a distance t > R, so A_R counts a walk whose first segment does. Needs
  // bounces ≥ 1 (a segment's hit distance is only known from an intersect query).
  std::vector<float> gbuffer_radii;
  // Per-bounce SH transfer of the escape directions (docs/sweep.md, "Transfer"): T0_SH0 …
  // channels, no extra rays.
  bool transfer = false;
};

// The view part of the random streams: 32-bit FNV-1a of the view's name (its glTF file stem, or
// <stem>_v<k> for an automatic view).
std::uint32_t viewStreamKey(const std::string& view_name);

// The random stream of pixel p of the view with key view_key.
inline std::uint64_t pixelStream(std::uint32_t view_key, std::uint64_t p) {
  return (static_cast<std::uint64_t>(view_key) << 32) | (p & 0xffffffffu);
}

// A cosine-distributed unit direction about the unit normal n, from (u0, u1) ∈ [0,1)² through the
// concentric disk map (Shirley & Chiu 1997) lifted to the hemisphere (Malley's method); the
// kernels of cosine_direction.h.
Eigen::Vector3f cosineDirection(const Eigen::Vector3f& n, float u0, float u1);

// Where bounce k of walk s points. Random numbers: one Philox call, counter (sample s, block
// ⌊k/2⌋) of the stream keyed by (seed, stream), gives four words, the (u0, u1) of two bounces:
// words 0, 1 for even k, words 2, 3 for odd k. The first bounce is stratified (cell ⌊s/2⌋ of the
// half's grid). Then cosineDirection about the normal.
class WalkSampler {
 public:
  WalkSampler(const WalkSettings& settings, std::uint64_t stream);
  // The Philox words of walk s's block ⌊k/2⌋: the draws of bounces 2⌊k/2⌋ and 2⌊k/2⌋ + 1.
  std::array<std::uint32_t, 4> blockWords(int s, int k) const;
  // Bounce k's direction from its block's words (blockWords(s, k)).
  Eigen::Vector3f direction(const Eigen::Vector3f& normal, int s, int k,
                            const std::array<std::uint32_t, 4>& words) const;
  Eigen::Vector3f direction(const Eigen::Vector3f& normal, int s, int k) const {
    return direction(normal, s, k, blockWords(s, k));
  }
  bool stratified() const { return stratify_; }
  const StratumGrid& grid() const { return grid_; }

 private:
  CounterRng rng_;
  bool stratify_;
  StratumGrid grid_;
};

// Per-thread buffers for the stream traversal, reused from point to point: per walk still alive
// (compacted after every bounce), structure of arrays so the per-bounce loops vectorize.
struct WalkScratch {
  std::vector<std::int32_t> walk;       // sample index s
  std::vector<std::uint32_t> words[4];  // Philox words of the current block (2, 3 carry to odd k)
  std::vector<float> u[2];              // this bounce's (u0, u1)
  std::vector<float> from[3];           // ray origin of the last segment
  std::vector<float> along[3];          // its direction
  std::vector<float> t;                 // its hit distance
  std::vector<float> ng[3];             // the hit's geometric normal (unnormalised)
  std::vector<float> tri_scale;         // the hit triangle's largest |vertex coordinate|
  std::vector<float> origin[3];         // the next segment's origin
  std::vector<float> direction[3];      // and direction
  std::vector<std::int32_t> near;       // first G-buffer radius index not yet escaped
  std::vector<float> cell[2];           // per sample: the first bounce's stratum (column, row)
  int cell_columns = 0;                 // grid the strata were made for
  int cell_count = 0;
  std::vector<RTCRayHit> rays;
};

// Traces settings.spp walks from `start` with random streams keyed by (seed, stream) and adds
// escape counts to counts[h * (K + 1) + k] for half h ∈ {0, 1} (sample parity) and k = 0..K.
// If first_escape_sum is given, adds to it (x, y, z, in double, in sample order) the first-bounce
// directions of the walks that escape at once: (π/N) times that sum estimates
// ∫ V (n·ω) ω dω, whose direction is the bent normal (cosine sampling cancels the (n·ω)/π).
// If near_counts is given, adds to near_counts[(2r + h)(K + 1) + k] the walks of half h that
// escape at radius R_r = settings.gbuffer_radii[r] after exactly k bounces: segment k is the
// first that misses or hits farther than R_r (docs/sweep.md, "Near-field truth"). A walk whose
// last segment K hits something (no unbounded escape) but that is alive at some R_r gets one more
// ray, that segment traced again up to the largest radius for its hit distance. Returns the
// number of rays traced. If transfer_sums is given, adds to transfer_sums[9k + i] (in double, in
// sample order) the SH basis Y_i (common/spherical_harmonics.h) at the escape direction of every
// walk that escapes after exactly k bounces: divided by N, the transfer T_k of docs/sweep.md,
// "Transfer". Depends only on (start, settings, stream).
std::uint64_t countEscapes(const EmbreeTracer& tracer, const SurfaceHit& start,
                           const WalkSettings& settings, std::uint64_t stream,
                           std::uint32_t* counts, WalkScratch* scratch,
                           double* first_escape_sum = nullptr, std::uint32_t* near_counts = nullptr,
                           double* transfer_sums = nullptr);

}  // namespace gtbake
