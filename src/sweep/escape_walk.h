// Escape probabilities p_k of cosine random walks: the estimator behind A and G (SPEC §1.1,
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
// this order gives exactly the counts of tracing walk after walk.
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
#include <cstdint>
#include <vector>

#include "common/rng.h"
#include "sweep/embree_tracer.h"

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
};

// A cosine-distributed unit direction about the unit normal n, from (u0, u1) ∈ [0,1)² through the
// concentric disk map (Shirley & Chiu 1997) lifted to the hemisphere (Malley's method).
Eigen::Vector3f cosineDirection(const Eigen::Vector3f& n, float u0, float u1);

// Where bounce k of walk s points: (u0, u1) from counter (sample s, block k) of the stream keyed
// by (seed, stream), the first bounce stratified (cell s/2 of the half's grid), mapped by
// cosineDirection about the normal.
class WalkSampler {
 public:
  WalkSampler(const WalkSettings& settings, std::uint64_t stream);
  Eigen::Vector3f direction(const Eigen::Vector3f& normal, int s, int k) const;

 private:
  CounterRng rng_;
  bool stratify_;
  int columns_;
  int rows_;
};

// Per-thread buffers for the stream traversal, reused from point to point.
struct WalkScratch {
  std::vector<SurfaceHit> at;
  std::vector<int> alive;
  std::vector<int> next;
  std::vector<RTCRayHit> rays;
};

// Traces settings.spp walks from `start` with random streams keyed by (seed, stream) and adds
// escape counts to counts[h * (K + 1) + k] for half h ∈ {0, 1} (sample parity) and k = 0..K.
// Returns the number of rays traced. Depends only on (start, settings, stream).
std::uint64_t countEscapes(const EmbreeTracer& tracer, const SurfaceHit& start,
                           const WalkSettings& settings, std::uint64_t stream,
                           std::uint32_t* counts, WalkScratch* scratch);

}  // namespace gtbake
